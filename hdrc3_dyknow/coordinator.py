"""Stream reasoning coordinator (section 8.6): formula -> matched streams -> states -> verdicts.

Given a monitor formula, the coordinator parses it, resolves its sorts to objects through the
ontology, grounds it, collects the ground fluents progression will actually read, finds a stream
for each by *semantic matching* (never by topic name), and hosts a :class:`MonitorUnit`: a
knowledge process that synchronises those streams into states (section 8.4) and progresses the
formula through them (section 9.3.3). Verdicts are queued as :class:`VerdictEvent` for the
caller to drain. Expected failures (syntax, unknown symbols) are returned as results.
"""

from __future__ import annotations

import itertools
from collections import deque
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from enum import StrEnum

from hdrc3_base.errors import Hdrc3Error
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
from hdrc3_dyknow.formula_parser import FormulaParser, FormulaSyntaxError
from hdrc3_dyknow.grounding import GroundingError, Scope, compile_formula
from hdrc3_dyknow.interpretation import FluentValue, State, UnknownFluentError, atom_key
from hdrc3_dyknow.knowledge_process import KnowledgeProcessHost, StepContext
from hdrc3_dyknow.policy import Policy
from hdrc3_dyknow.progression import Progressor, Verdict
from hdrc3_dyknow.residual import Kind, Node, NodeTable
from hdrc3_dyknow.sample import FeatureTerm, StreamError
from hdrc3_dyknow.semantic_matching import MatchStatus, SemanticMatcher
from hdrc3_dyknow.state_sync import StateSynchronizer

MAX_EVENTS = 1024
PROCESS_PREFIX = "monitor:"


class MonitorStatus(StrEnum):
    """Outcome of a coordinator request."""

    STARTED = "started"
    STOPPED = "stopped"
    BAD_REQUEST = "bad_request"
    PARSE_ERROR = "parse_error"
    UNKNOWN_SYMBOL = "unknown_symbol"
    NOT_FOUND = "not_found"


@dataclass(frozen=True, slots=True)
class MonitorResult:
    """Answer to start/stop: a status, a readable reason and the streams used."""

    status: MonitorStatus
    reason: str = ""
    streams: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class VerdictEvent:
    """A monitor's verdict after the state at ``time`` (ms)."""

    monitor_id: str
    formula: str
    time: int
    verdict: Verdict
    residual: str
    states: int


@dataclass(frozen=True, slots=True)
class MonitorPlan:
    """What evaluating a formula needs: its grounding scope and a stream per ground fluent."""

    formula: Formula
    scope: Scope
    streams: dict[str, str]  # ground atom key -> stream label


def _sorts(formula: Formula) -> Iterator[str]:
    """Sorts quantified over anywhere in ``formula``."""
    if isinstance(formula, Quantified):
        yield formula.sort
        yield from _sorts(formula.body)
    elif isinstance(formula, Not | Always | Eventually):
        yield from _sorts(formula.operand if isinstance(formula, Not) else formula.body)
    elif isinstance(formula, And | Or):
        for operand in formula.operands:
            yield from _sorts(operand)
    elif isinstance(formula, Implies | Until):
        yield from _sorts(formula.left)
        yield from _sorts(formula.right)


def _terms(tree: Formula | Term | None, objects: frozenset[str]) -> Iterator[FeatureTerm]:
    """Ground fluents read by a ground atom or comparison (object constants excluded).

    A fluent with nested arguments (``fuel(av, location(av))``) yields its nested fluents only:
    which fluent it reads itself depends on their values (see :func:`nested_candidates`).
    """
    if isinstance(tree, Atom):
        yield from _terms(tree.fluent, objects)
    elif isinstance(tree, FluentTerm):
        if tree.nested:
            for arg in tree.args:
                if isinstance(arg, FluentTerm):
                    yield from _terms(arg, objects)
        elif tree.args or tree.name not in objects:
            yield FeatureTerm(tree.name, tuple(str(arg) for arg in tree.args))
    elif isinstance(tree, Comparison | Arithmetic):
        yield from _terms(tree.left, objects)
        yield from _terms(tree.right, objects)
    elif isinstance(tree, Negative):
        yield from _terms(tree.operand, objects)


def nested_fluents(node: Node) -> set[FluentTerm]:
    """Ground fluent terms with nested arguments anywhere in ``node``."""
    found: set[FluentTerm] = set()
    stack = [node]
    seen: set[int] = set()
    while stack:
        current = stack.pop()
        if id(current) in seen:
            continue
        seen.add(id(current))
        stack.extend(current.children())
        if current.kind in (Kind.ATOM, Kind.COMPARE):
            found |= _nested_in(current.source)
    return found


