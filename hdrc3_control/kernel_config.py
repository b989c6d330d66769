"""Parameters of the PFC kernel (:class:`~hdrc3_control.kernel.PfcKernel`), one dataclass."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from hdrc3_control.car_following import CarFollowingConfig
from hdrc3_control.landing import LandingConfig
from hdrc3_control.path_following import PathFollowingConfig
from hdrc3_control.state_estimator import EstimatorConfig
from hdrc3_control.takeoff import TakeoffConfig
from hdrc3_control.wind_estimate import WindConfig


@dataclass(frozen=True, slots=True)
class KernelConfig:
    """Parameters of the PFC kernel."""

    model: Path | None = None
    """Automata file (default: the shipped ``automata/pfc.hcsm``)."""
    tick: float = 0.02
    takeoff: TakeoffConfig = field(default_factory=TakeoffConfig)
    path: PathFollowingConfig = field(default_factory=PathFollowingConfig)
    landing: LandingConfig = field(default_factory=LandingConfig)
    estimator: EstimatorConfig = field(default_factory=EstimatorConfig)
    wind: WindConfig = field(default_factory=WindConfig)
    """The on-board wind estimate (airframe drag and trim, filter time constants)."""
    track: CarFollowingConfig = field(default_factory=CarFollowingConfig)
    """fcl_track: the car's estimate and the following law."""
    climb_speed: float = 1.5
    """fcl_climb speed along the vertical segment, m/s."""
    segment_start_tolerance: float = 10.0
    """A first Traj3D segment must start this close to the aircraft, m."""
    power_timeout: float = 5.0
    """Wait for the power unit's answer (and for a first power report), s."""
    sync_period: float = 10.0
    ui_window: float = 3.0
    """UI Timer: a command key must follow the arm key within this time, s."""
    gps_timeout: float = 1.0
    """Sensors-Ok-CO wants a GPS fix at most this old, s."""
    gps_loss_tolerance: float = 3.0
    """Dead reckoning shorter than this rides through a GPS dropout; longer is Nav-Degraded, s."""
    warm_start_max_age: float = 120.0
    """A warm-start record older than this (sim time) is not used, s (``warm_start.py``)."""
    pause_gap: float = 0.1
    """Sim time between two ticks beyond which the simulation paused (the gap is not counted
    by the kernel's clock), s. In lockstep no tick is skipped; five are a pause."""
