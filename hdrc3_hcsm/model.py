"""Syntax tree of an HCSM model: frozen dataclasses produced by the parser (chapter section 6.1).

The tree keeps source positions so that validation can point at ``file:line:column``. It is a
faithful image of the ``.hcsm`` text; compilation into lookup tables happens in ``tables.py``.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

# Reserved trigger names: the periodic pulse and the exit event a child container sends upwards.
PULSE = "pulse"
EXIT = "exit"
# The memory slot that receives event data and that GET/PUT copy through.
CACHE = "cache"


@dataclass(frozen=True)
class SourcePos:
    """Where a construct starts in its source file (1-based line and column)."""

    file: str
    line: int
    column: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


class StateKind(enum.Enum):
    """Kinds of states: simple, the init and exit simple states, and superstates."""

    SIMPLE = "state"
    INIT = "init"
    EXIT = "exit"
    SUPER = "super"


# --- guards: Boolean expressions over named atomic conditions -------------------------------


@dataclass(frozen=True)
class CondRef:
    """An atomic condition, implemented procedurally (name ends with -CO by convention)."""

    name: str
    pos: SourcePos


@dataclass(frozen=True)
class Not:
    """Negation of a guard expression."""

    operand: Guard


@dataclass(frozen=True)
class And:
    """Conjunction of two or more guard expressions."""

    operands: tuple[Guard, ...]


@dataclass(frozen=True)
class Or:
    """Disjunction of two or more guard expressions."""

    operands: tuple[Guard, ...]


Guard = CondRef | Not | And | Or


def guard_text(guard: Guard) -> str:
    """Render a guard in the surface syntax (fully parenthesised where needed)."""
    if isinstance(guard, CondRef):
        return guard.name
    if isinstance(guard, Not):
        return f"NOT {guard_text(guard.operand)}"
    joiner = " AND " if isinstance(guard, And) else " OR "
    return "(" + joiner.join(guard_text(g) for g in guard.operands) + ")"


def guard_conditions(guard: Guard) -> tuple[CondRef, ...]:
    """All condition references of a guard, in textual order."""
    if isinstance(guard, CondRef):
        return (guard,)
    if isinstance(guard, Not):
        return guard_conditions(guard.operand)
    return tuple(ref for g in guard.operands for ref in guard_conditions(g))


# --- actions ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class SetAction:
    """``SET flag``: raise an action flag for the control functions of this iteration."""

    flag: str
    pos: SourcePos


@dataclass(frozen=True)
class SendAction:
    """``SEND event [data slot] [to computer]``; no target means the local computer."""

    event: str
    data_slot: str | None
    target: str | None
    pos: SourcePos


@dataclass(frozen=True)
class GetAction:
    """``GET slot``: copy a memory slot into the cache slot."""

    slot: str
    pos: SourcePos


@dataclass(frozen=True)
class PutAction:
    """``PUT slot``: copy the cache slot into a memory slot."""

    slot: str
    pos: SourcePos


Action = SetAction | SendAction | GetAction | PutAction


def action_text(action: Action) -> str:
    """Render an action in the surface syntax."""
    if isinstance(action, SetAction):
        return f"SET {action.flag}"
    if isinstance(action, GetAction):
        return f"GET {action.slot}"
    if isinstance(action, PutAction):
        return f"PUT {action.slot}"
    text = f"SEND {action.event}"
    if action.data_slot is not None:
        text += f" data {action.data_slot}"
    if action.target is not None:
        text += f" to {action.target}"
    return text


# --- declarations -----------------------------------------------------------------------------


@dataclass(frozen=True)
class Transition:
    """A numbered transition ``A.1: Src-ST -> Dst-ST on Ev-EV [guard] / actions``."""

    tid: str
    source: str
    target: str
    trigger: str
    guard: Guard | None
    actions: tuple[Action, ...]
    pos: SourcePos

    def label(self) -> str:
        """One-line label ``A.1 Ev-EV [guard] / actions`` for traces and drawings."""
        text = f"{self.tid} {self.trigger}"
        if self.guard is not None:
            text += f" [{guard_text(self.guard)}]"
        if self.actions:
            text += " / " + ", ".join(action_text(a) for a in self.actions)
        return text


@dataclass(frozen=True)
class State:
    """A state; superstates name the automata (or one container) of their ordered regions."""

    name: str
    kind: StateKind
    regions: tuple[str, ...]
    pos: SourcePos


@dataclass(frozen=True)
class Automaton:
    """A state machine with a letter label used to number its transitions."""

    label: str
    name: str
    states: tuple[State, ...]
    transitions: tuple[Transition, ...]
    pos: SourcePos

    def state(self, name: str) -> State | None:
        """Find the state called ``name``."""
        return next((s for s in self.states if s.name == name), None)

    def init_state(self) -> State | None:
        """Find the (first) init state."""
        return next((s for s in self.states if s.kind is StateKind.INIT), None)


@dataclass(frozen=True)
class Container:
    """A reusable state machine container: automata in ordered concurrent regions."""

    name: str
    regions: tuple[str, ...]
    pos: SourcePos


@dataclass(frozen=True)
class EventDecl:
    """An event with its globally unique id; ``source``/``target`` mark external events."""

    name: str
    event_id: int
    source: str | None
    target: str | None
    pos: SourcePos


@dataclass(frozen=True)
class NameDecl:
    """A declared condition, action flag or computer name."""

    name: str
    pos: SourcePos


@dataclass(frozen=True)
class SlotDecl:
    """A labelled memory-bank slot with its size limit in bytes."""

    name: str
    size: int
    pos: SourcePos


@dataclass(frozen=True)
class Include:
    """``include "file.hcsm";``: a path relative to the including file."""

    path: str
    pos: SourcePos


@dataclass(frozen=True)
class Model:
    """One ``.hcsm`` file: the state machines run by the interpreter of one computer."""

    file: str
    name: str | None
    computer: str | None
    header_pos: SourcePos | None
    computers: tuple[NameDecl, ...]
    events: tuple[EventDecl, ...]
    conditions: tuple[NameDecl, ...]
    flags: tuple[NameDecl, ...]
    slots: tuple[SlotDecl, ...]
    containers: tuple[Container, ...]
    automata: tuple[Automaton, ...]
    root: tuple[str, ...]
    root_pos: SourcePos | None
    includes: tuple[Include, ...] = ()
    # Second and later ``model``/``root`` declarations (an error reported by validation).
    redeclared: tuple[tuple[str, SourcePos], ...] = ()

    def automaton(self, name: str) -> Automaton | None:
        """Find the automaton called ``name``."""
        return next((a for a in self.automata if a.name == name), None)

    def container(self, name: str) -> Container | None:
        """Find the container called ``name``."""
        return next((c for c in self.containers if c.name == name), None)

    def regions_of(self, names: tuple[str, ...]) -> tuple[str, ...]:
        """Expand a region list: a single container name stands for its automata."""
        if len(names) == 1:
            container = self.container(names[0])
            if container is not None:
                return container.regions
        return names