def _nested_in(tree: Formula | Term | None) -> set[FluentTerm]:
    if isinstance(tree, Atom):
        return _nested_in(tree.fluent)
    if isinstance(tree, FluentTerm):
        inner = {t for arg in tree.args if isinstance(arg, FluentTerm) for t in _nested_in(arg)}
        return inner | ({tree} if tree.nested else set())
    if isinstance(tree, Comparison | Arithmetic):
        return _nested_in(tree.left) | _nested_in(tree.right)
    if isinstance(tree, Negative):
        return _nested_in(tree.operand)
    return set()


def nested_candidates(term: FluentTerm, objects: Iterable[str]) -> list[FeatureTerm]:
    """Every ground fluent ``term`` may read: each nested argument replaced by each object."""
    choices = [sorted(objects) if isinstance(arg, FluentTerm) else [arg] for arg in term.args]
    return [FeatureTerm(term.name, tuple(args)) for args in itertools.product(*choices)]


def needed_fluents(node: Node, objects: frozenset[str]) -> tuple[bool | None, set[FeatureTerm]]:
    """Return the static truth (if any) and the fluents progression reads for ``node``.

    Mirrors the engine's left-to-right short-circuit of and/or, so the branch of
    ``x != av1 implies ...`` that can never be reached for ``x = av1`` needs no stream.
    """
    kind = node.kind
    needed: set[FeatureTerm] = set()
    if kind == Kind.TRUE or kind == Kind.FALSE:
        return kind == Kind.TRUE, needed
    if kind == Kind.ATOM:
        return None, set(_terms(node.source, objects))
    if kind == Kind.COMPARE:
        assert node.compare is not None
        try:
            return node.compare({}, 0.0), set()
        except UnknownFluentError:
            return None, set(_terms(node.source, objects))
    if kind == Kind.NOT:
        assert node.first is not None
        truth, needed = needed_fluents(node.first, objects)
        return (None if truth is None else not truth), needed
    if kind == Kind.AND or kind == Kind.OR:
        absorbing = kind == Kind.OR
        all_neutral = True
        for operand in node.operands:
            truth, more = needed_fluents(operand, objects)
            needed |= more
            if truth is absorbing:
                return absorbing, needed
            all_neutral = all_neutral and truth is not None
        return (not absorbing if all_neutral else None), needed
    for child in node.children():
        needed |= needed_fluents(child, objects)[1]
    return None, needed


class MonitorUnit:
    """Knowledge process: synchronise matched streams into states and progress a formula."""

    def __init__(
        self,
        monitor_id: str,
        text: str,
        plan: MonitorPlan,
        synchronizer: StateSynchronizer,
        events: deque[VerdictEvent],
    ) -> None:
        self.monitor_id = monitor_id
        self.text = text
        self.plan = plan
        self._progressor = Progressor(plan.formula, plan.scope)
        self._sync = synchronizer
        self._events = events
        self._keys: dict[str, list[str]] = {}
        for key, label in plan.streams.items():
            self._keys.setdefault(label, []).append(key)
        self.states = 0
        self.errors = 0
        self.last_error = ""

    @property
    def verdict(self) -> Verdict:
        """Verdict after the states progressed so far."""
        return self._progressor.verdict

    def step(self, ctx: StepContext) -> None:
        """Feed new samples to the synchroniser and progress every state it emits."""
        for label, samples in ctx.inputs.items():
            for sample in samples:
                for key in self._keys.get(label, ()):
                    self._sync.update(key, sample)
        for synced in self._sync.advance(ctx.now):
            if self._progressor.verdict is not Verdict.UNDECIDED:
                return
            values: dict[str, FluentValue] = {}
            for name, value in synced.values.items():
                if isinstance(value, tuple):
                    self._fail(f"fluent {name} has a tuple value {value!r}; expected a scalar")
                    break
                values[str(name)] = value
            else:
                self._progress(State(synced.time, values), synced.time)

    def _progress(self, state: State, time: int) -> None:
        try:
            verdict = self._progressor.update(state)
        except Hdrc3Error as exc:  # fluent type/lookup errors: skip this state, keep monitoring
            self._fail(str(exc))
            return
        self.states += 1
        if self.states == 1 or verdict is not Verdict.UNDECIDED:
            residual = "" if verdict is not Verdict.UNDECIDED else str(self._progressor.residual)
            self._events.append(
                VerdictEvent(self.monitor_id, self.text, time, verdict, residual, self.states)
            )

    def _fail(self, reason: str) -> None:
        self.errors += 1
        self.last_error = reason


