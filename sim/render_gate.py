"""Holding world_sim's ticks until the camera images have kept up with sim time.

``world_render`` renders each camera exposure world_sim announces (``sensors/<camera>_camera`` +
``ground_truth/<camera>_camera_pose``) in its own process and skips exposures when it falls
behind. Unpaced (``--speed max``) the lockstepped physics outran it, so a camera pipeline got a
fraction of its frames. world_render therefore reports on ``/world_render/progress`` the stamp
of every exposure it has handled (rendered and published, or not wanted), and world_sim does not
start a tick while an agent's newest announced exposure is more than ``lag`` ahead of the
newest one handled: the renderer works on exposure *k* while the physics runs the next ticks,
and images follow sim time at any speed.

Without a world_render (no progress publisher) or without camera exposures announced, nothing is
held. A renderer that stops reporting while still present holds a tick at most ``stall_s`` of
wall time (the tick then runs, the skipped frames are lost as before, and it is counted).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from hdrc3_base.errors import ConfigError

DEFAULT_LAG_S = 0.1
"""Sim time the announced exposures may run ahead of the handled ones (2.5 frames at 25 Hz)."""
MAX_LAG_S = 10.0


@dataclass
class RenderGate:
    """Per agent: the newest exposure announced and the newest one the renderer handled."""

    lag_ns: int
    announced: dict[str, int] = field(default_factory=dict)
    handled: dict[str, int] = field(default_factory=dict)
    stalls: int = 0
    """Ticks that ran after waiting ``stall_s`` for a renderer that did not report."""

    @classmethod
    def from_seconds(cls, lag_s: float) -> RenderGate:
        """A gate allowing ``lag_s`` of sim time; ConfigError outside 0 .. :data:`MAX_LAG_S`."""
        if not 0.0 <= lag_s <= MAX_LAG_S:  # also false for NaN
            raise ConfigError(f"parameter render_lag: expected 0 .. {MAX_LAG_S} s, got {lag_s}")
        return cls(round(lag_s * 1e9))

    def announce(self, agent: str, stamp_ns: int) -> None:
        """world_sim published the metadata and pose of an exposure stamped ``stamp_ns``."""
        self.announced[agent] = stamp_ns

    def report(self, agent: str, stamp_ns: int) -> None:
        """The renderer handled ``agent``'s exposure ``stamp_ns`` (its newest report counts)."""
        self.handled[agent] = stamp_ns

    def behind(self) -> list[str]:
        """Agents whose renderer lags more than ``lag_ns`` behind their announced exposures."""
        return sorted(
            agent
            for agent, stamp in self.announced.items()
            if self.handled.get(agent, -1) < stamp - self.lag_ns
        )

    def reset(self) -> None:
        """Forget every stamp (a full reset restarts sim time at 0)."""
        self.announced.clear()
        self.handled.clear()
