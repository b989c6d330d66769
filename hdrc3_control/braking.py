"""Emergency braking (chapter 6.1.1, fcl_emergency_brake).

Path following on a straight path with zero target velocity until the aircraft has stopped;
then the kernel hovers there.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from hdrc3_control.commands import AttitudeCommand, EstimatedState, Vec3
from hdrc3_control.path_following import PathFollower, PathFollowingConfig, PathStatus
from hdrc3_control.path_segment import PathSegment
from hdrc3_control.velocity_profile import braking_distance


class BrakeStatus(enum.Enum):
    """Status of the braking function."""

    BRAKING = "braking"
    STOPPED = "stopped"
    NAVIGATION_LOST = "navigation_lost"


@dataclass(frozen=True, slots=True)
class BrakeOutput:
    """Command and status of one tick; ``hover_point`` is set once stopped."""

    command: AttitudeCommand
    status: BrakeStatus
    speed: float
    hover_point: Vec3 | None


def braking_segment(state: EstimatedState, decel: float, segment_id: int = -1) -> PathSegment:
    """Straight path along the current ground track, long enough to stop, zero target velocity."""
    ve, vn, _ = state.velocity
    speed = math.hypot(ve, vn)
    if speed > 0.5:
        de, dn = ve / speed, vn / speed
    else:
        de, dn = math.sin(state.heading), math.cos(state.heading)
    length = braking_distance(speed, decel) + 5.0
    x, y, z = state.position
    end = (x + de * length, y + dn * length, z)
    return PathSegment.straight(state.position, end, 0.0, 0.0, segment_id)


class EmergencyBrake:
    """Brakes from the state it is started in (Braking-ST of the Mode Switch automaton)."""

    def __init__(self, config: PathFollowingConfig | None = None) -> None:
        """Create the function; :meth:`start` engages it."""
        self.follower = PathFollower(config)

    def start(self, state: EstimatedState, integral: tuple[float, float] = (0.0, 0.0)) -> None:
        """Engage braking from ``state``."""
        seg = braking_segment(state, self.follower.config.limits.braking_decel)
        self.follower.start(state, seg, integral)

    def update(self, state: EstimatedState, now: float) -> BrakeOutput:
        """One tick."""
        out = self.follower.update(state, now)
        status = {
            PathStatus.STOPPED: BrakeStatus.STOPPED,
            PathStatus.NAVIGATION_LOST: BrakeStatus.NAVIGATION_LOST,
        }.get(out.status, BrakeStatus.BRAKING)
        speed = math.hypot(state.velocity[0], state.velocity[1])
        return BrakeOutput(out.command, status, speed, out.hover_point)
