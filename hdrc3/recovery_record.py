"""What a recording says about a load lost or not lifted, and its recovery (section 9.3).

Reads an MCAP of a run such as ``hdrc3 tst run examples/tst/delivery_box_drop.tst --launch
--fault uav0:hook:release@fly-to#2+10 --out DIR`` (:func:`read_lost_load`): when the load left the
hook in the simulator's ground truth (``/world_sim/objects``), when the agent's carrying sensor
stopped reporting it, the execution monitor's violation, the TST manager's recovery steps with
the new plan, the flight control's modes in between, and where the load finally lies. Or of
``hdrc3 tst run examples/tst/delivery_carrier_overweight.tst --launch --out DIR``
(:func:`read_failed_lift`): when the winch first stalled under the load, the violation, the
recovery and where every object finally lies. Used by the integration tests and
``bench/box_drop_recovery.py``; the ground truth here only measures, it decides nothing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rclpy.serialization import deserialize_message

from hdrc3.mcap_recording import RecordingReader
from hdrc3.message_types import message_class


def stamp_ms(stamp: Any) -> int:
    """A ``builtin_interfaces/Time`` in milliseconds."""
    return int(stamp.sec) * 1000 + int(stamp.nanosec) // 1_000_000


@dataclass(frozen=True)
class LostLoadRecord:
    """One lost load's detection and recovery as recorded (sim times in ms)."""

    released_ms: int | None
    """Ground truth: the first objects message with the load no longer held."""
    sensor_ms: int | None
    """The first carrying-sensor reading without the load after it was held."""
    violation: Any | None
    """The first ``MonitorViolation`` (KIND_VIOLATION) naming the load in its arguments."""
    recovery: tuple[Any, ...]
    """The ``RecoveryEvent``s of that violation, in order."""
    modes: tuple[int, ...]
    """PFC modes from the violation to the new plan (``PfcState.MODE_*``)."""
    final: Any | None
    """The load's ``WorldObject`` in the last objects message."""

    @property
    def detection_ms(self) -> int | None:
        """Violation stamp minus the ground-truth release."""
        if self.violation is None or self.released_ms is None:
            return None
        return stamp_ms(self.violation.header.stamp) - self.released_ms

    @property
    def reaction_ms(self) -> int | None:
        """The manager's first recovery step minus the ground-truth release."""
        if not self.recovery or self.released_ms is None:
            return None
        return stamp_ms(self.recovery[0].header.stamp) - self.released_ms


def _messages(path: Path, topics: tuple[str, ...]) -> dict[str, list[Any]]:
    recording = RecordingReader.open(path)
    types = {t: s for t, s in recording.topics().items() if t in topics}
    out: dict[str, list[Any]] = {topic: [] for topic in topics}
    for m in recording.messages(list(types)):
        out[m.topic].append(deserialize_message(m.data, message_class(types[m.topic])))
    return out


def read_lost_load(path: Path, agent: str, load: str) -> LostLoadRecord:
    """The record of ``load`` lost by ``agent`` in the recording at ``path``."""
    objects, carrying, violations, events, pfc = (
        "/world_sim/objects",
        f"/{agent}/sensors/carrying",
        f"/{agent}/monitor_violations",
        f"/{agent}/recovery_events",
        f"/{agent}/pfc/state",
    )
    got = _messages(path, (objects, carrying, violations, events, pfc))
    released = None
    held = False
    for msg in got[objects]:
        (obj,) = [o for o in msg.objects if o.id == load] or [None]
        if obj is None:
            continue
        if obj.held_by == agent:
            held = True
        elif held:
            released = stamp_ms(msg.header.stamp)
            break
    sensor = None
    held = False
    for reading in got[carrying]:
        if reading.object_id == load:
            held = True
        elif held:
            sensor = stamp_ms(reading.header.stamp)
            break
    violation = next(
        (
            v
            for v in got[violations]
            if v.kind == v.KIND_VIOLATION and load in list(v.argument_values)
        ),
        None,
    )
    recovery: tuple[Any, ...] = ()
    modes: tuple[int, ...] = ()
    if violation is not None:
        recovery = tuple(e for e in got[events] if e.monitor_id == violation.monitor_id)
        start = stamp_ms(violation.header.stamp)
        end = stamp_ms(recovery[-1].header.stamp) if recovery else start
        modes = tuple(p.mode for p in got[pfc] if start <= stamp_ms(p.header.stamp) <= end)
    final = None
    if got[objects]:
        final = next((o for o in got[objects][-1].objects if o.id == load), None)
    return LostLoadRecord(released, sensor, violation, recovery, modes, final)


@dataclass(frozen=True)
class FailedLiftRecord:
    """One load too heavy to lift: its detection and recovery as recorded (sim times in ms)."""

    stalled_ms: int | None
    """The first carrying-sensor reading of the stall the violation followed: holding the load
    with the winch stalled, and stalled in every reading since (up to the violation)."""
    violation: Any | None
    """The first ``MonitorViolation`` (KIND_VIOLATION) naming the load in its arguments."""
    recovery: tuple[Any, ...]
    """The ``RecoveryEvent``s of that violation, in order."""
    final: dict[str, Any]
    """Every object's ``WorldObject`` in the last objects message, by id."""

    @property
    def detection_ms(self) -> int | None:
        """Violation stamp minus the first stalled reading."""
        if self.violation is None or self.stalled_ms is None:
            return None
        return stamp_ms(self.violation.header.stamp) - self.stalled_ms


def read_failed_lift(path: Path, agent: str, load: str) -> FailedLiftRecord:
    """The record of ``load`` that ``agent``'s hook could not lift, in the recording at ``path``."""
    objects, carrying, violations, events = (
        "/world_sim/objects",
        f"/{agent}/sensors/carrying",
        f"/{agent}/monitor_violations",
        f"/{agent}/recovery_events",
    )
    got = _messages(path, (objects, carrying, violations, events))
    violation = next(
        (
            v
            for v in got[violations]
            if v.kind == v.KIND_VIOLATION and load in list(v.argument_values)
        ),
        None,
    )
    until = math.inf if violation is None else stamp_ms(violation.header.stamp)
    stalled: int | None = None
    for reading in got[carrying]:
        at = stamp_ms(reading.header.stamp)
        if at > until:
            break
        if reading.object_id != load or reading.winch != reading.WINCH_STALLED:
            stalled = None  # the drum turned again: a moment of lift-off, not a failed lift
        elif stalled is None:
            stalled = at
    recovery: tuple[Any, ...] = ()
    if violation is not None:
        recovery = tuple(e for e in got[events] if e.monitor_id == violation.monitor_id)
    final = {o.id: o for o in got[objects][-1].objects} if got[objects] else {}
    return FailedLiftRecord(stalled, violation, recovery, final)
