"""Transition tables: a validated model compiled into integer-indexed dict lookups.

The interpreter never looks at names in its hot path: states and events are integers and the
transitions of an automaton are found with ``table[state].get(event)``. Each template also knows
every event its subtree can react to (``interest``) so a step skips subtrees that cannot react.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from hdrc3_hcsm.errors import ModelError
from hdrc3_hcsm.model import (
    EXIT,
    PULSE,
    Action,
    GetAction,
    Guard,
    Model,
    PutAction,
    SetAction,
    StateKind,
    action_text,
)

PULSE_INDEX = 0
EXIT_INDEX = 1


class OpCode(enum.IntEnum):
    """Action kinds in compiled form."""

    SET = 0
    SEND = 1
    GET = 2
    PUT = 3


@dataclass(frozen=True, slots=True)
class ActionSpec:
    """One compiled action: ``name`` is the flag, slot or event; SEND also has data and target."""

    op: OpCode
    name: str
    event: int
    data_slot: str | None
    remote: str | None
    text: str


@dataclass(frozen=True, slots=True)
class TransitionSpec:
    """One compiled transition."""

    tid: str
    source: int
    target: int
    event: int
    guard: Guard | None
    actions: tuple[ActionSpec, ...]
    label: str


@dataclass(frozen=True)
class AutomatonTable:
    """Compiled automaton: state names, init state, exit states, regions and the lookup table."""

    name: str
    label: str
    states: tuple[str, ...]
    init: int
    exits: tuple[bool, ...]
    regions: dict[int, tuple[str, ...]]
    table: tuple[dict[int, tuple[TransitionSpec, ...]], ...]
    interest: frozenset[int]


@dataclass(frozen=True)
class EventTable:
    """Event names, ids and indices; indices 0 and 1 are the reserved pulse and exit events."""

    names: tuple[str, ...]
    ids: tuple[int, ...]
    index: dict[str, int]
    by_id: dict[int, int]

    def id_of(self, name: str) -> int:
        """The globally unique id of the event ``name`` (KeyError if the model lacks it)."""
        return self.ids[self.index[name]]


@dataclass(frozen=True)
class CompiledModel:
    """Everything the interpreter needs to run a model without further name resolution."""

    name: str
    computer: str
    events: EventTable
    automata: dict[str, AutomatonTable]
    root: tuple[str, ...]
    slots: dict[str, int]
    flags: frozenset[str]
    conditions: frozenset[str]
    source: Model


def _events(model: Model) -> EventTable:
    names = (PULSE, EXIT, *(e.name for e in model.events))
    ids = (0, 0, *(e.event_id for e in model.events))
    index = {n: i for i, n in enumerate(names)}
    by_id = {e.event_id: index[e.name] for e in model.events}
    return EventTable(names, ids, index, by_id)


def _action(action: Action, events: EventTable, local: str) -> ActionSpec:
    if isinstance(action, SetAction):
        return ActionSpec(OpCode.SET, action.flag, -1, None, None, action_text(action))
    if isinstance(action, GetAction):
        return ActionSpec(OpCode.GET, action.slot, -1, None, None, action_text(action))
    if isinstance(action, PutAction):
        return ActionSpec(OpCode.PUT, action.slot, -1, None, None, action_text(action))
    remote = action.target if action.target not in (None, local) else None
    return ActionSpec(
        OpCode.SEND,
        action.event,
        events.index[action.event],
        action.data_slot,
        remote,
        action_text(action),
    )


def compile_model(model: Model) -> CompiledModel:
    """Compile a validated, runnable model (see ``loader.load_file``) into lookup tables."""
    if model.computer is None or not model.root:
        raise ModelError(f"{model.file}: a runnable model needs a header and a root")
    events = _events(model)
    automata: dict[str, AutomatonTable] = {}
    for a in model.automata:
        states = tuple(s.name for s in a.states)
        sidx = {n: i for i, n in enumerate(states)}
        init = a.init_state()
        if init is None:
            raise ModelError(f"{a.pos}: automaton {a.name!r} has no init state")
        table: list[dict[int, list[TransitionSpec]]] = [{} for _ in states]
        for t in a.transitions:
            spec = TransitionSpec(
                t.tid,
                sidx[t.source],
                sidx[t.target],
                events.index[t.trigger],
                t.guard,
                tuple(_action(x, events, model.computer) for x in t.actions),
                t.label(),
            )
            table[spec.source].setdefault(spec.event, []).append(spec)
        automata[a.name] = AutomatonTable(
            name=a.name,
            label=a.label,
            states=states,
            init=sidx[init.name],
            exits=tuple(s.kind is StateKind.EXIT for s in a.states),
            regions={
                sidx[s.name]: model.regions_of(s.regions)
                for s in a.states
                if s.kind is StateKind.SUPER
            },
            table=tuple({e: tuple(ts) for e, ts in row.items()} for row in table),
            interest=frozenset(e for row in table for e in row),
        )
    automata = _with_subtree_interest(automata)
    return CompiledModel(
        name=model.name or model.file,
        computer=model.computer,
        events=events,
        automata=automata,
        root=model.regions_of(model.root),
        slots={s.name: s.size for s in model.slots},
        flags=frozenset(f.name for f in model.flags),
        conditions=frozenset(c.name for c in model.conditions),
        source=model,
    )


def _with_subtree_interest(automata: dict[str, AutomatonTable]) -> dict[str, AutomatonTable]:
    """Extend each automaton's interest with the events of the automata nested in it."""
    memo: dict[str, frozenset[int]] = {}

    def interest(name: str) -> frozenset[int]:
        if name not in memo:
            a = automata[name]
            nested = [interest(child) for names in a.regions.values() for child in names]
            memo[name] = a.interest.union(*nested)
        return memo[name]

    out: dict[str, AutomatonTable] = {}
    for name, a in automata.items():
        out[name] = AutomatonTable(
            a.name, a.label, a.states, a.init, a.exits, a.regions, a.table, interest(name)
        )
    return out
