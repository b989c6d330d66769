"""TAL formulas of TALF where clauses and conditions, and of TALF's semantics (section 9.4).

The parser builds the first group (atoms, comparisons over linear expressions, memberships,
references to named constraint sets, connectives and quantifiers); the translation into the
base logic L(FL_FP) adds ``Occurs`` and the fixpoint construct (:class:`Lfp`, applied with
:class:`PredApp`). One printer, :func:`formula_text`, writes them all in ASCII TAL.

Written here rather than reusing :mod:`hdrc3_deliberative.model`: the planner's formulas are
evaluated over states at ``[t]``/``[t+1]`` only, while TALF's name arbitrary timepoint variables
and need ``Occurs`` and fixpoints.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from hdrc3_deliberative.mission_syntax import (
    NOWHERE,
    Arg,
    Cmp,
    Comparison,
    ConsRef,
    LinExpr,
    Membership,
    Name,
    SourcePos,
    Term,
)


@dataclass(frozen=True)
class Atom:
    """``[t] name(args)``: a fluent or predicate, at timepoint ``time`` when given."""

    name: str
    args: tuple[Arg, ...]
    time: str | None = None
    pos: SourcePos = field(default=NOWHERE, compare=False, repr=False)


@dataclass(frozen=True)
class TrueF:
    """``true`` (an omitted where clause)."""


@dataclass(frozen=True)
class Not:
    """Negation."""

    arg: Formula


@dataclass(frozen=True)
class And:
    """Conjunction (flat: no And directly inside)."""

    args: tuple[Formula, ...]


@dataclass(frozen=True)
class Or:
    """Disjunction."""

    args: tuple[Formula, ...]


@dataclass(frozen=True)
class Implies:
    """``left -> right``."""

    left: Formula
    right: Formula


@dataclass(frozen=True)
class Iff:
    """``left <-> right`` (the definition of a composite action type)."""

    left: Formula
    right: Formula


@dataclass(frozen=True)
class Exists:
    """``exists VARS (body)``."""

    vars: tuple[str, ...]
    body: Formula


@dataclass(frozen=True)
class Forall:
    """``forall VARS (body)``."""

    vars: tuple[str, ...]
    body: Formula


@dataclass(frozen=True)
class Occurs:
    """``Occurs(t, t', name(args))``: the action ``name(args)`` is executed over ``[t, t']``."""

    start: str
    end: str
    name: str
    args: tuple[Arg, ...]


@dataclass(frozen=True)
class PredApp:
    """``W(a, b)``: a fixpoint's predicate variable applied to timepoints."""

    pred: str
    args: tuple[str, ...]


@dataclass(frozen=True)
class Lfp:
    """``lfp W(x, y). body``: the least fixpoint of ``body`` in the predicate variable ``W``.

    Applied as ``(lfp W(x, y). body)(a, b)``: ``args`` are the actual timepoints.
    """

    pred: str
    params: tuple[str, ...]
    body: Formula
    args: tuple[str, ...]


Formula = (
    Comparison
    | Membership
    | ConsRef
    | Atom
    | TrueF
    | Not
    | And
    | Or
    | Implies
    | Iff
    | Exists
    | Forall
    | Occurs
    | PredApp
    | Lfp
)


def conj(*parts: Formula | None) -> Formula:
    """The flat conjunction of the parts (None, ``true`` and repeats dropped; ``true`` if empty)."""
    flat: list[Formula] = []
    for part in parts:
        if part is None or isinstance(part, TrueF):
            continue
        flat.extend(p for p in (part.args if isinstance(part, And) else (part,)) if p not in flat)
    if not flat:
        return TrueF()
    return flat[0] if len(flat) == 1 else And(tuple(flat))


def conjuncts(formula: Formula | None) -> tuple[Formula, ...]:
    """The conjuncts of a formula (none for None or ``true``)."""
    if formula is None or isinstance(formula, TrueF):
        return ()
    return formula.args if isinstance(formula, And) else (formula,)


def time_le(a: str, b: str) -> Formula:
    """``a <= b`` over two timepoint variables (``true`` when they are the same)."""
    if a == b:
        return TrueF()
    return Comparison(LinExpr((Term(1.0, Name(a)),)), Cmp.LE, LinExpr((Term(1.0, Name(b)),)))


def negate(formula: Formula) -> Formula:
    """``not formula``, without a double negation."""
    return formula.arg if isinstance(formula, Not) else Not(formula)


# --- text --------------------------------------------------------------------------------------


def number_text(value: float) -> str:
    """Shortest text that reads back as the same float (integers without ``.0``)."""
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return repr(value)


def arg_text(arg: Arg) -> str:
    """One argument."""
    return arg.id if isinstance(arg, Name) else number_text(arg.value)


