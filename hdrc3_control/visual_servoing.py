"""Camera pan-tilt visual servoing: keep a tracked object in the image's centre (§5.4, §6.1).

"Camera Pan-Tilt visual servoing control: Keep a tracked object in the center of the camera
image. The position of the object is provided by image processing functionalities such as
vision-based color object tracking." The landing pad's pose (state estimation) and the colour
tracker's target are two such objects.

Each :class:`Sighting` says in which direction of an image's optical frame the object was; with
the PTU's angles at that image's time (interpolated in its read-out history) the direction is
turned into the pan and tilt that put it on the optical axis. Angles at the image's time, not
the current ones: the image is late, and re-aiming from today's angles with yesterday's offset
would overshoot. A moving object (a car at 10 m/s) moves on while the image travels and while
the PTU turns, so successive sightings feed a constant-velocity (alpha-beta) estimate of the
object's pan and tilt, and the servo aims where the object will be when the PTU gets there
(``lead`` after the set-point leaves). The estimate is bounded: its rates at most the PTU's
slew rates, its extrapolation at most ``horizon`` past the last sighting, restarted after a gap.
The set-point moves towards the aim at most at the slew rates (:class:`PtuLimits`), so the
commands stay within what the unit can do. After the object is lost the set-point holds
``hold`` seconds (an occlusion is short), then the PTU goes back to its commanded mode.

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

READING_WINDOW = 0.1
"""s: a sighting needs a PTU read-out within this of its image's time."""
GAIN_ANGLE = 0.6
"""Alpha of the alpha-beta estimate: share of a new sighting's residual taken into the angle."""
GAIN_RATE = 0.25
"""Beta of the alpha-beta estimate (critically damped for ``GAIN_ANGLE``: b = a^2 / (2 - a))."""
RESTART_GAP = 0.5
"""s: sightings further apart than this restart the rate estimate (too old to difference)."""


@dataclass(frozen=True, slots=True)
class Sighting:
    """The tracked object's centre in the optical frame of the image taken at ``time``."""

    time: float
    direction: Vec3
    """Optical frame (x right, y down, z forward); any length (a position in m works)."""


@dataclass(frozen=True, slots=True)
class _Estimate:
    """The object's pan and tilt (rad) at ``time`` and their rates (rad/s)."""

    time: float
    pan: float
    tilt: float
    pan_rate: float = 0.0
    tilt_rate: float = 0.0
    measured: bool = True
    """False while holding still for a new object's first sighting (no rates to keep)."""

    def at(self, time: float) -> tuple[float, float]:
        """Angles extrapolated to ``time``."""
        dt = time - self.time
        return self.pan + self.pan_rate * dt, self.tilt + self.tilt_rate * dt


def aim_at(direction: Vec3, pan: float, tilt: float) -> tuple[float, float]:
    """Pan and tilt that put an optical-frame ``direction`` (seen at ``pan``, ``tilt``) on axis."""
    ox, oy, oz = direction
    bx, by, bz = oz, ox, oy  # PTU frame: x boresight, y right, z down
    ct, st = math.cos(tilt), math.sin(tilt)
    x1, z1 = ct * bx - st * bz, st * bx + ct * bz  # tilt about y (positive looks down)
    cp, sp = math.cos(pan), math.sin(pan)
    x, y = cp * x1 - sp * by, sp * x1 + cp * by  # pan about z
    return math.atan2(y, x), math.atan2(z1, math.hypot(x, y))


