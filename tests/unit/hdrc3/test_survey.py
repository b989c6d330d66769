import itertools
import math

import numpy as np
import pytest

from hdrc3.survey import SurveyArea, lawn_mower
from hdrc3_base.errors import ConfigError


@pytest.mark.parametrize(("legs", "segments"), [(1, 1), (2, 3), (4, 7)])
def test_legs_are_joined_by_turns(legs: int, segments: int) -> None:
    path = lawn_mower(SurveyArea(0.0, 0.0, 100.0, 20.0, legs, 30.0), 8.0, 3.0)
    assert len(path) == segments
    assert [s.end_velocity for s in path][-1] == 0.0
    assert all(s.end_velocity > 0 for s in path[:-1])
    for a, b in itertools.pairwise(path):
        assert np.allclose(a.end, b.start)
        assert np.allclose(a.tangent(1.0), b.tangent(0.0))  # tangent-continuous


def test_first_leg_runs_along_the_heading_and_turns_left() -> None:
    north = lawn_mower(SurveyArea(10.0, 20.0, 100.0, 20.0, 2, 30.0, heading=0.0), 8.0, 3.0)
    assert np.allclose(north[0].start, (10.0, 20.0, 30.0))
    assert np.allclose(north[0].end, (10.0, 120.0, 30.0))
    assert np.allclose(north[2].start, (-10.0, 120.0, 30.0))  # left of north is west
    assert np.allclose(north[2].end, (-10.0, 20.0, 30.0))
    assert north[0].target_velocity == 8.0 and north[1].target_velocity == 3.0


@pytest.mark.parametrize(
    "area",
    [
        dict(leg_length=0.0),
        dict(spacing=-1.0),
        dict(legs=0),
        dict(altitude=math.nan),
    ],
)
def test_bad_areas_are_rejected(area: dict[str, float]) -> None:
    base = dict(
        corner_east=0.0, corner_north=0.0, leg_length=50.0, spacing=10.0, legs=2, altitude=20.0
    )
    base.update(area)
    with pytest.raises(ConfigError):
        SurveyArea(**base)  # type: ignore[arg-type]


def test_speeds_must_be_positive() -> None:
    with pytest.raises(ConfigError, match="speeds must be positive"):
        lawn_mower(SurveyArea(0.0, 0.0, 50.0, 10.0, 1, 20.0), 0.0, 3.0)
