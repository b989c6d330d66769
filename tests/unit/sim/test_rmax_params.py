import math

import pytest

from hdrc3_base.errors import ConfigError
from sim.rmax_params import RmaxParams


def test_derived_values() -> None:
    p = RmaxParams()
    assert p.omega == pytest.approx(850.0 * 2 * math.pi / 60)
    assert p.omega * p.main_rotor.radius == pytest.approx(138.6, abs=0.1)  # tip speed, m/s
    assert p.max_engine_torque * p.omega == pytest.approx(15660.0)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"empty_mass": 0.0},
        {"rotor_rpm": -850.0},
        {"engine_power": math.nan},
        {"collective_min": 0.3, "collective_max": 0.2},
        {"transmission_efficiency": 1.5},
    ],
)
def test_invalid_parameters_rejected(kwargs: dict[str, float]) -> None:
    with pytest.raises(ConfigError):
        RmaxParams(**kwargs)  # type: ignore[arg-type]
