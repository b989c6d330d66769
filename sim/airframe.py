"""Where the payload sits on the simulated RMAX: the mounting calibration the stack knows too.

The one source of the pan-tilt unit's mount point: the simulator's cameras are built to it
(``sim.sensors.camera``), and the autonomy stack reads it as calibration data (the PPC's look-at
angles, the perception core's camera pose, the landing pad fix), like the world file.
"""

from __future__ import annotations

PTU_MOUNT_FRD: tuple[float, float, float] = (0.3, 0.0, 0.45)
"""PTU centre relative to the centre of gravity, body FRD, m (platform under the fuselage)."""