class PtuServo:
    """Set-points that keep the object centred; None when there is nothing (recent) to track.

    Args:
        limits: PTU ranges and slew rates.
        hold: s the set-point holds after the last sighting before letting go.
        lead: s from a set-point's computation to the PTU pointing there (the command's trip
            and half the PPC's period); the aim is the object's predicted angles then.
        horizon: s, at most this far past the last sighting the angles are extrapolated;
            0 disables the prediction (aim at the last sighting).
    """

    def __init__(
        self,
        limits: PtuLimits | None = None,
        hold: float = 2.0,
        *,
        lead: float = 0.04,
        horizon: float = 0.5,
    ) -> None:
        self.limits = limits or PtuLimits()
        self.hold = hold
        self.lead = lead
        self.horizon = horizon
        self._readings: deque[tuple[float, float, float]] = deque(maxlen=50)
        self._estimate: _Estimate | None = None
        self._seen = -math.inf
        self.setpoint: tuple[float, float] | None = None
        self._time: float | None = None
        self.sightings = 0
        """Sightings taken into the estimate (the others had no PTU reading of their time)."""

    def reset(self) -> None:
        """Stop tracking (image processing stopped, object lost): no estimate, no set-point."""
        self._estimate, self.setpoint, self._seen = None, None, -math.inf

    def restart(self, now: float) -> None:
        """A new object: forget the old one's motion; if servoing, hold still until it is seen.

        A set-point holds for ``hold`` seconds from ``now`` (the camera stays where the new
        object was picked, instead of swinging back to the commanded mode in between); without
        one the PTU keeps following its commanded mode until the first sighting.
        """
        held = self.setpoint
        self.reset()
        if held is not None:
            self._estimate = _Estimate(now, held[0], held[1], measured=False)
            self._seen = now

    def reading(self, time: float, pan: float, tilt: float) -> None:
        """A PTU angle read-out (times increase; others are dropped)."""
        if all(math.isfinite(v) for v in (time, pan, tilt)) and (
            not self._readings or time > self._readings[-1][0]
        ):
            self._readings.append((time, pan, tilt))

    def angles_at(self, time: float) -> tuple[float, float] | None:
        """The PTU's angles at ``time`` from its read-outs; None without one near enough."""
        before = next((r for r in reversed(self._readings) if r[0] <= time), None)
        after = next((r for r in self._readings if r[0] >= time), None)
        if before is not None and after is not None and after[0] > before[0]:
            w = (time - before[0]) / (after[0] - before[0])
            return (
                before[1] + w * (after[1] - before[1]),
                before[2] + w * (after[2] - before[2]),
            )
        near = before or after
        if near is None or abs(near[0] - time) > READING_WINDOW:
            return None
        return near[1], near[2]

    def see(self, sighting: Sighting) -> bool:
        """Take a sighting into the estimate.

        Returns:
            False if it was unusable: not finite, behind the camera, no PTU reading within
            0.1 s of its time, or not newer than the estimate (or older than a restart).
        """
        d = sighting.direction
        if not all(math.isfinite(v) for v in (sighting.time, *d)) or d[2] <= 0.0:
            return False
        angles = self.angles_at(sighting.time)
        est = self._estimate
        stale = est is not None and (
            sighting.time <= est.time if est.measured else sighting.time < est.time
        )
        if angles is None or stale:
            return False
        pan, tilt = aim_at(d, *angles)
        turns = [pan + k * math.tau for k in (-1, 0, 1)]
        reachable = [p for p in turns if self.limits.min_pan <= p <= self.limits.max_pan]
        pan = min(reachable or turns, key=lambda p: abs(p - angles[0]))  # the shorter way round
        self._estimate = self._filtered(sighting.time, pan, tilt)
        self._seen = max(self._seen, sighting.time)
        self.sightings += 1
        return True

    def _filtered(self, time: float, pan: float, tilt: float) -> _Estimate:
        """The alpha-beta step of the estimate with one measured pan and tilt."""
        est = self._estimate
        dt = math.inf if est is None else time - est.time
        if est is None or not est.measured or dt > RESTART_GAP:
            return _Estimate(time, pan, tilt)
        pred_pan, pred_tilt = est.at(time)
        r_pan, r_tilt = pan - pred_pan, tilt - pred_tilt
        lim = self.limits
        return _Estimate(
            time,
            pred_pan + GAIN_ANGLE * r_pan,
            pred_tilt + GAIN_ANGLE * r_tilt,
            _bounded(est.pan_rate + GAIN_RATE * r_pan / dt, lim.pan_rate),
            _bounded(est.tilt_rate + GAIN_RATE * r_tilt / dt, lim.tilt_rate),
        )

    @property
    def rates(self) -> tuple[float, float]:
        """Estimated pan and tilt rates of the object (rad/s; zero without an estimate)."""
        est = self._estimate
        return (0.0, 0.0) if est is None else (est.pan_rate, est.tilt_rate)

    def aim(self, now: float) -> tuple[float, float] | None:
        """Where the object is predicted to be ``lead`` after ``now`` (settable angles)."""
        est = self._estimate
        if est is None:
            return None
        ahead = min(max(now + self.lead - est.time, 0.0), self.horizon)
        return clamp(self.limits, *est.at(est.time + ahead))

    def update(self, now: float) -> tuple[float, float] | None:
        """The set-point at ``now``: towards the aim within the slew rates, or None."""
        dt = 0.0 if self._time is None else max(0.0, now - self._time)
        self._time = now
        target = self.aim(now)
        if target is None or now - self._seen > self.hold:
            self.reset()
            return None
        if self.setpoint is None:
            start = self._readings[-1][1:] if self._readings else target
            self.setpoint = (start[0], start[1])
        lim = self.limits
        pan = _towards(self.setpoint[0], target[0], lim.pan_rate * dt)
        tilt = _towards(self.setpoint[1], target[1], lim.tilt_rate * dt)
        self.setpoint = (pan, tilt)
        return self.setpoint


def _bounded(value: float, bound: float) -> float:
    return min(max(value, -bound), bound)


def _towards(value: float, target: float, step: float) -> float:
    return value + _bounded(target - value, step)
