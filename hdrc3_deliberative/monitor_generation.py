"""Automatic generation of monitor formulas from the planning domain (chapter 9.3).

"One can automatically generate formulas verifying that preconditions and prevail conditions
are satisfied, that expected effects take place, and that bounds on action durations are not
violated ... automatic generation only takes place for those conditions that are flagged for
monitoring." The flags live in the monitor specification, beside the hand-written formulas, so
the planner's domain files stay as they are::

    generate for pick-up-box: pre, prevail, effects, duration within 2000 ms;

For operator ``o(h, b, l)`` of the TAL/PDDL domain (``agent h`` first among the parameters), the
generated operator-specific formulas are (``within`` is the slack, default 1000 ms):

* ``pre:o``      the precondition, checked at the first state of the step;
* ``prevail:o``  ``always (EXEC implies C)`` over the step;
* ``effects:o``  ``EXEC until (not EXEC and eventually[0,slack] E)`` (persistent): the effects
  at ``t'`` hold within ``slack`` of the step's end;
* ``duration:o`` ``eventually[0, D * unit + slack] not EXEC`` for a constant duration ``D``.

Not generated: effects at ``[t+1]`` and numeric effects (``fuel(h) -= ...``, which need the value
before the step), durations given by expressions (``flight-time``), and causal links between the
steps of a plan. Conditions are written in the monitor language and parsed back, so the result
is an ordinary :class:`~hdrc3_deliberative.monitor_spec.MonitorDecl`.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from hdrc3_deliberative.errors import PlanningInputError
from hdrc3_deliberative.model import Atom as PlanAtom
from hdrc3_deliberative.model import (
    AtomEffect,
    BinOp,
    Comparison,
    Condition,
    Domain,
    EffectTime,
    Equality,
    FuncTerm,
    Literal,
    Num,
    NumExpr,
    Operator,
)
from hdrc3_deliberative.monitor_spec import (
    Generated,
    MonitorDecl,
    MonitorSpec,
    MonitorSpecError,
)
from hdrc3_deliberative.pddl import PddlReader
from hdrc3_deliberative.planner import is_pddl
from hdrc3_deliberative.tal_language import TalReader
from hdrc3_dyknow.formula_parser import FormulaParser

DEFAULT_TIME_UNIT_MS = 1000.0
"""Milliseconds per time unit of the planning domain (TALplanner durations are seconds)."""


def read_domain_file(path: Path) -> Domain:
    """Read a planning domain, PDDL or the TAL domain language (as the task planner does).

    Raises:
        PlanningInputError: The file is unreadable or malformed (``file:line:column``).

    """
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise PlanningInputError(f"cannot read the domain: {exc}", str(path)) from None
    if is_pddl(text):
        return PddlReader().read_domain(text, str(path))
    return TalReader().read_domain(text, str(path))


def expand(
    spec: MonitorSpec,
    domain: Domain,
    time_unit_ms: float = DEFAULT_TIME_UNIT_MS,
    parser: FormulaParser | None = None,
) -> MonitorSpec:
    """``spec`` with its ``generate`` requests replaced by the generated formulas.

    Raises:
        MonitorSpecError: A request names an operator the domain does not have, or a kind
            the operator gives nothing to generate from (at the request's position).

    """
    parser = parser or FormulaParser()
    operators = {op.name: op for op in domain.operators}
    generated: list[MonitorDecl] = []
    for request in spec.generate:
        operator = operators.get(request.operator)
        if operator is None:
            known = ", ".join(sorted(operators)) or "none"
            raise MonitorSpecError(
                f"operator {request.operator!r} is not in domain {domain.name!r} (known: {known})",
                spec.source,
                request.line,
                request.column,
            )
        for kind in sorted(request.kinds, key=list(Generated).index):
            text = _formula(operator, kind, request.slack_ms, time_unit_ms)
            if text is None:
                raise MonitorSpecError(
                    f"operator {operator.name!r} has no {kind.value} to monitor",
                    spec.source,
                    request.line,
                    request.column,
                )
            generated.append(
                MonitorDecl(
                    name=f"{kind.value}:{operator.name}",
                    formula=parser.parse(text, f"<generated {kind.value}:{operator.name}>"),
                    text=text,
                    operator=operator.name,
                    parameters=_parameters(operator),
                    persistent=kind is Generated.EFFECTS,
                    line=request.line,
                    column=request.column,
                )
            )
    names = {decl.name for decl in spec.monitors}
    for decl in generated:
        if decl.name in names:
            raise MonitorSpecError(
                f"monitor {decl.name!r} is declared twice", spec.source, decl.line, decl.column
            )
        names.add(decl.name)
    return replace(spec, monitors=spec.monitors + tuple(generated), generate=())


def _parameters(operator: Operator) -> tuple[str, ...]:
    """The operator's parameters, its agent first (the flag's agent binds it)."""
    names = [param.name for param in operator.params]
    agent = operator.agent if operator.agent in names else names[0] if names else "agent"
    return (agent, *(name for name in names if name != agent))


def _formula(operator: Operator, kind: Generated, slack_ms: int, unit_ms: float) -> str | None:
    if kind is Generated.PRE:
        return _conjunction(operator.pre)
    if kind is Generated.PREVAIL:
        prevail = _conjunction(operator.prevail)
        return None if prevail is None else f"always (EXEC implies ({prevail}))"
    if kind is Generated.EFFECTS:
        ends = [
            _literal(effect.literal)
            for effect in operator.effects
            if isinstance(effect, AtomEffect) and effect.time is EffectTime.END
        ]
        if not ends:
            return None
        return f"EXEC until (not EXEC and eventually[0,{slack_ms}] ({' and '.join(ends)}))"
    if not isinstance(operator.duration, Num):
        return None
    bound = operator.duration.value * unit_ms + slack_ms
    return f"eventually[0,{bound:g}] not EXEC"


def _conjunction(conditions: tuple[Condition, ...]) -> str | None:
    if not conditions:
        return None
    return " and ".join(f"({_condition(c)})" for c in conditions)


def _condition(condition: Condition) -> str:
    if isinstance(condition, Literal):
        return _literal(condition)
    if isinstance(condition, Equality):
        op = "==" if condition.positive else "!="
        return f"{condition.left.name} {op} {condition.right.name}"
    assert isinstance(condition, Comparison)
    op = "==" if condition.op == "=" else condition.op
    return f"{_num(condition.left)} {op} {_num(condition.right)}"


def _literal(literal: Literal) -> str:
    text = _atom(literal.atom)
    return text if literal.positive else f"not {text}"


def _atom(atom: PlanAtom) -> str:
    if not atom.args:
        return atom.pred
    return f"{atom.pred}({', '.join(term.name for term in atom.args)})"


def _num(expr: NumExpr) -> str:
    if isinstance(expr, Num):
        return f"{expr.value:g}"
    if isinstance(expr, FuncTerm):
        return _atom(expr.atom)
    assert isinstance(expr, BinOp)
    return f"({_num(expr.left)} {expr.op} {_num(expr.right)})"
