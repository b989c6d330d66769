"""Emulated RC transmitter of the RMAX: mode switch, engine switch, sticks, link status."""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from hdrc3_base.errors import ConfigError


class FlightModeSwitch(enum.Enum):
    """Position of the transmitter switch that hands control to the flight computer (§6.1.1)."""

    MANUAL = "manual"
    AUTONOMOUS = "autonomous"


@dataclass(frozen=True, slots=True)
class RcSticks:
    """Stick positions: attitude-stabilised (YACS) manual flying."""

    roll: float = 0.0
    """-1 .. 1, right positive."""
    pitch: float = 0.0
    """-1 .. 1, forward (nose down) positive."""
    yaw: float = 0.0
    """-1 .. 1, nose right positive."""
    throttle: float = 0.0
    """Collective stick, 0 .. 1."""

    def __post_init__(self) -> None:
        """Reject positions outside the stick travel."""
        for name in ("roll", "pitch", "yaw"):
            value = getattr(self, name)
            if not (math.isfinite(value) and -1.0 <= value <= 1.0):
                raise ConfigError(f"RC stick {name}={value} outside [-1, 1]")
        if not (math.isfinite(self.throttle) and 0.0 <= self.throttle <= 1.0):
            raise ConfigError(f"RC throttle={self.throttle} outside [0, 1]")


@dataclass(frozen=True, slots=True)
class RcState:
    """Snapshot of everything the transmitter sends (or fails to send)."""

    link_ok: bool
    """True while the transmitter is on and its signal reaches the aircraft."""
    mode: FlightModeSwitch
    engine_on: bool
    sticks: RcSticks


class RcTransmitter:
    """The safety pilot's transmitter: starts powered, manual, engine off, sticks centred."""

    def __init__(self) -> None:
        """Create a powered transmitter in manual mode with the engine switch off."""
        self._link_ok = True
        self._mode = FlightModeSwitch.MANUAL
        self._engine_on = False
        self._sticks = RcSticks()
        self._state = self._snapshot()

    def _snapshot(self) -> RcState:
        return RcState(self._link_ok, self._mode, self._engine_on, self._sticks)

    def set_mode(self, mode: FlightModeSwitch) -> None:
        """Flip the manual/autonomous switch."""
        self._mode = mode
        self._state = self._snapshot()

    def set_engine(self, on: bool) -> None:
        """Engine switch: on starts (and keeps) the engine running, off stops it."""
        self._engine_on = on
        self._state = self._snapshot()

    def set_link(self, ok: bool) -> None:
        """Transmitter power / radio link (False emulates a lost link)."""
        self._link_ok = ok
        self._state = self._snapshot()

    def set_sticks(self, sticks: RcSticks) -> None:
        """Move the sticks."""
        self._sticks = sticks
        self._state = self._snapshot()

    @property
    def state(self) -> RcState:
        """What the aircraft receives now."""
        return self._state