@dataclass
class StreamReasoningCoordinator:
    """Finds, synchronises and reasons over the streams a formula needs."""

    host: KnowledgeProcessHost
    matcher: SemanticMatcher
    parser: FormulaParser = field(default_factory=FormulaParser)
    events: deque[VerdictEvent] = field(default_factory=lambda: deque(maxlen=MAX_EVENTS))
    _units: dict[str, MonitorUnit] = field(default_factory=dict)

    def plan(self, text: str) -> MonitorPlan | MonitorResult:
        """Parse, ground and match ``text``; a :class:`MonitorResult` on failure."""
        try:
            formula = self.parser.parse(text)
        except FormulaSyntaxError as exc:
            return MonitorResult(MonitorStatus.PARSE_ERROR, str(exc))
        ontology = self.matcher.ontology
        domains: dict[str, tuple[str, ...]] = {"Object": tuple(ontology.objects())}
        for sort in _sorts(formula):
            found = self.matcher.match_sort(sort)
            if found.status is not MatchStatus.MATCHED:
                return MonitorResult(MonitorStatus.UNKNOWN_SYMBOL, found.reason)
            domains[sort] = found.objects
        scope = Scope(domains)
        try:
            node = compile_formula(NodeTable(), formula, scope)
        except GroundingError as exc:
            return MonitorResult(MonitorStatus.UNKNOWN_SYMBOL, str(exc))
        streams: dict[str, str] = {}
        for term in sorted(needed_fluents(node, scope.objects())[1], key=str):
            match = self.matcher.match(term)
            if not match.ok:
                return MonitorResult(MonitorStatus.UNKNOWN_SYMBOL, match.reason)
            streams[atom_key(term.feature, term.args)] = match.labels[0]
        return MonitorPlan(formula, scope, streams)

    def start(self, monitor_id: str, text: str, period_ms: int, max_delay_ms: int) -> MonitorResult:
        """Start monitoring ``text`` with states every ``period_ms`` (ms)."""
        if not monitor_id or monitor_id in self._units:
            why = "empty" if not monitor_id else "already running"
            return MonitorResult(MonitorStatus.BAD_REQUEST, f"monitor id {monitor_id!r} {why}")
        if period_ms <= 0 or max_delay_ms < 0:
            return MonitorResult(
                MonitorStatus.BAD_REQUEST,
                f"need state period > 0 and max delay >= 0 ms, got {period_ms}, {max_delay_ms}",
            )
        plan = self.plan(text)
        if isinstance(plan, MonitorResult):
            return plan
        if not plan.streams:
            return MonitorResult(
                MonitorStatus.BAD_REQUEST, f"formula {text!r} reads no fluent: nothing to monitor"
            )
        labels = tuple(sorted(set(plan.streams.values())))
        try:
            sync = StateSynchronizer(list(plan.streams), period_ms, max_delay_ms)
        except StreamError as exc:
            return MonitorResult(MonitorStatus.BAD_REQUEST, str(exc))
        unit = MonitorUnit(monitor_id, text, plan, sync, self.events)
        self.host.add_process(PROCESS_PREFIX + monitor_id, unit, dict.fromkeys(labels, Policy()))
        self._units[monitor_id] = unit
        return MonitorResult(MonitorStatus.STARTED, f"monitoring {text}", labels)

    def stop(self, monitor_id: str) -> MonitorResult:
        """Stop a monitor and release its subscriptions."""
        unit = self._units.pop(monitor_id, None)
        if unit is None:
            running = ", ".join(sorted(self._units)) or "none"
            return MonitorResult(
                MonitorStatus.NOT_FOUND, f"no monitor {monitor_id!r}; running: {running}"
            )
        self.host.remove_process(PROCESS_PREFIX + monitor_id)
        return MonitorResult(MonitorStatus.STOPPED, f"stopped after {unit.states} states")

    def unit(self, monitor_id: str) -> MonitorUnit | None:
        """Return the running monitor ``monitor_id``, if any."""
        return self._units.get(monitor_id)

    def monitors(self) -> list[str]:
        """Ids of running monitors, sorted."""
        return sorted(self._units)

    def drain(self) -> list[VerdictEvent]:
        """Take the verdict events queued since the last drain."""
        out = list(self.events)
        self.events.clear()
        return out
