"""Survey patterns: a lawn-mower over a rectangle as a chain of cubic traj3d segments.

Straight legs are joined by U-turn segments whose end directions are opposite, so the path is
tangent-continuous and the path-following mode can fly it without stopping; the last segment ends
with zero velocity (it is the single/last segment of chapter §7.2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from hdrc3_base.errors import ConfigError
from hdrc3_control.path_segment import PathSegment


@dataclass(frozen=True, slots=True)
class SurveyArea:
    """A rectangle flown leg by leg, in the local ENU frame."""

    corner_east: float
    corner_north: float
    leg_length: float
    """Length of each leg along ``heading``, m."""
    spacing: float
    """Distance between neighbouring legs, m."""
    legs: int
    altitude: float
    """Flight altitude, m (ENU up of the world origin)."""
    heading: float = math.pi / 2
    """Direction of the first leg, rad clockwise from north (pi/2: east)."""

    def __post_init__(self) -> None:
        """Reject areas the pattern cannot be flown over."""
        numbers = (
            self.corner_east,
            self.corner_north,
            self.leg_length,
            self.spacing,
            self.altitude,
        )
        if not all(math.isfinite(v) for v in (*numbers, self.heading)):
            raise ConfigError(f"survey area must be finite, got {numbers}")
        if self.leg_length <= 0 or self.spacing <= 0 or self.legs < 1:
            raise ConfigError("survey area needs positive leg length and spacing, and >= 1 leg")


def lawn_mower(area: SurveyArea, leg_speed: float, turn_speed: float) -> list[PathSegment]:
    """Build the survey path: legs alternate direction, joined by U-turns to the left.

    Args:
        area: Where to fly.
        leg_speed: Target speed on the legs, m/s.
        turn_speed: Target speed on the turns, m/s (the path follower may lower it further).

    Returns:
        Segments in flight order; only the last has ``end_velocity == 0``.

    """
    if not (leg_speed > 0 and turn_speed > 0):
        raise ConfigError("survey speeds must be positive")
    along = (math.sin(area.heading), math.cos(area.heading), 0.0)
    across = (-along[1], along[0], 0.0)  # 90 degrees to the left of the first leg
    segments: list[PathSegment] = []
    z = area.altitude
    for leg in range(area.legs):
        sign = 1.0 if leg % 2 == 0 else -1.0
        offset = leg * area.spacing
        base = (
            area.corner_east + across[0] * offset,
            area.corner_north + across[1] * offset,
        )
        if sign < 0:
            base = (base[0] + along[0] * area.leg_length, base[1] + along[1] * area.leg_length)
        direction = (along[0] * sign, along[1] * sign, 0.0)
        start = (base[0], base[1], z)
        end = (
            base[0] + direction[0] * area.leg_length,
            base[1] + direction[1] * area.leg_length,
            z,
        )
        last_leg = leg == area.legs - 1
        segments.append(
            PathSegment(
                start,
                end,
                direction,
                direction,
                leg_speed,
                0.0 if last_leg else turn_speed,
                segment_id=len(segments),
            )
        )
        if last_leg:
            break
        turn_end = (end[0] + across[0] * area.spacing, end[1] + across[1] * area.spacing, z)
        reverse = (-direction[0], -direction[1], 0.0)
        segments.append(
            PathSegment(
                end, turn_end, direction, reverse, turn_speed, turn_speed, segment_id=len(segments)
            )
        )
    return segments
