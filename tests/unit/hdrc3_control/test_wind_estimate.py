"""On-board wind estimate: the attitude that holds the velocity against the fuselage's drag."""

from __future__ import annotations

import math

import pytest

from hdrc3_base.errors import ConfigError
from hdrc3_control.commands import EstimatedState, EstimatorHealth, G
from hdrc3_control.wind_estimate import (
    WindConfig,
    WindEstimate,
    WindEstimator,
    WindStatus,
    relative_air,
    thrust_accel,
)

CONFIG = WindConfig()


def _trimmed(
    wind: tuple[float, float],
    heading: float,
    velocity: tuple[float, float] = (0.0, 0.0),
    t: float = 0.0,
    on_ground: bool = False,
    health: EstimatorHealth = EstimatorHealth.OK,
) -> EstimatedState:
    """The state of an aircraft flying ``velocity`` steadily in ``wind`` (the model's attitude)."""
    s, c = math.sin(heading), math.cos(heading)
    ae, an = wind[0] - velocity[0], wind[1] - velocity[1]
    u, v = ae * s + an * c, ae * c - an * s  # the air relative to the aircraft, body x and y
    drag_forward = CONFIG.drag_forward * u * abs(u)
    drag_right = CONFIG.drag_side * v * abs(v)
    pitch = CONFIG.trim_pitch + math.atan(drag_forward / G)  # the thrust cancels the drag
    roll = CONFIG.trim_roll + math.atan(-drag_right / G)
    return EstimatedState(
        t, (0.0, 0.0, 10.0), (*velocity, 0.0), roll, pitch, heading,
        on_ground=on_ground, health=health,
    )  # fmt: skip


def _fly(estimator: WindEstimator, states: list[EstimatedState]) -> WindEstimate:
    out = estimator.estimate()
    for state in states:
        out = estimator.update(state)
    return out


@pytest.mark.parametrize(
    ("wind", "heading_deg", "velocity"),
    [
        ((10.0, 0.0), 0.0, (0.0, 0.0)),  # from the west, side-on
        ((10.0, 0.0), 270.0, (0.0, 0.0)),  # nose into it
        ((10.0, 0.0), 90.0, (0.0, 0.0)),  # tailwind
        ((-3.0, 4.0), 45.0, (0.0, 0.0)),  # 5 m/s from 143 deg, oblique
        ((0.0, -5.0), 200.0, (2.0, 1.0)),  # from the north, flying across it
        ((0.0, 0.0), 120.0, (3.0, 0.0)),  # calm air, flying east: the drag is the airspeed's
    ],
)
def test_the_estimate_converges_to_the_wind_the_attitude_holds_against(
    wind: tuple[float, float], heading_deg: float, velocity: tuple[float, float]
) -> None:
    heading = math.radians(heading_deg)
    states = [_trimmed(wind, heading, velocity, t=k * 0.02) for k in range(2000)]
    out = _fly(WindEstimator(), states)
    assert out.status is WindStatus.OK
    assert out.east == pytest.approx(wind[0], abs=0.05)
    assert out.north == pytest.approx(wind[1], abs=0.05)


@pytest.mark.parametrize(
    ("seconds", "on_ground", "health", "status"),
    [
        (0.0, False, EstimatorHealth.OK, WindStatus.NONE),  # one sample: no derivative yet
        (4.0, False, EstimatorHealth.OK, WindStatus.SETTLING),
        (10.0, False, EstimatorHealth.OK, WindStatus.OK),
        (10.0, True, EstimatorHealth.OK, WindStatus.NONE),  # on the skids: the ground holds it
        (10.0, False, EstimatorHealth.DEGRADED, WindStatus.NONE),  # velocity dead-reckoned
    ],
)
def test_the_estimate_is_ok_only_after_settling_airborne_on_a_good_solution(
    seconds: float, on_ground: bool, health: EstimatorHealth, status: WindStatus
) -> None:
    ticks = round(seconds / 0.02) + 1
    states = [
        _trimmed((5.0, 0.0), 0.0, t=k * 0.02, on_ground=on_ground, health=health)
        for k in range(ticks)
    ]
    assert _fly(WindEstimator(), states).status is status


def test_a_gap_in_the_solution_starts_the_settling_over() -> None:
    est = WindEstimator()
    _fly(est, [_trimmed((5.0, 0.0), 0.0, t=k * 0.02) for k in range(600)])
    assert est.estimate().status is WindStatus.OK
    late = est.update(_trimmed((5.0, 0.0), 0.0, t=20.0))
    assert late.status is WindStatus.NONE


@pytest.mark.parametrize(
    ("east", "north", "from_deg", "text"),
    [
        (10.0, 0.0, 270.0, "10.0 m/s from 270 deg"),  # blowing east: from the west
        (0.0, -4.0, 0.0, "4.0 m/s from 0 deg"),
        (-3.0, 3.0, 135.0, "4.2 m/s from 135 deg"),
    ],
)
def test_the_wind_comes_from_the_opposite_of_where_it_blows(
    east: float, north: float, from_deg: float, text: str
) -> None:
    wind = WindEstimate(east, north, WindStatus.OK)
    assert math.degrees(wind.from_direction) == pytest.approx(from_deg)
    assert wind.describe() == text


@pytest.mark.parametrize("heading_deg", [0.0, 37.0, 90.0, 215.0])
def test_relative_air_inverts_the_drag_of_the_thrust(heading_deg: float) -> None:
    heading = math.radians(heading_deg)
    state = _trimmed((4.0, -6.0), heading)
    te, tn = thrust_accel(state.roll, state.pitch, heading, CONFIG)
    air = relative_air(-te, -tn, heading, CONFIG)  # hovering: drag = -thrust
    assert air == pytest.approx((4.0, -6.0), abs=1e-9)


@pytest.mark.parametrize(
    "changes",
    [{"drag_forward": 0.0}, {"drag_side": -1.0}, {"wind_time": math.nan}, {"settle_time": -1.0}],
)
def test_non_physical_coefficients_are_rejected(changes: dict[str, float]) -> None:
    with pytest.raises(ConfigError):
        WindConfig(**changes)
