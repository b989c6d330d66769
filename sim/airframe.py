"""Where the payload sits on the simulated RMAX: the mounting calibration the stack knows too.

The one source of the pan-tilt unit's and the laser range finder's mount points: the simulator's
sensors are built to them (``sim.sensors.camera``, ``sim.sensors.laser``), and the autonomy stack
reads them as calibration data (the PPC's look-at angles, the perception core's camera pose, the
landing pad fix, the laser mapper's point cloud), like the world file.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from sim.sensors.frames import body_to_enu, rot_y

PTU_MOUNT_FRD: tuple[float, float, float] = (0.3, 0.0, 0.45)
"""PTU centre relative to the centre of gravity, body FRD, m (platform under the fuselage)."""
LRF_MOUNT_FRD: tuple[float, float, float] = (1.4, 0.0, 0.3)
"""Laser range finder centre relative to the centre of gravity, body FRD, m (front of the
fuselage, Figure 3)."""
LRF_MOUNT_TILT = 0.0
"""Rotation axis of the laser's mechanism (its middle beam) below the body x axis, rad."""


def scan_rays(
    position: tuple[float, float, float],
    attitude: tuple[float, float, float],
    rotation_angle: float,
    beam_angles: NDArray[np.float64],
    mount_offset: tuple[float, float, float] = LRF_MOUNT_FRD,
    mount_tilt: float = LRF_MOUNT_TILT,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Where one laser scan line's beams start and point, for an aircraft pose.

    The one beam geometry of the rotating LMS-291: the simulator casts the beams from the true
    pose (``sim.sensors.laser``); the laser mapper registers returns with the aircraft's own
    navigation solution.

    Args:
        position: Centre of gravity, local ENU, m.
        attitude: Roll, pitch and heading (clockwise from north), rad.
        rotation_angle: The mechanism's angle about the middle beam, rad.
        beam_angles: Beam angles in the scan plane, rad.
        mount_offset: Sensor centre in body FRD, m.
        mount_tilt: Middle beam below the body x axis, rad.

    Returns:
        The sensor origin (ENU) and unit beam directions (N x 3, ENU).

    """
    alpha = np.asarray(beam_angles, dtype=np.float64)
    c, s = math.cos(rotation_angle), math.sin(rotation_angle)
    # Scan plane spanned by the middle beam (x) and the rotated sensor y axis.
    local = np.stack([np.cos(alpha), np.sin(alpha) * c, np.sin(alpha) * s], axis=1)
    body = body_to_enu(*attitude)
    to_enu = body @ rot_y(-mount_tilt)
    origin = np.asarray(position, dtype=np.float64) + body @ np.asarray(mount_offset)
    directions: NDArray[np.float64] = local @ to_enu.T
    return origin, directions
