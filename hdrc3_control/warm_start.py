"""The PFC's warm-start record: what a restarted control kernel cannot measure again in the air.

The navigation filter references the barometer on the skids before take-off (the ground reference
of :class:`~hdrc3_control.state_estimator.StateEstimator`): from then on the barometer, corrected
by its estimated bias, carries the height. A control kernel restarted in flight has no ground to
reference on; initialised on a GPS fix alone, its height is off by the GPS's vertical error (3 m
sigma, correlated over minutes: measured 5-7 m after a restart). Autopilots keep such state in
memory that survives a software reset (ArduPilot's watchdog "persistent data" keeps the home
position across an in-flight reset); here it is a small JSON file the node rewrites every second
of sim time while the solution is good, and reads when it starts.

Written atomically (temporary file + rename). A missing, unreadable, malformed or stale record
(older than ``max_age`` of sim time, or from a later time: the simulation started over) is not
used; the reason is given, the kernel then initialises as on a cold start.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from dataclasses import asdict, dataclass
from pathlib import Path

FORMAT = 1


@dataclass(frozen=True, slots=True)
class WarmStart:
    """The filter's barometer reference at one instant of sim time."""

    time: float
    """Sim time of the record, s."""
    baro_bias: float
    """Estimated barometer bias (barometric height minus height), m."""
    baro_bias_sigma: float
    """Its standard deviation, m."""

    def valid(self) -> bool:
        """All fields finite, the sigma positive."""
        values = (self.time, self.baro_bias, self.baro_bias_sigma)
        return all(math.isfinite(v) for v in values) and self.baro_bias_sigma > 0.0

    def usable_at(self, now: float, max_age: float) -> str | None:
        """Why the record cannot seed a filter at sim time ``now`` (None: it can)."""
        age = now - self.time
        if age < 0.0:
            return f"record of t = {self.time:.2f} s is later than now (t = {now:.2f} s)"
        if age > max_age:
            return f"record is {age:.1f} s old (limit {max_age:g} s)"
        return None


@dataclass(frozen=True, slots=True)
class WarmStartLoad:
    """Outcome of :func:`read_warm_start`: the record, or why there is none."""

    record: WarmStart | None
    reason: str = ""


def write_warm_start(path: Path, record: WarmStart) -> None:
    """Replace the record at ``path`` atomically (OSError if impossible)."""
    data = json.dumps({"format": FORMAT, **asdict(record)}).encode()
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as out:
            out.write(data)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def read_warm_start(path: Path) -> WarmStartLoad:
    """The record at ``path``; never raises on a missing or bad file."""
    try:
        raw = json.loads(path.read_bytes())
    except FileNotFoundError:
        return WarmStartLoad(None, f"no warm-start record at {path}")
    except (OSError, ValueError) as exc:
        return WarmStartLoad(None, f"cannot read {path}: {exc}")
    if not isinstance(raw, dict) or raw.get("format") != FORMAT:
        return WarmStartLoad(None, f"{path} is not a warm-start record of format {FORMAT}")
    try:
        record = WarmStart(
            float(raw["time"]), float(raw["baro_bias"]), float(raw["baro_bias_sigma"])
        )
    except (KeyError, TypeError, ValueError) as exc:
        return WarmStartLoad(None, f"{path}: bad field {exc}")
    if not record.valid():
        return WarmStartLoad(None, f"{path}: non-finite or non-positive values")
    return WarmStartLoad(record)
