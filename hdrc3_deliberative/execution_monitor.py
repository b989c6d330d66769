"""Execution monitor core (HDRC3 chapter 9.3): global and operator-specific monitor formulas.

As a plan executes, :class:`ExecutionMonitor` synthesises states from DyKnow streams and
execution flags (:mod:`monitor_states`) and progresses its active formulas through them
(§9.3.3, :mod:`hdrc3_dyknow.progression`):

* **global** formulas are activated by :meth:`ExecutionMonitor.start` and run until decided;
* **operator-specific** formulas are activated when a step of their operator starts (an
  execution flag with ``executing`` true), with the operator's parameters bound to the step's
  agent and arguments (Example 9.2); ``EXEC`` is the step's own flag (Example 9.3). They are
  retired after the first state at or after the step's end unless declared ``persistent``
  (Example 9.4 waits for the put-down after the pick-up has ended).

Fluents are matched to streams *by meaning* (semantic matching, §8.5);
``executing-<op>(...)`` fluents are execution flags. A formula over a fluent that is neither
known nor streamed is refused with the fluent named: :meth:`ExecutionMonitor.start` refuses to
start at all for a global formula or an operator formula naming an unknown feature, and an
activation whose ground fluents have no stream is a ``REFUSED`` event — never a monitor that
silently never fires. A state lacking a fluent (stale or dropped stream) is not progressed into
the formulas that read it; the stale-data alarm says why.

Everything the monitor decides is a :class:`MonitorEvent` returned by :meth:`advance` and
:meth:`on_flag`; misuse raises :class:`~hdrc3_base.errors.Hdrc3Error`.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field

from hdrc3_base.errors import DataError
from hdrc3_deliberative.monitor_spec import MonitorDecl, MonitorSpec
from hdrc3_deliberative.monitor_states import (
    FLAG_PREFIX,
    StaleChange,
    StateSynthesizer,
    Step,
    SynthesizedState,
)
from hdrc3_dyknow.coordinator import needed_fluents, nested_candidates, nested_fluents
from hdrc3_dyknow.formula import (
    Always,
    And,
    Arithmetic,
    Atom,
    Comparison,
    Eventually,
    FluentTerm,
    Formula,
    Implies,
    Negative,
    Not,
    Or,
    Quantified,
    Term,
    Until,
)
from hdrc3_dyknow.grounding import EXEC, GroundingError, Scope, compile_formula, quantified_sorts
from hdrc3_dyknow.interpretation import State, atom_key
from hdrc3_dyknow.knowledge_process import KnowledgeProcessHost
from hdrc3_dyknow.progression import ProgressionEngine, Verdict
from hdrc3_dyknow.residual import NodeTable
from hdrc3_dyknow.semantic_matching import MatchStatus, SemanticMatcher


class EventKind(enum.Enum):
    """What happened to a monitor formula."""

    ACTIVATED = "activated"
    SATISFIED = "satisfied"
    VIOLATED = "violated"
    RETIRED = "retired"
    REFUSED = "refused"
    STALE_DATA = "stale_data"
    DATA_RESUMED = "data_resumed"


class StartStatus(enum.Enum):
    """Outcome of :meth:`ExecutionMonitor.start`."""

    STARTED = "started"
    UNKNOWN_SYMBOL = "unknown_symbol"
    ALREADY_STARTED = "already_started"


@dataclass(frozen=True, slots=True)
class StartResult:
    """Whether monitoring started; the reason names the offending formula and symbol."""

    status: StartStatus
    reason: str = ""
    monitors: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class FlagUpdate:
    """An execution flag (``hdrc3_interfaces/msg/ExecutionFlag``) as the core sees it."""

    time_ms: int
    agent: str
    node_id: str
    action: str
    executing: bool
    arguments: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True, slots=True)
class MonitorEvent:
    """Something the execution monitor decided at ``time_ms`` (a state's valid time).

    ``monitor_id`` is the declaration's name, with ``@node_id`` for operator formulas;
    ``formula`` the formula as activated (residual for RETIRED); ``reason`` readable detail.
    """

    kind: EventKind
    time_ms: int
    monitor_id: str = ""
    formula: str = ""
    decl: MonitorDecl | None = None
    node_id: str = ""
    arguments: tuple[tuple[str, str], ...] = ()
    reason: str = ""
    activated_ms: int = 0
    states: int = 0


@dataclass(slots=True)
class _Active:
    ident: str
    decl: MonitorDecl
    text: str
    engine: ProgressionEngine
    engine_id: int
    keys: frozenset[str]
    activated_ms: int
    node_id: str = ""
    arguments: tuple[tuple[str, str], ...] = ()
    ends_ms: int | None = None
    states: int = 0
    skipped: int = 0

    def event(self, kind: EventKind, time_ms: int, **extra: str) -> MonitorEvent:
        return MonitorEvent(
            kind,
            time_ms,
            self.ident,
            extra.get("formula", self.text),
            self.decl,
            self.node_id,
            self.arguments,
            extra.get("reason", ""),
            self.activated_ms,
            self.states,
        )


@dataclass(frozen=True, slots=True)
class _Plan:
    scope: Scope
    streams: dict[str, tuple[str, ...]]
    flags: dict[str, tuple[str, tuple[str, ...]]]


@dataclass
class ExecutionMonitor:
    """The monitor set of one agent: active formulas over synthesised states.

    Args:
        spec: The monitor specification.
        host: DyKnow host whose streams feed the states.
        matcher: Semantic matching of fluents to streams (and sorts to objects).

    """

    spec: MonitorSpec
    host: KnowledgeProcessHost
    matcher: SemanticMatcher
    synthesizer: StateSynthesizer = field(init=False)
    _active: dict[str, _Active] = field(default_factory=dict, init=False)
    _started: bool = field(default=False, init=False)
    _pending: list[MonitorEvent] = field(default_factory=list, init=False)

    def __post_init__(self) -> None:
        settings = self.spec.settings
        self.synthesizer = StateSynthesizer(
            self.host, settings.period_ms, settings.max_delay_ms, settings.stale_ms
        )

    @property
    def active(self) -> list[str]:
        """Ids of the active formulas, sorted."""
        return sorted(self._active)

    def check(self) -> StartResult:
        """Validate every formula without activating any (what :meth:`start` would refuse)."""
        problem = self._validate()
        return problem if isinstance(problem, StartResult) else StartResult(StartStatus.STARTED)

    def start(self, now_ms: int) -> StartResult:
        """Check every formula and activate the global ones; states begin at ``now_ms``.

        Their ACTIVATED events come with the next :meth:`advance`. Nothing is activated if any
        global formula reads an unknown fluent or any formula names an unknown feature or sort.
        """
        if self._started:
            return StartResult(StartStatus.ALREADY_STARTED, "the monitor is already running")
        plans = self._validate()
        if isinstance(plans, StartResult):
            return plans
        self._started = True
        self.synthesizer.start(now_ms)
        for decl, plan in plans:
            self._pending.append(self._activate(decl, plan, decl.name, now_ms))
        return StartResult(
            StartStatus.STARTED, f"{len(plans)} global formulas active", tuple(self.active)
        )

    def _validate(self) -> list[tuple[MonitorDecl, _Plan]] | StartResult:
        if self.spec.generate:
            first = self.spec.generate[0]
            return StartResult(
                StartStatus.UNKNOWN_SYMBOL,
                f"{self.spec.source}:{first.line}:{first.column}: 'generate' needs the planning"
                " domain (monitor_generation.expand; the node's domain_file parameter)",
            )
        plans: list[tuple[MonitorDecl, _Plan]] = []
        for decl in self.spec.monitors:
            problem = self._unknown_feature(decl)
            if problem:
                return self._refuse(decl, problem)
            if decl.is_global:
                plan = self._plan(decl, {})
                if isinstance(plan, str):
                    return self._refuse(decl, plan)
                plans.append((decl, plan))
        return plans

    def on_flag(self, flag: FlagUpdate) -> list[MonitorEvent]:
        """Record an execution flag; a start activates the operator's formulas."""
        if not flag.executing:
            self.synthesizer.step_stopped(flag.node_id, flag.time_ms)
            for active in self._active.values():
                if active.node_id == flag.node_id and not active.decl.persistent:
                    active.ends_ms = flag.time_ms
            return []
        step = Step(flag.node_id, flag.action, flag.agent, flag.arguments, flag.time_ms)
        self.synthesizer.step_started(step)
        events: list[MonitorEvent] = []
        if not self._started:
            return events
        given = dict(flag.arguments)
        for decl in self.spec.for_operator(flag.action):
            ident = f"{decl.name}@{flag.node_id}"
            bindings = {decl.parameters[0]: flag.agent}
            unbound = []
            for name in decl.parameters[1:]:
                if name in given:
                    bindings[name] = given[name]
                else:
                    unbound.append(name)
            plan: _Plan | str
            if unbound:
                plan = (
                    f"step {flag.node_id} of {flag.action} gives no argument for parameter(s)"
                    f" {', '.join(unbound)} (it gave: {', '.join(sorted(given)) or 'none'})"
                )
            else:
                plan = self._plan(decl, bindings)
            if isinstance(plan, str):
                events.append(
                    MonitorEvent(
                        EventKind.REFUSED,
                        flag.time_ms,
                        ident,
                        decl.text,
                        decl,
                        flag.node_id,
                        flag.arguments,
                        plan,
                        flag.time_ms,
                    )
                )
                continue
            self._active.pop(ident, None)
            events.append(self._activate(decl, plan, ident, flag.time_ms, flag))
        return events

    def advance(self, now_ms: int) -> list[MonitorEvent]:
        """Synthesise the states complete at ``now_ms`` and progress the active formulas."""
        if not self._started:
            return []
        states, changes = self.synthesizer.advance(now_ms)
        events, self._pending = self._pending, []
        events.extend(self._stale_event(change) for change in changes)
        for state in states:
            events.extend(self._progress(state))
        return events

    def stop(self, now_ms: int) -> list[MonitorEvent]:
        """Retire every active formula (end of execution): RETIRED events with residuals."""
        events = [
            active.event(
                EventKind.RETIRED,
                now_ms,
                formula=str(active.engine.residual(active.engine_id)),
                reason="monitoring stopped",
            )
            for active in self._active.values()
        ]
        self.synthesizer.release(key for a in self._active.values() for key in a.keys)
        self._active.clear()
        return events

    # --- formulas ------------------------------------------------------------------------
    def _unknown_feature(self, decl: MonitorDecl) -> str:
        """Name an unknown sort or a fluent that is no ontology feature (before binding)."""
        for sort in sorted(quantified_sorts(decl.formula)):
            found = self.matcher.match_sort(sort)
            if found.status is not MatchStatus.MATCHED:
                return found.reason
        variables = set(decl.parameters) | set(_variables(decl.formula))
        objects = set(self.matcher.ontology.objects())
        for term in _fluents(decl.formula):
            if term.name == EXEC:
                if decl.is_global:
                    return "EXEC is only meaningful in an operator-specific formula"
                continue
            if term.name.startswith(FLAG_PREFIX):
                continue
            if not term.args and (term.name in variables or term.name in objects):
                continue
            if self.matcher.ontology.feature(term.name) is None:
                return (
                    f"unknown fluent {term.name!r}: no feature of the ontology and no"
                    f" execution flag ({FLAG_PREFIX}<operator>)"
                )
        return ""

    def _plan(self, decl: MonitorDecl, bindings: Mapping[str, str]) -> _Plan | str:
        """Ground ``decl`` and match each fluent it reads to streams; a reason on failure."""
        domains: dict[str, tuple[str, ...]] = {"Object": tuple(self.matcher.ontology.objects())}
        for sort in quantified_sorts(decl.formula):
            found = self.matcher.match_sort(sort)
            if found.status is not MatchStatus.MATCHED:
                return found.reason
            domains[sort] = found.objects
        exec_flag = None
        if decl.operator:
            args = tuple(bindings[p] for p in decl.parameters)
            exec_flag = atom_key(FLAG_PREFIX + decl.operator, args)
        scope = Scope(domains, dict(bindings), exec_flag)
        try:
            node = compile_formula(NodeTable(), decl.formula, scope)
        except GroundingError as exc:
            return str(exc)
        streams: dict[str, tuple[str, ...]] = {}
        flags: dict[str, tuple[str, tuple[str, ...]]] = {}
        for term in sorted(needed_fluents(node, scope.objects())[1], key=str):
            key = atom_key(term.feature, term.args)
            if term.feature.startswith(FLAG_PREFIX):
                flags[key] = (term.feature[len(FLAG_PREFIX) :], term.args)
                continue
            match = self.matcher.match(term)
            if not match.ok:
                return match.reason
            streams[key] = self._fused(match.labels)
        for nested in sorted(nested_fluents(node), key=str):
            # Which fluent it reads depends on the state: carry every one that has a stream.
            readable = 0
            for term in nested_candidates(nested, scope.objects()):
                match = self.matcher.match(term)
                if match.ok:
                    streams[atom_key(term.feature, term.args)] = self._fused(match.labels)
                    readable += 1
            if not readable:
                return f"no stream contains {nested} for any object as its nested argument"
        return _Plan(scope, streams, flags)

    def _fused(self, labels: tuple[str, ...]) -> tuple[str, ...]:
        """The matched streams of the best-matching feature or an equivalent class.

        One per ``sameAs`` name or per agent's ontology; a more specific feature
        (``GroundSpeed`` for ``speed``) is used only when no stream has the feature itself.
        """
        ontology, semantics = self.matcher.ontology, self.matcher.semantics

        def feature(label: str) -> str:
            annotation = semantics.annotation(label)
            found = None if annotation is None else ontology.feature(annotation.feature)
            return found or ""

        best = feature(labels[0])
        return tuple(
            label
            for label in labels
            if ontology.subsumes(best, feature(label)) and ontology.subsumes(feature(label), best)
        )

    def _activate(
        self,
        decl: MonitorDecl,
        plan: _Plan,
        ident: str,
        now_ms: int,
        flag: FlagUpdate | None = None,
    ) -> MonitorEvent:
        engine = ProgressionEngine()
        engine_id = engine.add(decl.formula, plan.scope)
        text = str(engine.residual(engine_id))
        self.synthesizer.need(plan.streams, now_ms)
        self.synthesizer.need_flags(plan.flags)
        active = _Active(
            ident,
            decl,
            text,
            engine,
            engine_id,
            frozenset(plan.streams) | frozenset(plan.flags),
            now_ms,
            flag.node_id if flag else "",
            flag.arguments if flag else (),
        )
        self._active[ident] = active
        return active.event(EventKind.ACTIVATED, now_ms)

    def _progress(self, state: SynthesizedState) -> Iterator[MonitorEvent]:
        view = State(state.time_ms, state.values)
        retired: list[str] = []
        for ident, active in self._active.items():
            if state.time_ms < active.activated_ms:
                continue
            if active.keys & state.missing:
                active.skipped += 1
            else:
                try:
                    decided = active.engine.update(view)
                except DataError as exc:  # a fluent of the wrong type: skip, say why
                    active.skipped += 1
                    yield active.event(EventKind.REFUSED, state.time_ms, reason=str(exc))
                    retired.append(ident)
                    continue
                active.states += 1
                if decided:
                    verdict = decided[0][1]
                    kind = EventKind.SATISFIED if verdict is Verdict.TRUE else EventKind.VIOLATED
                    yield active.event(kind, state.time_ms, reason=_why(active, view))
                    retired.append(ident)
                    continue
            if active.ends_ms is not None and state.time_ms >= active.ends_ms:
                yield active.event(
                    EventKind.RETIRED,
                    state.time_ms,
                    formula=str(active.engine.residual(active.engine_id)),
                    reason="its step ended",
                )
                retired.append(ident)
        for ident in retired:
            gone = self._active.pop(ident)
            still = {key for a in self._active.values() for key in a.keys}
            self.synthesizer.release(gone.keys - still)

    def _stale_event(self, change: StaleChange) -> MonitorEvent:
        fluents = [
            key
            for a in self._active.values()
            for key in sorted(a.keys)
            if change.label in self.synthesizer.labels_of(key)
        ]
        last = "never" if change.last_sample_ms is None else f"at {change.last_sample_ms} ms"
        reason = (
            f"stream {change.label} {'has no sample since' if change.stale else 'delivers again'}"
            f" (last sample {last}; stale after {self.synthesizer.stale} ms);"
            f" fluents: {', '.join(sorted(set(fluents))) or 'none'}"
        )
        return MonitorEvent(
            EventKind.STALE_DATA if change.stale else EventKind.DATA_RESUMED,
            change.time_ms,
            monitor_id=change.label,
            reason=reason,
        )

    def _refuse(self, decl: MonitorDecl, reason: str) -> StartResult:
        return StartResult(
            StartStatus.UNKNOWN_SYMBOL,
            f"{self.spec.source}:{decl.line}:{decl.column}: monitor {decl.name!r}: {reason}",
        )


def _why(active: _Active, state: State) -> str:
    """The values of the fluents the formula reads at the deciding state."""
    shown = []
    for key in sorted(active.keys):
        value = state.values.get(key)
        if isinstance(value, float):
            shown.append(f"{key}={value:.3g}" if math.isfinite(value) else f"{key}={value}")
        else:
            shown.append(f"{key}={value}")
    return ", ".join(shown)


def _variables(formula: Formula) -> Iterator[str]:
    for sub in _subformulas(formula):
        if isinstance(sub, Quantified):
            yield sub.variable


def _subformulas(formula: Formula) -> Iterator[Formula]:
    yield formula
    if isinstance(formula, Not):
        yield from _subformulas(formula.operand)
    elif isinstance(formula, And | Or):
        for operand in formula.operands:
            yield from _subformulas(operand)
    elif isinstance(formula, Implies | Until):
        yield from _subformulas(formula.left)
        yield from _subformulas(formula.right)
    elif isinstance(formula, Always | Eventually | Quantified):
        yield from _subformulas(formula.body)


def _fluents(formula: Formula) -> Iterator[FluentTerm]:
    for sub in _subformulas(formula):
        if isinstance(sub, Atom):
            yield from _term_fluents(sub.fluent)
        elif isinstance(sub, Comparison):
            yield from _term_fluents(sub.left)
            yield from _term_fluents(sub.right)


def _term_fluents(term: Term) -> Iterator[FluentTerm]:
    if isinstance(term, FluentTerm):
        yield term
        for arg in term.args:
            if isinstance(arg, FluentTerm):
                yield from _term_fluents(arg)
    elif isinstance(term, Negative):
        yield from _term_fluents(term.operand)
    elif isinstance(term, Arithmetic):
        yield from _term_fluents(term.left)
        yield from _term_fluents(term.right)


__all__ = [
    "EventKind",
    "ExecutionMonitor",
    "FlagUpdate",
    "MonitorEvent",
    "StartResult",
    "StartStatus",
]
