"""The HCSM interpreter: Algorithm 2 of the chapter over compiled transition tables.

ExecuteStateMachine, MakeTransitions and ExecuteActions are methods of :class:`Interpreter`.

One call of :meth:`Interpreter.execute` is one macro step: a pulse event is queued, then the
external events present at the start of the call are taken one at a time, each followed by micro
steps over the internal queue until it is empty (synchrony hypothesis: events posted during the
step wait for the next one). The memory bank is locked for the whole step. Micro steps per macro
step are bounded; hitting the bound ends the step with ``StepStatus.LIVELOCK``.
"""

from __future__ import annotations

import enum
import logging
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

from hdrc3_hcsm.errors import BindingError
from hdrc3_hcsm.event import EventOrigin, PostStatus, WireEvent
from hdrc3_hcsm.memory import ActionFlags, MemoryBank
from hdrc3_hcsm.model import CACHE, And, CondRef, Guard, Not
from hdrc3_hcsm.tables import (
    EXIT_INDEX,
    PULSE_INDEX,
    CompiledModel,
    OpCode,
    TransitionSpec,
)
from hdrc3_hcsm.trace import FiredTransition, TraceRecord, TraceSink

_log = logging.getLogger(__name__)

Condition = Callable[[], bool]
_GuardFn = Callable[[], bool]
# Queue entries: (event index, data or None, exit target (machine, state) or None, origin).
_QueuedEvent = tuple[int, bytes | None, "tuple[_Machine, int] | None", EventOrigin]


class StepStatus(enum.Enum):
    """Outcome of one macro step."""

    OK = "ok"
    LIVELOCK = "livelock"
    FINISHED = "finished"


class FaultKind(enum.Enum):
    """What went wrong inside a step without stopping it."""

    ACTION_FAILED = "action_failed"
    GUARD_FAILED = "guard_failed"


@dataclass(frozen=True)
class Fault:
    """A transition whose guard raised or whose actions failed; the machine kept its state."""

    kind: FaultKind
    tid: str
    machine: str
    message: str

    def __str__(self) -> str:
        return f"{self.kind.value} {self.tid} in {self.machine}: {self.message}"


@dataclass(frozen=True)
class StepResult:
    """Summary of one macro step."""

    status: StepStatus
    micro_steps: int
    transitions: int
    external_events: int
    faults: tuple[Fault, ...]
    unconsumed: tuple[str, ...] = ()
    """External events, in order, that made no transition in any machine (no transition on
    them from an active state, every guard false, or the selected one's actions failed)."""


@dataclass(frozen=True)
class InterpreterConfig:
    """Bounds of one interpreter."""

    max_micro_steps: int = 1000
    external_queue_size: int = 256
    outbox_size: int = 256


@dataclass
class InterpreterStats:
    """Counters since creation."""

    macro_steps: int = 0
    micro_steps: int = 0
    transitions: int = 0
    unknown_events: int = 0
    rejected_events: int = 0
    livelocks: int = 0
    faults: int = 0
    by_status: dict[PostStatus, int] = field(default_factory=dict)


class _Bound:
    """A transition with its guard bound to condition callables."""

    __slots__ = ("actions", "guard", "spec", "target")

    def __init__(self, spec: TransitionSpec, guard: _GuardFn | None) -> None:
        self.spec = spec
        self.target = spec.target
        self.guard = guard
        self.actions = spec.actions


class _Machine:
    """One instance of an automaton in the instance tree."""

    __slots__ = (
        "active",
        "down",
        "exits",
        "init",
        "interest",
        "name",
        "parent",
        "path",
        "regions",
        "state",
        "states",
        "table",
    )

    def __init__(self, name: str, path: str, parent: _Machine | None) -> None:
        self.name = name
        self.path = path
        self.parent = parent
        self.state = 0
        self.init = 0
        self.states: tuple[str, ...] = ()
        self.exits: tuple[bool, ...] = ()
        self.interest: frozenset[int] = frozenset()
        self.table: tuple[dict[int, tuple[_Bound, ...]], ...] = ()
        self.regions: dict[int, list[_Machine]] = {}
        self.active: list[_Machine] | None = None
        # Per state: events the nested machines of that state can react to.
        self.down: tuple[frozenset[int], ...] = ()

    def reset(self) -> None:
        """Enter the init state (a fresh start of this instance)."""
        self.state = self.init
        self.active = self.regions.get(self.init)
        if self.active is not None:
            for child in self.active:
                child.reset()


