"""The PTU keeps the landing pad in the image's centre (chapter §5.4, §6.1).

"Once the pattern is found another state machine controls the camera in order to keep the
pattern in the centre of the image."

Visual servoing on the pad_pose node's output: each pose says where the pad's centre is in the
optical frame of an image; with the PTU's angles at that image's time (its read-out history)
that direction is turned into the body frame and into the pan and tilt that put it on the
optical axis. The set-point moves there at most at the PTU's slew rates (:class:`PtuLimits`),
so the commands stay within what the unit can do (and the picture does not blur). Angles at the
image's time, not the current ones: the image is late, and re-aiming from today's angles with
yesterday's offset would overshoot. After the pad is lost the set-point holds ``hold`` seconds
(an occlusion is short), then the PTU goes back to its commanded mode (e.g. a search pointing).

PTU conventions as :mod:`hdrc3_control.ppc_modes`: pan about body z (right), tilt about the
panned y (down); optical frame x right, y down, z forward.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

from hdrc3_control.ppc_hardware import PtuLimits
from hdrc3_control.ppc_modes import clamp

Vec3 = tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class PadSighting:
    """The pad's centre in the optical frame of the image taken at ``time``."""

    time: float
    position: Vec3
    """m, optical frame (x right, y down, z forward)."""


def aim_at(direction: Vec3, pan: float, tilt: float) -> tuple[float, float]:
    """Pan and tilt that put an optical-frame ``direction`` (seen at ``pan``, ``tilt``) on axis."""
    ox, oy, oz = direction
    bx, by, bz = oz, ox, oy  # PTU frame: x boresight, y right, z down
    ct, st = math.cos(tilt), math.sin(tilt)
    x1, z1 = ct * bx - st * bz, st * bx + ct * bz  # tilt about y (positive looks down)
    cp, sp = math.cos(pan), math.sin(pan)
    x, y = cp * x1 - sp * by, sp * x1 + cp * by  # pan about z
    return math.atan2(y, x), math.atan2(z1, math.hypot(x, y))


class PadTracker:
    """Set-points that keep the pad centred; None when there is nothing (recent) to track."""

    def __init__(self, limits: PtuLimits | None = None, hold: float = 2.0) -> None:
        self.limits = limits or PtuLimits()
        self.hold = hold
        self._readings: deque[tuple[float, float, float]] = deque(maxlen=50)
        self._target: tuple[float, float] | None = None
        self._seen = -math.inf
        self.setpoint: tuple[float, float] | None = None
        self._time: float | None = None
        self.sightings = 0
        """Sightings turned into a target (the others had no PTU reading of their time)."""

    def reset(self) -> None:
        """Stop tracking (image processing stopped): no target, no set-point."""
        self._target, self.setpoint, self._seen = None, None, -math.inf

    def reading(self, time: float, pan: float, tilt: float) -> None:
        """A PTU angle read-out (times increase; others are dropped)."""
        if all(math.isfinite(v) for v in (time, pan, tilt)) and (
            not self._readings or time > self._readings[-1][0]
        ):
            self._readings.append((time, pan, tilt))

    def see(self, sighting: PadSighting) -> bool:
        """Aim at a sighting; False if no PTU reading lies within 0.1 s of its time."""
        if not all(math.isfinite(v) for v in sighting.position) or sighting.position[2] <= 0.0:
            return False
        near = min(self._readings, key=lambda r: abs(r[0] - sighting.time), default=None)
        if near is None or abs(near[0] - sighting.time) > 0.1:
            return False
        pan, tilt = aim_at(sighting.position, near[1], near[2])
        turns = [pan + k * math.tau for k in (-1, 0, 1)]
        reachable = [p for p in turns if self.limits.min_pan <= p <= self.limits.max_pan]
        pan = min(reachable or turns, key=lambda p: abs(p - near[1]))  # the shorter way round
        self._target = clamp(self.limits, pan, tilt)
        self._seen = max(self._seen, sighting.time)
        self.sightings += 1
        return True

    def update(self, now: float) -> tuple[float, float] | None:
        """The set-point at ``now``: towards the target within the slew rates, or None."""
        dt = 0.0 if self._time is None else max(0.0, now - self._time)
        self._time = now
        if self._target is None or now - self._seen > self.hold:
            self.setpoint = None
            return None
        if self.setpoint is None:
            start = self._readings[-1][1:] if self._readings else self._target
            self.setpoint = (start[0], start[1])
        lim = self.limits
        pan = _towards(self.setpoint[0], self._target[0], lim.pan_rate * dt)
        tilt = _towards(self.setpoint[1], self._target[1], lim.tilt_rate * dt)
        self.setpoint = (pan, tilt)
        return self.setpoint


def _towards(value: float, target: float, step: float) -> float:
    return value + min(max(target - value, -step), step)
