"""The PFC's and PPC's latest state data as the DRC sees it (inputs of the DRC conditions).

The PFC publishes its state every control tick (hdrc3_interfaces/PfcState); the PPC publishes the
camera state. The node converts both into these dataclasses; the DRC automaton's conditions
(On-Ground-CO, Auto-CO, Hover-Stable-CO, Data-Fresh-CO) and the Data Interface read them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from hdrc3_control.pfc_state import FlightMode

Vec3 = tuple[float, float, float]

HOVER_SPEED_TOLERANCE = 1.0
"""m/s, horizontal and vertical (Hover-Stable-CO tolerances of section 6.1.1)."""


@dataclass(frozen=True, slots=True)
class PfcSample:
    """One PFC state report (local ENU, SI units; WGS84 position in degrees / metres)."""

    pfc_time: float
    """s, the PFC clock when the state was computed."""
    received: float
    """s, the DRC clock when the report arrived."""
    position_enu: Vec3
    velocity_enu: Vec3
    latitude: float
    longitude: float
    altitude: float
    roll: float
    pitch: float
    heading: float
    rpm: float
    on_ground: bool
    auto_flag: bool
    mode: int = FlightMode.BOOT
    command_id: int = 0
    power_status: int = 0
    failsafe: int = 0
    """PfcState.FAILSAFE_* (hdrc3_control.pfc_state.Failsafe)."""
    failsafe_reason: str = ""

    @property
    def hover_stable(self) -> bool:
        """Hovering in autonomous mode with velocities inside the tolerances."""
        v = self.velocity_enu
        return (
            self.mode == FlightMode.HOVER
            and self.auto_flag
            and not self.on_ground
            and math.hypot(v[0], v[1]) < HOVER_SPEED_TOLERANCE
            and abs(v[2]) < HOVER_SPEED_TOLERANCE
        )


@dataclass(frozen=True, slots=True)
class CameraSample:
    """One camera state from the PPC."""

    camera_id: int
    pan: float
    tilt: float
    zoom: float
    ipc_time: float
    """s, the PPC clock of the report."""
    received: float
    """s, the DRC clock when it arrived."""


class PlatformStatus:
    """Latest PFC and PPC data with freshness checks."""

    def __init__(self, stale_after: float = 2.0) -> None:
        self.stale_after = stale_after
        self.pfc: PfcSample | None = None
        self.cameras: dict[int, CameraSample] = {}
        self.power_status = 0
        self.now = 0.0

    def update_pfc(self, sample: PfcSample) -> None:
        """Store a PFC report."""
        self.pfc = sample

    def update_camera(self, sample: CameraSample) -> None:
        """Store a PPC camera report."""
        self.cameras[sample.camera_id] = sample

    def pfc_fresh(self) -> bool:
        """True if the last PFC report is younger than ``stale_after`` (DRC clock)."""
        return self.pfc is not None and self.now - self.pfc.received <= self.stale_after

    def ppc_fresh(self) -> bool:
        """True if a camera report from the PPC is younger than ``stale_after``."""
        return any(self.now - c.received <= self.stale_after for c in self.cameras.values())

    # --- DRC conditions -------------------------------------------------------------------
    def on_ground(self) -> bool:
        """On-Ground-CO."""
        return self.pfc_fresh() and self.pfc is not None and self.pfc.on_ground

    def airborne(self) -> bool:
        """Airborne-CO."""
        return self.pfc_fresh() and self.pfc is not None and not self.pfc.on_ground

    def auto(self) -> bool:
        """Auto-CO."""
        return self.pfc is not None and self.pfc.auto_flag

    def hover_stable(self) -> bool:
        """Hover-Stable-CO."""
        return self.pfc_fresh() and self.pfc is not None and self.pfc.hover_stable