def _bind_guard(guard: Guard, conditions: Mapping[str, Condition]) -> _GuardFn:
    if isinstance(guard, CondRef):
        return conditions[guard.name]
    if isinstance(guard, Not):
        inner = _bind_guard(guard.operand, conditions)
        return lambda: not inner()
    parts = tuple(_bind_guard(g, conditions) for g in guard.operands)
    # Two operands are by far the most common; a plain closure avoids a generator per call.
    if len(parts) == 2:
        first, second = parts
        if isinstance(guard, And):
            return lambda: first() and second()
        return lambda: first() or second()
    if isinstance(guard, And):
        return lambda: all(p() for p in parts)
    return lambda: any(p() for p in parts)


class Interpreter:
    """Runs one compiled model on one computer (Algorithm 2)."""

    def __init__(
        self,
        model: CompiledModel,
        conditions: Mapping[str, Condition],
        *,
        memory: MemoryBank | None = None,
        flags: ActionFlags | None = None,
        config: InterpreterConfig | None = None,
        trace: TraceSink | None = None,
    ) -> None:
        self.config = config or InterpreterConfig()
        self.stats = InterpreterStats()
        self.memory = memory or MemoryBank(model.slots)
        self.flags = flags or ActionFlags(model.flags)
        self._trace = trace
        self._conditions = dict(conditions)
        self._external: deque[_QueuedEvent] = deque()
        self._internal: deque[_QueuedEvent] = deque()
        self._outbox: list[WireEvent] = []
        self._fired: list[tuple[_Machine, TransitionSpec, int]] = []
        self._faults: list[Fault] = []
        self._finished = False
        self._install(model)
        self.restart()

    # --- model ---------------------------------------------------------------------------
    def _install(self, model: CompiledModel) -> None:
        missing = sorted(model.conditions - set(self._conditions))
        if missing:
            raise BindingError("conditions without implementation: " + ", ".join(missing))
        for slot in model.slots:
            self.memory.size(slot)  # raises BindingError for a bank that lacks the slot
        absent = sorted(model.flags - self.flags.names())
        if absent:
            raise BindingError("action flags missing from the flag set: " + ", ".join(absent))
        self.model = model
        self.computer = model.computer
        self._event_index = model.events.index
        self._event_names = model.events.names
        self._root = self._instantiate(model.root, None, "")

    def _instantiate(
        self, names: tuple[str, ...], parent: _Machine | None, prefix: str
    ) -> list[_Machine]:
        machines: list[_Machine] = []
        for i, name in enumerate(names):
            table = self.model.automata[name]
            suffix = f"[{i + 1}]" if names.count(name) > 1 else ""
            m = _Machine(name, f"{prefix}{name}{suffix}", parent)
            m.states, m.init, m.exits, m.interest = (
                table.states,
                table.init,
                table.exits,
                table.interest,
            )
            m.table = tuple(
                {
                    ev: tuple(
                        _Bound(
                            s, None if s.guard is None else _bind_guard(s.guard, self._conditions)
                        )
                        for s in specs
                    )
                    for ev, specs in row.items()
                }
                for row in table.table
            )
            m.regions = {
                state: self._instantiate(children, m, f"{m.path}/{table.states[state]}/")
                for state, children in table.regions.items()
            }
            m.down = tuple(
                frozenset().union(*(c.interest for c in m.regions.get(i, ())))
                for i in range(len(m.states))
            )
            machines.append(m)
        return machines

    def restart(self) -> None:
        """Put every machine back into its init state and drop queued events."""
        for m in self._root:
            m.reset()
        self._external.clear()
        self._outbox.clear()
        self._finished = False

    def reload(
        self,
        model: CompiledModel,
        *,
        memory: MemoryBank | None = None,
        flags: ActionFlags | None = None,
    ) -> None:
        """Swap in a new model between steps, keeping states that still exist by path and name.

        Queued external events are carried over by name (ones the new model lacks are counted
        as unknown). Pass a new memory bank or flag set when the model adds slots or flags.
        """
        old = self.configuration()
        pending = [(self._event_names[index], data) for index, data, _, _ in self._external]
        previous = (self.memory, self.flags)
        self.memory, self.flags = memory or self.memory, flags or self.flags
        try:
            self._install(model)
        except BindingError:
            self.memory, self.flags = previous
            raise
        for m in self._root:
            m.reset()
        self._finished = False
        self._restore(self._root, dict(entry.rsplit(":", 1) for entry in old))
        self._external.clear()
        for name, data in pending:
            self.post_external(name, data)

    def _restore(self, machines: list[_Machine], kept: dict[str, str]) -> None:
        for m in machines:
            name = kept.get(m.path)
            if name in m.states:
                m.state = m.states.index(name)
                m.active = m.regions.get(m.state)
                if m.active is not None:
                    for child in m.active:
                        child.reset()
            if m.active is not None:
                self._restore(m.active, kept)

    # --- queues --------------------------------------------------------------------------
    def post_external(self, name: str, data: bytes | None = None) -> PostStatus:
        """Queue an external event by name; unknown events are logged and counted, not fatal."""
        index = self._event_index.get(name)
        if index is None or index in (PULSE_INDEX, EXIT_INDEX):
            return self._reject(PostStatus.UNKNOWN_EVENT, name)
        if len(self._external) >= self.config.external_queue_size:
            return self._reject(PostStatus.QUEUE_FULL, name)
        if data and not self.memory.fits(CACHE, data):
            return self._reject(PostStatus.TOO_LARGE, name)
        self._external.append((index, data or None, None, EventOrigin.EXTERNAL))
        return PostStatus.ACCEPTED

    def post_wire(self, event: WireEvent) -> PostStatus:
        """Queue an event received from another computer after checking target, name and id."""
        if event.target != self.computer:
            return self._reject(PostStatus.WRONG_TARGET, event.name)
        index = self._event_index.get(event.name)
        if index is None:
            return self._reject(PostStatus.UNKNOWN_EVENT, event.name)
        if self.model.events.ids[index] != event.event_id:
            return self._reject(PostStatus.ID_MISMATCH, event.name)
        return self.post_external(event.name, event.data)

    def _reject(self, status: PostStatus, name: str) -> PostStatus:
        if status is PostStatus.UNKNOWN_EVENT:
            self.stats.unknown_events += 1
        self.stats.rejected_events += 1
        self.stats.by_status[status] = self.stats.by_status.get(status, 0) + 1
        _log.warning("%s: external event %r rejected: %s", self.computer, name, status.value)
        return status

    def take_outbox(self) -> list[WireEvent]:
        """Events SENT to other computers since the last call (the external communication queue)."""
        out, self._outbox = self._outbox, []
        return out

    def pending_external(self) -> int:
        """Count the external events waiting for the next macro step."""
        return len(self._external)

    # --- Algorithm 2 ----------------------------------------------------------------------
    def execute(self, now: float) -> StepResult:
        """ExecuteStateMachine: one macro step at time ``now`` (seconds)."""
        stats = self.stats
        stats.macro_steps += 1
        self._faults = []
        internal = self._internal
        internal.clear()
        internal.append((PULSE_INDEX, None, None, EventOrigin.PULSE))
        external = self._external
        pending = len(external)
        taken = pending
        limit = self.config.max_micro_steps
        micro = 0
        transitions = stats.transitions
        status = StepStatus.OK
        tracing = self._trace is not None
        unconsumed: list[str] = []
        with self.memory.lock:
            while True:
                if pending:
                    pending -= 1
                    internal.append(external.popleft())
                while internal:
                    if micro >= limit:
                        status = StepStatus.LIVELOCK
                        break
                    index, data, exit_target, origin = internal.popleft()
                    micro += 1
                    faults_before = len(self._faults)
                    if data is not None:
                        self.memory.commit(data, None)
                    if exit_target is None:
                        self._make_transitions(self._root, index)
                        if origin is EventOrigin.EXTERNAL and not self._fired:
                            unconsumed.append(self._event_names[index])
                    else:
                        self._deliver_exit(exit_target)
                    if tracing:
                        self._record(now, micro, index, origin, faults_before)
                    else:
                        self._fired.clear()
                if status is StepStatus.LIVELOCK or not pending:
                    break
        if status is StepStatus.LIVELOCK:
            internal.clear()
            stats.livelocks += 1
            _log.error("%s: livelock, more than %d micro steps", self.computer, limit)
        elif self._finished:
            status = StepStatus.FINISHED
        stats.micro_steps += micro
        stats.faults += len(self._faults)
        return StepResult(
            status,
            micro,
            stats.transitions - transitions,
            taken - pending,
            tuple(self._faults),
            tuple(unconsumed),
        )

    def _make_transitions(self, machines: list[_Machine], event: int) -> None:
        """MakeTransitions: outer levels first; a machine that does not react passes down."""
        for m in machines:
            if event not in m.interest:
                continue
            candidates = m.table[m.state].get(event)
            if candidates is not None and self._try(m, candidates):
                continue
            active = m.active
            if active is not None and event in m.down[m.state]:
                self._make_transitions(active, event)

    def _deliver_exit(self, target: tuple[_Machine, int]) -> None:
        machine, state = target
        # Since the exit event was queued the parent may have left the superstate, or an
        # ancestor may have aborted the parent itself; then the event is stale.
        if machine.state != state or not self._is_active(machine):
            return
        candidates = machine.table[state].get(EXIT_INDEX)
        if candidates is not None:
            self._try(machine, candidates)

    def _is_active(self, m: _Machine) -> bool:
        """Tell whether ``m`` is part of the current configuration."""
        while m.parent is not None:
            parent = m.parent
            if parent.active is None or not any(child is m for child in parent.active):
                return False
            m = parent
        return any(root is m for root in self._root)

    def _try(self, m: _Machine, candidates: tuple[_Bound, ...]) -> bool:
        """Take the first transition whose guard holds; True if one was selected."""
        for bound in candidates:
            guard = bound.guard
            if guard is not None:
                try:
                    if not guard():
                        continue
                except Exception as exc:  # condition code is user code: report, treat as false
                    self._fault(FaultKind.GUARD_FAILED, bound.spec, m, repr(exc))
                    continue
            if bound.actions and not self._execute_actions(m, bound.spec):
                return True
            self._enter(m, bound)
            return True
        return False

    def _execute_actions(self, m: _Machine, spec: TransitionSpec) -> bool:
        """ExecuteActions, all or nothing: effects are staged and committed only if all succeed."""
        memory = self.memory
        cache = memory.cache
        writes: dict[str, bytes] = {}
        flags: list[str] = []
        sends: list[tuple[int, bytes | None, str | None]] = []
        remote = 0
        for action in spec.actions:
            op = action.op
            if op is OpCode.SET:
                flags.append(action.name)
            elif op is OpCode.GET:
                cache = writes[action.name] if action.name in writes else memory.read(action.name)
            elif op is OpCode.PUT:
                if not memory.fits(action.name, cache):
                    size = memory.size(action.name)
                    return self._fault(
                        FaultKind.ACTION_FAILED,
                        spec,
                        m,
                        f"{action.text}: {len(cache)} bytes exceed slot size {size}",
                    )
                writes[action.name] = cache
            else:
                slot = action.data_slot
                data = None
                if slot is not None:
                    data = cache if slot == CACHE else writes.get(slot, memory.read(slot))
                if action.remote is not None:
                    remote += 1
                    if len(self._outbox) + remote > self.config.outbox_size:
                        return self._fault(
                            FaultKind.ACTION_FAILED, spec, m, f"{action.text}: outbox full"
                        )
                sends.append((action.event, data, action.remote))
        memory.commit(cache, writes)
        for flag in flags:
            self.flags.raise_flag(flag)
        for event, data, target in sends:
            if target is None:
                self._internal.append((event, data, None, EventOrigin.INTERNAL))
            else:
                self._outbox.append(
                    WireEvent(
                        self.model.events.ids[event],
                        self._event_names[event],
                        data or b"",
                        self.computer,
                        target,
                    )
                )
        return True

    def _enter(self, m: _Machine, bound: _Bound) -> None:
        """Make the transition: leaving a superstate aborts its children, entering restarts them."""
        source = m.state
        target = bound.target
        m.state = target
        active = m.regions.get(target)
        if active is not None:
            for child in active:
                child.reset()
        m.active = active
        self.stats.transitions += 1
        self._fired.append((m, bound.spec, source))
        if m.exits[target]:
            self._child_exited(m)

    def _child_exited(self, m: _Machine) -> None:
        parent = m.parent
        siblings = self._root if parent is None else parent.active
        if siblings is None or not all(s.exits[s.state] for s in siblings):
            return
        if parent is None:
            self._finished = True
        else:
            self._internal.append((EXIT_INDEX, None, (parent, parent.state), EventOrigin.EXIT))

    def _fault(self, kind: FaultKind, spec: TransitionSpec, m: _Machine, message: str) -> bool:
        fault = Fault(kind, spec.tid, m.path, message)
        self._faults.append(fault)
        _log.error("%s: %s", self.computer, fault)
        return False

    # --- inspection ----------------------------------------------------------------------
    def configuration(self) -> tuple[str, ...]:
        """Active states as ``path:state`` entries, outer machines first, regions in order."""
        out: list[str] = []

        def walk(machines: list[_Machine]) -> None:
            for m in machines:
                out.append(f"{m.path}:{m.states[m.state]}")
                if m.active is not None:
                    walk(m.active)

        walk(self._root)
        return tuple(out)

    def _record(
        self, now: float, micro: int, index: int, origin: EventOrigin, first_fault: int
    ) -> None:
        assert self._trace is not None
        fired = tuple(
            FiredTransition(
                spec.tid,
                m.path,
                m.states[source],
                m.states[spec.target],
                tuple(a.text for a in spec.actions),
            )
            for m, spec, source in self._fired
        )
        self._fired.clear()
        self._trace.record(
            TraceRecord(
                computer=self.computer,
                macro_step=self.stats.macro_steps,
                micro_step=micro,
                time=now,
                event=self._event_names[index],
                origin=origin.value,
                transitions=fired,
                faults=tuple(str(f) for f in self._faults[first_fault:]),
                configuration=self.configuration(),
            )
        )
