"""Data Interface: the §6.2.4 fields, their conversion, and the 25 Hz gate on sim time."""

from __future__ import annotations

import itertools
import math

import pytest

from hdrc3_platform_server.data_interface import (
    CAMERA_FIELDS,
    HELICOPTER_FIELDS,
    RateGate,
    camera_state,
    helicopter_state,
)
from hdrc3_platform_server.fakes import FakeRig
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.platform_status import CameraSample, PfcSample

FRAME = WorldFrame(55.70, 13.47, 95.0)

CHAPTER_HELICOPTER = {
    "altitude",
    "latitude",
    "longitude",
    "velocity_north",
    "velocity_east",
    "velocity_up",
    "pitch",
    "roll",
    "heading",
    "rpm",
    "on_ground_flag",
    "auto_flag",
    "drc_minus_pfc_time",
    "ppc_minus_pfc_time",
    "power_status",
    "pfc_time",
}
FAILSAFE_FIELDS = {"failsafe", "failsafe_reason"}
"""Beyond the chapter (issue 21): the PFC's navigation failsafe in the Data Interface."""


def sample(**changes: object) -> PfcSample:
    base: dict[str, object] = dict(
        pfc_time=10.0,
        received=10.004,
        position_enu=(100.0, 50.0, 30.0),
        velocity_enu=(1.0, 2.0, -0.5),
        latitude=0.0,
        longitude=0.0,
        altitude=0.0,
        roll=0.1,
        pitch=-0.05,
        heading=-0.5,
        rpm=1400.0,
        on_ground=False,
        auto_flag=True,
        power_status=7,
    )
    base.update(changes)
    return PfcSample(**base)  # type: ignore[arg-type]


def test_field_names_are_the_chapters() -> None:
    assert set(HELICOPTER_FIELDS) == CHAPTER_HELICOPTER | FAILSAFE_FIELDS
    assert set(CAMERA_FIELDS) == {"id", "pan", "tilt", "zoom", "ipc_time"}
    data = helicopter_state(sample(), FRAME, 10.004, 9.99, 0)
    assert set(data.as_dict()) == CHAPTER_HELICOPTER | FAILSAFE_FIELDS


def test_the_pfc_failsafe_is_in_the_data_interface() -> None:
    text = "failsafe: emergency landing: navigation lost: IMU frozen (identical samples)"
    data = helicopter_state(sample(failsafe=2, failsafe_reason=text), FRAME, 10.0, None, 0)
    assert (data.failsafe, data.failsafe_reason) == (2, text)


def test_conversion_from_enu_and_clock_differences() -> None:
    data = helicopter_state(sample(), FRAME, 10.004, 9.99, 0)
    lon, lat, alt = FRAME.to_wgs84(100.0, 50.0, 30.0)
    assert (data.longitude, data.latitude, data.altitude) == pytest.approx((lon, lat, alt))
    assert (data.velocity_north, data.velocity_east, data.velocity_up) == (2.0, 1.0, -0.5)
    assert data.heading == pytest.approx(2 * math.pi - 0.5)
    assert data.drc_minus_pfc_time == pytest.approx(0.004)
    assert data.ppc_minus_pfc_time == pytest.approx(-0.01)
    assert data.power_status == 7 and data.pfc_time == 10.0


def test_wgs84_from_the_pfc_is_kept() -> None:
    data = helicopter_state(sample(latitude=55.1, longitude=13.2, altitude=99.0), FRAME, 0, None, 3)
    assert (data.latitude, data.longitude, data.altitude) == (55.1, 13.2, 99.0)
    assert data.power_status == 3 and data.ppc_minus_pfc_time == 0.0


def test_camera_state() -> None:
    cam = camera_state(CameraSample(1, 0.2, 1.5, 0.0, 4.0, 4.1))
    assert cam.as_dict() == {"id": 1, "pan": 0.2, "tilt": 1.5, "zoom": 0.0, "ipc_time": 4.0}


@pytest.mark.parametrize(("period", "expected"), [(0.02, 25), (0.01, 25), (0.04, 25), (0.005, 25)])
def test_gate_gives_25_hz_for_any_input_rate(period: float, expected: int) -> None:
    gate = RateGate()
    n = round(1.0 / period)
    count = sum(gate.due(3.0 + i * period) for i in range(n))
    assert count == expected


def test_gate_restarts_after_time_goes_back() -> None:
    gate = RateGate()
    assert gate.due(100.0)
    assert gate.due(0.0)  # a simulation reset


def test_rig_publishes_25_hz_of_sim_time() -> None:
    rig = FakeRig(FRAME)
    rig.published.clear()
    rig.run(4.0)
    times = [d.pfc_time for d in rig.published]
    assert len(times) == 100
    assert all(abs((b - a) - 0.04) < 1e-6 for a, b in itertools.pairwise(times))
