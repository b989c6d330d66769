"""Real-time-factor pacing of sim time against the wall clock (the only wall-clock use of the sim).

Pacing decides *when* a tick may run, never *what* it computes, so trajectories do not depend on
it. The anchor is moved whenever pacing restarts (start, resume, reset, end of lockstep) so that a
pause or a slow phase is not "caught up" afterwards in a burst.
"""

from __future__ import annotations

import math

from hdrc3_base.errors import ConfigError


class Pacer:
    """Maps sim time to the wall time it is due at, for a speed factor (0: unpaced)."""

    def __init__(self, speed: float) -> None:
        """``speed`` is sim seconds per wall second; 0 means as fast as possible."""
        if not (math.isfinite(speed) and speed >= 0.0):
            raise ConfigError(
                f"speed must be a finite factor >= 0 (0: as fast as possible), got {speed}"
            )
        self.speed = speed
        self._anchor: tuple[float, float] | None = None

    def restart(self) -> None:
        """Forget the anchor: the next :meth:`due` call re-anchors at its own times."""
        self._anchor = None

    def due(self, sim_time: float, wall_now: float) -> float:
        """Wall time at which ``sim_time`` is due (``wall_now`` anchors a fresh start)."""
        if self.speed == 0.0:
            return wall_now
        if self._anchor is None:
            self._anchor = (wall_now, sim_time)
        wall0, sim0 = self._anchor
        return wall0 + (sim_time - sim0) / self.speed

    def wait_time(self, sim_time: float, wall_now: float) -> float:
        """Seconds still to wait before ``sim_time`` may run (>= 0).

        A tick running more than a second late re-anchors (the sim cannot keep up, or was
        paused): the factor then holds from now on instead of racing to catch up.
        """
        remaining = self.due(sim_time, wall_now) - wall_now
        if remaining < -1.0:
            self._anchor = (wall_now, sim_time)
            return 0.0
        return max(0.0, remaining)
