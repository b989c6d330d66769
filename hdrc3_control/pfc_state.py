"""What the PFC kernel takes in besides sensor samples, and what it reports every tick.

:class:`PlatformStatus` is the YACS/RC side (RC switch, link, engine), :class:`PowerReading` the
power management unit; :class:`PfcSnapshot` is the state the node publishes as
``hdrc3_interfaces/PfcState`` on ``<agent>/pfc/state``.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from hdrc3_control.commands import EstimatorHealth, Vec3

POWER_DRC = 4
POWER_GPS = 8
POWER_IMU = 16
"""Power status bits of HelicopterState.POWER_* (chapter section 4.3)."""
SENSOR_POWER = POWER_GPS | POWER_IMU
"""Devices the PFC needs to fly."""


class FlightMode(enum.IntEnum):
    """The PFC's flight mode (numbers of PfcState.MODE_*, sent in Mode-Changed-EV)."""

    BOOT = 0
    MANUAL = 1
    GROUND_IDLE = 2
    BRAKING = 3
    HOVER = 4
    TAKEOFF = 5
    TRAJ3D = 6
    FLYTO = 7
    LAND = 8
    SWITCHING = 9


class Failsafe(enum.IntEnum):
    """The navigation failsafe in force (numbers of PfcState/HelicopterState.FAILSAFE_*).

    Decided by the Failsafe automaton (``automata/failsafe.hcsm``); the policy is in
    ``hdrc3_platform_server/README.md``.
    """

    NONE = 0
    HOLD = 1
    """GPS lost: braking and hovering on dead reckoning; flight commands but land refused."""
    LAND = 2
    """Navigation lost: emergency landing."""


FAILSAFE_STATES = {
    "Fs-None-ST": Failsafe.NONE,
    "Fs-Hold-ST": Failsafe.HOLD,
    "Fs-Land-ST": Failsafe.LAND,
}
"""Failsafe automaton state -> failsafe."""
FAILSAFE_PREFIX = "failsafe"
"""PFC-Fault-EV texts starting with this announce a failsafe change (docs/realtime_events.md)."""


@dataclass(frozen=True, slots=True)
class PlatformStatus:
    """The RC transmitter and engine as the YACS reports them (``<agent>/yacs/status``)."""

    time: float
    autonomous: bool
    """RC flight mode switch in the autonomous position."""
    rc_link_ok: bool
    engine_running: bool
    rotor_rpm: float


@dataclass(frozen=True, slots=True)
class PowerReading:
    """One power management unit report: which devices are powered (POWER_* bits)."""

    time: float
    status: int


@dataclass(frozen=True, slots=True)
class PfcSnapshot:
    """The kernel's state after one tick (sim time ``time``)."""

    time: float
    mode: FlightMode
    position: Vec3
    velocity: Vec3
    roll: float
    pitch: float
    heading: float
    rates: Vec3
    rotor_rpm: float
    on_ground: bool
    auto: bool
    engine_running: bool
    estimator_initialised: bool
    health: EstimatorHealth
    position_sigma: float
    control_function: str
    mode_switch_state: str
    command_id: int
    ticks: int
    failsafe: Failsafe = Failsafe.NONE
    failsafe_reason: str = ""
    """The announcement of the failsafe in force ("" when none)."""
