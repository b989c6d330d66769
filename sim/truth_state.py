"""Ground-truth state of one simulated aircraft: the contract between flight model and sensors.

The flight model produces it every FDM step; sensors, the world_sim node and test evaluation read
it. The autonomy stack itself never sees it (it only gets sensor samples).

Frames: positions and velocities in the world's local ENU frame (metres, origin at the world's
geodetic origin, z up); body frame FRD (x forward, y right, z down) for rates and specific force.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class TruthState:
    """Exact state of one aircraft at one instant of simulated time."""

    time: float
    """Simulated time, s since the simulation started."""
    position_enu: tuple[float, float, float]
    """Position of the centre of gravity, m, local ENU frame."""
    velocity_enu: tuple[float, float, float]
    """Velocity of the centre of gravity, m/s, local ENU frame."""
    roll: float
    """Roll angle (Euler 3-2-1), rad, right wing down positive."""
    pitch: float
    """Pitch angle (Euler 3-2-1), rad, nose up positive."""
    heading: float
    """Heading (yaw, Euler 3-2-1), rad, clockwise from north, in [0, 2*pi)."""
    body_rates: tuple[float, float, float]
    """Angular rates p, q, r about body x, y, z (FRD), rad/s."""
    specific_force_body: tuple[float, float, float]
    """What an ideal accelerometer measures, m/s^2, body FRD (hover: about (0, 0, -9.81))."""
    rotor_rpm: float
    """Main rotor speed, revolutions per minute."""
    engine_running: bool
    """True while the engine runs."""
    on_ground: bool
    """True while the skids carry weight (ground contact)."""
    height_above_ground: float
    """Height of the skids above the terrain directly below, m."""
    mass: float
    """Current total mass, kg (empty mass + fuel + payload)."""
