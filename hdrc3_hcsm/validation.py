"""Static checks of a parsed model: names, reachability, init states, receivers, ids.

Every finding is a :class:`~hdrc3_hcsm.diagnostics.Diagnostic` with ``file:line:column``.
A model without ``root`` is checked as a library (root-dependent checks are skipped).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from hdrc3_hcsm.diagnostics import Diagnostic, Severity
from hdrc3_hcsm.model import (
    CACHE,
    EXIT,
    PULSE,
    Action,
    Automaton,
    GetAction,
    Model,
    PutAction,
    SendAction,
    SetAction,
    SourcePos,
    StateKind,
    guard_conditions,
)

MAX_EVENT_ID = 2**64 - 1


class _Checker:
    """Collects diagnostics for one model."""

    def __init__(self, model: Model) -> None:
        self.model = model
        self.out: list[Diagnostic] = []

    def error(self, code: str, message: str, pos: SourcePos) -> None:
        self.out.append(Diagnostic(Severity.ERROR, code, message, pos))

    def warning(self, code: str, message: str, pos: SourcePos) -> None:
        self.out.append(Diagnostic(Severity.WARNING, code, message, pos))

    def duplicates(self, kind: str, items: Iterable[tuple[str, SourcePos]]) -> None:
        seen: dict[str, SourcePos] = {}
        for name, pos in items:
            if name in seen:
                self.error("E010", f"{kind} {name!r} already declared at {seen[name]}", pos)
            else:
                seen[name] = pos

    # --- declarations -------------------------------------------------------------------
    def declarations(self) -> None:
        m = self.model
        top = SourcePos(m.file, 1, 1)
        declared = (m.computers, m.events, m.conditions, m.flags, m.slots, m.containers)
        if not (any(declared) or m.automata or m.includes or m.header_pos or m.root_pos):
            self.error("E017", "empty model: the file declares nothing", top)
        elif not m.automata and (m.header_pos is not None or m.root_pos is not None):
            where = m.header_pos or m.root_pos or top
            name = f"model {m.name}" if m.name else "the model"
            self.error("E018", f"{name} declares no automaton", where)
        if m.computer is None and m.root_pos is not None:
            self.error("E011", "missing header 'model NAME on COMPUTER;'", top)
        for kind, pos in m.redeclared:
            self.error("E016", f"'{kind}' declared more than once", pos)
        computers = {c.name for c in m.computers}
        if m.computer is not None and m.header_pos is not None and m.computer not in computers:
            self.error("E012", f"local computer {m.computer!r} not in 'computers'", m.header_pos)
        self.duplicates("computer", ((c.name, c.pos) for c in m.computers))
        self.duplicates("event", ((e.name, e.pos) for e in m.events))
        self.duplicates("event id", ((str(e.event_id), e.pos) for e in m.events))
        self.duplicates("condition", ((c.name, c.pos) for c in m.conditions))
        self.duplicates("flag", ((f.name, f.pos) for f in m.flags))
        self.duplicates("slot", ((s.name, s.pos) for s in m.slots))
        self.duplicates(
            "automaton or container",
            [(a.name, a.pos) for a in m.automata] + [(c.name, c.pos) for c in m.containers],
        )
        self.duplicates("automaton label", ((a.label, a.pos) for a in m.automata))
        for e in m.events:
            if e.name in (PULSE, EXIT):
                self.error("E013", f"event name {e.name!r} is reserved", e.pos)
            if e.event_id > MAX_EVENT_ID:
                self.error("E014", f"event id {e.event_id} does not fit in 64 bits", e.pos)
            for comp in (e.source, e.target):
                if comp is not None and comp not in computers:
                    self.error("E020", f"undefined computer {comp!r}", e.pos)
        for s in m.slots:
            if s.name == CACHE:
                self.error("E013", "slot name 'cache' is reserved", s.pos)
            if s.size <= 0:
                self.error("E015", f"slot {s.name!r} must have a positive size", s.pos)

    # --- structure ----------------------------------------------------------------------
    def regions(self, names: tuple[str, ...], pos: SourcePos) -> None:
        m = self.model
        if len(names) == 1 and m.container(names[0]) is not None:
            return
        for name in names:
            if m.automaton(name) is None:
                self.error("E021", f"undefined automaton or container {name!r}", pos)

    def structure(self) -> None:
        m = self.model
        for c in m.containers:
            self.regions(c.regions, c.pos)
        if m.root_pos is not None:
            self.regions(m.root, m.root_pos)
        self.cycles()
        if m.root_pos is None:
            self.warning(
                "W003", "no 'root' declared: checked as a library", SourcePos(m.file, 1, 1)
            )
        else:
            used = self.instantiated()
            for a in m.automata:
                if a.name not in used:
                    self.warning("W001", f"automaton {a.name!r} is never instantiated", a.pos)

    def children(self, automaton: Automaton) -> list[str]:
        return [
            name
            for s in automaton.states
            if s.kind is StateKind.SUPER
            for name in self.model.regions_of(s.regions)
        ]

    def cycles(self) -> None:
        m = self.model
        done: set[str] = set()

        def visit(name: str, stack: tuple[str, ...]) -> None:
            automaton = m.automaton(name)
            if automaton is None or name in done:
                return
            if name in stack:
                chain = " -> ".join((*stack, name))
                self.error("E030", f"automaton nests itself: {chain}", automaton.pos)
                return
            for child in self.children(automaton):
                visit(child, (*stack, name))
            done.add(name)

        for a in m.automata:
            visit(a.name, ())

    def instantiated(self) -> set[str]:
        m = self.model
        used: set[str] = set()
        todo = list(m.regions_of(m.root))
        while todo:
            name = todo.pop()
            automaton = m.automaton(name)
            if name in used or automaton is None:
                continue
            used.add(name)
            todo.extend(self.children(automaton))
        return used

    # --- automata -----------------------------------------------------------------------
    def automaton(self, a: Automaton) -> None:
        m = self.model
        self.duplicates("state", ((s.name, s.pos) for s in a.states))
        self.duplicates("transition", ((t.tid, t.pos) for t in a.transitions))
        inits = [s for s in a.states if s.kind is StateKind.INIT]
        if not inits:
            self.error("E040", f"automaton {a.name!r} has no init state", a.pos)
        for extra in inits[1:]:
            self.error("E041", f"automaton {a.name!r} has more than one init state", extra.pos)
        for s in a.states:
            if s.kind is StateKind.SUPER:
                self.regions(s.regions, s.pos)
        events = {e.name for e in m.events}
        conditions = {c.name for c in m.conditions}
        for t in a.transitions:
            if t.tid.split(".")[0] != a.label:
                self.error("E042", f"transition {t.tid} must be numbered {a.label}.N", t.pos)
            src, dst = a.state(t.source), a.state(t.target)
            for name, state in ((t.source, src), (t.target, dst)):
                if state is None:
                    self.error("E022", f"undefined state {name!r} in {a.name!r}", t.pos)
            if src is not None and src.kind is StateKind.EXIT:
                self.error("E043", f"transition {t.tid} leaves exit state {src.name!r}", t.pos)
            if t.trigger == EXIT and src is not None and src.kind is not StateKind.SUPER:
                self.error("E044", f"'on exit' needs a superstate, {src.name!r} is not", t.pos)
            if t.trigger not in (PULSE, EXIT) and t.trigger not in events:
                self.error("E023", f"undefined event {t.trigger!r}", t.pos)
            if t.guard is not None:
                for ref in guard_conditions(t.guard):
                    if ref.name not in conditions:
                        self.error("E024", f"undefined condition {ref.name!r}", ref.pos)
            self.actions(t.actions)
        self.reachability(a)

    def actions(self, actions: tuple[Action, ...]) -> None:
        m = self.model
        flags = {f.name for f in m.flags}
        slots = {s.name for s in m.slots} | {CACHE}
        computers = {c.name for c in m.computers}
        events = {e.name: e for e in m.events}
        for action in actions:
            if isinstance(action, SetAction) and action.flag not in flags:
                self.error("E025", f"undefined flag {action.flag!r}", action.pos)
            elif isinstance(action, GetAction | PutAction) and action.slot not in slots:
                self.error("E026", f"undefined memory slot {action.slot!r}", action.pos)
            elif isinstance(action, SendAction):
                if action.event not in events:
                    self.error("E023", f"undefined event {action.event!r}", action.pos)
                if action.data_slot is not None and action.data_slot not in slots:
                    self.error("E026", f"undefined memory slot {action.data_slot!r}", action.pos)
                if action.target is not None and action.target not in computers:
                    self.error("E020", f"undefined computer {action.target!r}", action.pos)
                decl = events.get(action.event)
                target = action.target or m.computer
                if decl is not None and decl.target is not None and decl.target != target:
                    self.error(
                        "E027",
                        f"event {decl.name!r} is declared 'to {decl.target}', sent to {target}",
                        action.pos,
                    )

    def reachability(self, a: Automaton) -> None:
        init = a.init_state()
        if init is None:
            return
        seen = {init.name}
        todo = [init.name]
        while todo:
            name = todo.pop()
            for t in a.transitions:
                if t.source == name and t.target not in seen:
                    seen.add(t.target)
                    todo.append(t.target)
        for s in a.states:
            if s.name not in seen:
                self.error("E045", f"state {s.name!r} is unreachable from {init.name!r}", s.pos)

    # --- events -------------------------------------------------------------------------
    def receivers(self) -> None:
        m = self.model
        if m.root_pos is None:
            return  # a library's events may be sent and received by other files
        triggers = {t.trigger for a in m.automata for t in a.transitions}
        local_sends: set[str] = set()
        any_sends: set[str] = set()
        for a in m.automata:
            for t in a.transitions:
                for action in t.actions:
                    if isinstance(action, SendAction):
                        any_sends.add(action.event)
                        if action.target is None or action.target == m.computer:
                            local_sends.add(action.event)
        for e in m.events:
            incoming = e.source is not None or e.name in local_sends
            if incoming and e.name not in triggers:
                self.error("E050", f"event {e.name!r} has no receiver in this model", e.pos)
            elif e.name not in triggers and e.name not in any_sends:
                self.warning("W002", f"event {e.name!r} is never sent nor received", e.pos)


def validate(model: Model) -> tuple[Diagnostic, ...]:
    """Check a parsed model; errors make it unfit to run, warnings are advice."""
    checker = _Checker(model)
    checker.declarations()
    checker.structure()
    for automaton in model.automata:
        checker.automaton(automaton)
    checker.receivers()
    return tuple(sorted(checker.out, key=lambda d: (d.pos.line, d.pos.column, d.code)))


def validate_system(models: Sequence[Model]) -> tuple[Diagnostic, ...]:
    """Check models of several computers together: event ids must be globally unique.

    The same event name must carry the same id everywhere, different names different ids, and
    an event declared ``to X`` must be received (declared ``from`` this computer) by X's model.
    """
    out: list[Diagnostic] = []
    by_name: dict[str, tuple[int, SourcePos]] = {}
    by_id: dict[int, tuple[str, SourcePos]] = {}
    for model in models:
        for e in model.events:
            seen = by_name.setdefault(e.name, (e.event_id, e.pos))
            if seen[0] != e.event_id:
                msg = f"event {e.name!r} has id {e.event_id} here but {seen[0]} at {seen[1]}"
                out.append(Diagnostic(Severity.ERROR, "E060", msg, e.pos))
            other = by_id.setdefault(e.event_id, (e.name, e.pos))
            if other[0] != e.name:
                msg = f"event id {e.event_id} of {e.name!r} also names {other[0]!r} at {other[1]}"
                out.append(Diagnostic(Severity.ERROR, "E061", msg, e.pos))
    by_computer = {m.computer: m for m in models if m.computer is not None}
    for model in models:
        for e in model.events:
            receiver = by_computer.get(e.target) if e.target is not None else None
            if receiver is None:
                continue
            incoming = {x.name for x in receiver.events if x.source == model.computer}
            if e.name not in incoming:
                msg = f"{e.target} model {receiver.file} lacks {e.name!r} from {model.computer}"
                out.append(Diagnostic(Severity.ERROR, "E062", msg, e.pos))
    return tuple(out)
