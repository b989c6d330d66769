"""The helicopter's position and attitude from the landing pad's pose (chapter §5.4).

"The pose parameters are converted to helicopter position and attitude using angles from the
PTU and known frame offsets and rotations." The inputs are all the aircraft's own knowledge:

- the pad's pose in the colour camera's optical frame (:mod:`hdrc3_perception.pad_pose`);
- the PTU's angle read-out at the image's time (:class:`~hdrc3_perception.history.PtuHistory`,
  interpolated);
- the PTU's mount point on the airframe (``sim.airframe``, via :data:`camera.MOUNT_OFFSET`);
- where the pad lies (map knowledge: the world file's pad, ``sim.landing_pattern``'s frame).

Chain: camera in the pad frame ``-R^T t`` -> ENU with the pad's placement; optical -> ENU is
``A R^T`` (``A`` pad -> ENU); body -> ENU is that times the PTU's optical -> body inverse;
the centre of gravity is the camera minus the mount offset rotated to ENU. The attitude comes
from the vision rotation alone, so the fix does not depend on the attitude sensor (its
magnetic heading error of about a degree would move a fix taken 12 m off the pad by 20 cm).

:func:`fix_sigma` is the fix's 1-sigma per axis as a function of the range to the pad, fitted
to ``bench/pad_pose.py`` (the camera's position on the pad carries the attitude error times the
range): what the Kalman filter weighs it with.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from hdrc3_base.errors import ConfigError
from hdrc3_perception.camera import MOUNT_OFFSET, Vec3, euler_of, optical_to_body
from sim.landing_pattern import pad_axes, pad_origin
from sim.world import World

SIGMA_FLOOR_M = 0.02
"""Fix 1-sigma close to the pad (pixel quantisation, PTU read-out over the mount lever), m."""
SIGMA_PER_M2 = 2.5e-4
"""Growth of the fix 1-sigma with the squared range (attitude error times range), 1/m."""


class FixStatus(enum.Enum):
    """Whether a pad pose gave a helicopter fix."""

    OK = "ok"
    NO_PTU = "no_ptu"  # no PTU reading close enough to the image's time
    BAD_POSE = "bad_pose"  # non-finite or degenerate pose


@dataclass(frozen=True, slots=True)
class PadPlacement:
    """Where the pattern lies: the pad frame's origin (ENU, m) and its axes (pad -> ENU)."""

    name: str
    origin: NDArray[np.float64]
    axes: NDArray[np.float64]

    @staticmethod
    def of_world(world: World, name: str = "") -> PadPlacement:
        """The world's patterned pad ``name`` ("" = its only one); ConfigError otherwise."""
        patterned = [p for p in world.pads if p.pattern]
        if name:
            chosen = [p for p in patterned if p.name == name]
        else:
            chosen = patterned if len(patterned) == 1 else []
        if not chosen:
            names = ", ".join(p.name for p in patterned) or "none"
            wanted = repr(name) if name else "its only one"
            raise ConfigError(
                f"world {world.name!r} has no patterned pad {wanted} (patterned: {names})"
            )
        pad = chosen[0]
        ground = world.terrain.height(pad.east, pad.north)
        return PadPlacement(
            pad.name, pad_origin(pad.east, pad.north, ground), pad_axes(pad.heading)
        )


@dataclass(frozen=True, slots=True)
class HelicopterFix:
    """The helicopter's centre of gravity (ENU) and attitude from one image, or why none."""

    status: FixStatus
    time: float
    reason: str = ""
    position: Vec3 = (math.nan, math.nan, math.nan)
    roll: float = math.nan
    pitch: float = math.nan
    heading: float = math.nan
    """rad clockwise from north, [0, 2 pi)."""
    range_m: float = math.nan
    """Distance camera - pad centre, m."""
    sigma: float = math.nan
    """1-sigma per axis of ``position``, m (:func:`fix_sigma`)."""


def fix_sigma(range_m: float) -> float:
    """1-sigma per axis of a fix taken ``range_m`` from the pad, m."""
    return SIGMA_FLOOR_M + SIGMA_PER_M2 * range_m * range_m


def helicopter_fix(
    time: float,
    rotation: NDArray[np.float64],
    translation: NDArray[np.float64],
    ptu: tuple[float, float] | None,
    placement: PadPlacement,
    mount: Vec3 = MOUNT_OFFSET,
) -> HelicopterFix:
    """The helicopter fix from the pad's pose in the optical frame and the PTU angles.

    ``rotation`` takes pad vectors to the camera frame, ``translation`` is the pad's origin in
    the camera frame, ``ptu`` the (pan, tilt) at the image's ``time`` (None: no reading).
    """
    if ptu is None:
        return HelicopterFix(FixStatus.NO_PTU, time, "no PTU reading at the image's time")
    r = np.asarray(rotation, dtype=np.float64)
    t = np.asarray(translation, dtype=np.float64)
    finite = bool(np.all(np.isfinite(r)) and np.all(np.isfinite(t)))
    if not (finite and r.shape == (3, 3) and t.shape == (3,) and math.isfinite(sum(ptu))):
        return HelicopterFix(FixStatus.BAD_POSE, time, "pose or PTU angles not finite")
    if abs(float(np.linalg.det(r)) - 1.0) > 1e-6 or float(np.linalg.norm(t)) <= 0.0:
        return HelicopterFix(FixStatus.BAD_POSE, time, "rotation not proper or zero range")
    camera = placement.origin + placement.axes @ (-r.T @ t)
    optical = placement.axes @ r.T
    body = optical @ optical_to_body(*ptu).T
    cg = camera - body @ np.asarray(mount, dtype=np.float64)
    roll, pitch, heading = euler_of(body)
    distance = float(np.linalg.norm(t))
    return HelicopterFix(
        FixStatus.OK,
        time,
        position=(float(cg[0]), float(cg[1]), float(cg[2])),
        roll=roll,
        pitch=pitch,
        heading=heading,
        range_m=distance,
        sigma=fix_sigma(distance),
    )
