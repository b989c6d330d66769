"""What the aircraft knew at an image's time: recent navigation states and PTU read-outs.

An image reaches a perception node later than the state and the PTU angles of the moment it
was exposed (the renderer, the transport, a busy executor), so a node that paired each image
with the latest state would place what it sees where the aircraft had moved to since. The
nodes keep the last states and read-outs here and look them up at the image's stamp:
:class:`NavHistory` (the Data Interface's ``helicopter_state``, 25 Hz: the nearest one) and
:class:`PtuHistory` (``sensors/ptu``: interpolated between the two around the time).
"""

from __future__ import annotations

import math
from collections import deque

from hdrc3_perception.camera import NavPose

MAX_GAP_S = 0.1
"""A state or PTU reading farther than this from an image's time does not describe that image."""
HISTORY_S = 10.0
"""How far back both histories reach at the Data Interface's 25 Hz: an image that waited in a
busy node's queue still finds the state of its exposure."""
_SIZE = round(HISTORY_S * 25)


class NavHistory:
    """The last navigation solutions; the one nearest an image's time."""

    def __init__(self, size: int = _SIZE, max_gap: float = MAX_GAP_S) -> None:
        """Keep ``size`` states; one farther than ``max_gap`` s from a time does not describe it."""
        self._states: deque[tuple[float, NavPose]] = deque(maxlen=size)
        self.max_gap = max_gap

    def add(self, time: float, nav: NavPose) -> None:
        """Remember a state (non-finite times are dropped)."""
        if math.isfinite(time):
            self._states.append((time, nav))

    def at(self, time: float) -> NavPose | None:
        """The state nearest ``time``; None when none lies within ``max_gap`` of it."""
        if not self._states or not math.isfinite(time):
            return None
        t, nav = min(self._states, key=lambda s: abs(s[0] - time))
        return nav if abs(t - time) <= self.max_gap else None


class PtuHistory:
    """The last PTU read-outs; (pan, tilt) at an image's time, linearly interpolated."""

    def __init__(self, size: int = _SIZE, max_gap: float = MAX_GAP_S) -> None:
        self._samples: deque[tuple[float, float, float]] = deque(maxlen=size)
        self.max_gap = max_gap

    def add(self, time: float, pan: float, tilt: float) -> None:
        """Remember a reading (out-of-order and non-finite ones are dropped)."""
        if not all(math.isfinite(v) for v in (time, pan, tilt)):
            return
        if self._samples and time <= self._samples[-1][0]:
            return
        self._samples.append((time, pan, tilt))

    def at(self, time: float) -> tuple[float, float] | None:
        """(pan, tilt) at ``time``; None when no reading lies within ``max_gap`` of it."""
        samples = self._samples
        before = next((s for s in reversed(samples) if s[0] <= time), None)
        after = next((s for s in samples if s[0] >= time), None)
        if before is not None and after is not None and after[0] - before[0] <= 2 * self.max_gap:
            if after[0] == before[0]:
                return before[1], before[2]
            w = (time - before[0]) / (after[0] - before[0])
            return (
                before[1] + w * (after[1] - before[1]),
                before[2] + w * (after[2] - before[2]),
            )
        near = [s for s in (before, after) if s is not None and abs(s[0] - time) <= self.max_gap]
        if not near:
            return None
        best = min(near, key=lambda s: abs(s[0] - time))
        return best[1], best[2]