def args_text(args: tuple[Arg, ...]) -> str:
    """Comma-separated arguments."""
    return ", ".join(arg_text(a) for a in args)


def _term(term: Term, first: bool) -> str:
    size = abs(term.coef)
    if term.name is None:
        body = number_text(size)
    elif size == 1:
        body = term.name.id
    else:
        body = f"{number_text(size)} * {term.name.id}"
    if first:
        return f"-{body}" if term.coef < 0 else body
    return f"{'-' if term.coef < 0 else '+'} {body}"


def expr_text(expr: LinExpr) -> str:
    """A linear expression."""
    return " ".join(_term(t, i == 0) for i, t in enumerate(expr.terms))


def _wrap(formula: Formula, timed: bool) -> str:
    text = _text(formula, timed)
    return f"({text})" if isinstance(formula, And | Or | Implies | Iff) else text


def atom_times(formula: Formula) -> set[str | None]:
    """The timepoints of the atoms in a formula (None for an untimed atom)."""
    if isinstance(formula, Atom):
        return {formula.time}
    if isinstance(formula, Not):
        return atom_times(formula.arg)
    if isinstance(formula, And | Or):
        return set().union(*(atom_times(a) for a in formula.args))
    if isinstance(formula, Implies | Iff):
        return atom_times(formula.left) | atom_times(formula.right)
    if isinstance(formula, Exists | Forall | Lfp):
        return atom_times(formula.body)
    return set()


def formula_text(formula: Formula, hoist: bool = True) -> str:
    """ASCII TAL: ``and``, ``or``, ``not``, ``->``, ``<->``, ``exists x (..)``, ``[t] p(x)``.

    ``[t]`` scopes over the whole formula after it: when every atom is at the same timepoint
    (and ``hoist``) it is written once in front, else each timed atom as ``([t] p(x))``.
    """
    times = atom_times(formula)
    if hoist and len(times) == 1 and None not in times:
        return f"[{next(iter(times))}] {_text(formula, False)}"
    return _text(formula, True)


def _text(formula: Formula, timed: bool) -> str:
    if isinstance(formula, Comparison):
        return f"{expr_text(formula.left)} {formula.op.value} {expr_text(formula.right)}"
    if isinstance(formula, Membership):
        return f"{formula.var.id} in {{{args_text(formula.values)}}}"
    if isinstance(formula, ConsRef):
        return formula.name.id
    if isinstance(formula, Atom):
        text = f"{formula.name}({args_text(formula.args)})"
        return f"([{formula.time}] {text})" if timed and formula.time is not None else text
    if isinstance(formula, TrueF):
        return "true"
    if isinstance(formula, Not):
        return f"not {_wrap(formula.arg, timed)}"
    if isinstance(formula, And | Or):
        word = " and " if isinstance(formula, And) else " or "
        return word.join(_wrap(a, timed) for a in formula.args)
    if isinstance(formula, Implies | Iff):
        arrow = " -> " if isinstance(formula, Implies) else " <-> "
        return f"{_wrap(formula.left, timed)}{arrow}{_wrap(formula.right, timed)}"
    if isinstance(formula, Exists | Forall):
        word = "exists" if isinstance(formula, Exists) else "forall"
        return f"{word} {', '.join(formula.vars)} ({_text(formula.body, timed)})"
    if isinstance(formula, Occurs):
        return f"Occurs({formula.start}, {formula.end}, {formula.name}({args_text(formula.args)}))"
    if isinstance(formula, PredApp):
        return f"{formula.pred}({', '.join(formula.args)})"
    head = f"lfp {formula.pred}({', '.join(formula.params)})"
    return f"({head}. {_text(formula.body, timed)})({', '.join(formula.args)})"


def formula_names(formula: Formula) -> tuple[Name, ...]:
    """Every name a where clause or condition uses (arguments, expression variables), in order.

    Names bound by quantifiers inside the formula are left out.
    """
    if isinstance(formula, Comparison):
        return tuple(t.name for e in (formula.left, formula.right) for t in e.terms if t.name)
    if isinstance(formula, Membership):
        return (formula.var, *(v for v in formula.values if isinstance(v, Name)))
    if isinstance(formula, Atom):
        names = tuple(a for a in formula.args if isinstance(a, Name))
        return (Name(formula.time, formula.pos), *names) if formula.time else names
    if isinstance(formula, Not):
        return formula_names(formula.arg)
    if isinstance(formula, And | Or):
        return tuple(n for a in formula.args for n in formula_names(a))
    if isinstance(formula, Implies | Iff):
        return formula_names(formula.left) + formula_names(formula.right)
    if isinstance(formula, Exists | Forall):
        return tuple(n for n in formula_names(formula.body) if n.id not in formula.vars)
    return ()
