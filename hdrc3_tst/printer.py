"""Printer: syntax tree -> ``.tst`` text that parses back to an equal tree.

One node per line, children indented; a composite child always ends with its where clause
(``where true`` when it has none), which is what closes its list in the grammar.
"""

from __future__ import annotations

from hdrc3_deliberative.mission_syntax import (
    AgentsDecl,
    AreaDecl,
    Comparison,
    ConsRef,
    LinExpr,
    Membership,
    Name,
    Number,
    PathDecl,
    PointDecl,
    Term,
    WorldDecl,
)
from hdrc3_tst.errors import TstError
from hdrc3_tst.syntax import (
    ActionTask,
    CallTask,
    ConcurrentTask,
    Condition,
    ConsDef,
    Constraint,
    ForeachTask,
    GoalTask,
    IfTask,
    Item,
    SequenceTask,
    TstDef,
    TstFile,
    WhileTask,
)

INDENT = "  "


def number_text(value: float) -> str:
    """Shortest text that reads back as the same float (integers without ``.0``)."""
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return repr(value)


def arg_text(arg: Name | Number) -> str:
    """One argument."""
    return arg.id if isinstance(arg, Name) else number_text(arg.value)


def _args(args: tuple[Name | Number, ...]) -> str:
    return ", ".join(arg_text(a) for a in args)


def _term(term: Term, first: bool) -> str:
    sign = "-" if term.coef < 0 else "+"
    size = abs(term.coef)
    if term.name is None:
        body = number_text(size)
    elif size == 1:
        body = term.name.id
    else:
        body = f"{number_text(size)} * {term.name.id}"
    if first:
        return f"-{body}" if sign == "-" else body
    return f"{sign} {body}"


def expr_text(expr: LinExpr) -> str:
    """A linear expression."""
    return " ".join(_term(t, i == 0) for i, t in enumerate(expr.terms))


def constraint_text(cons: Constraint) -> str:
    """One constraint."""
    if isinstance(cons, Comparison):
        return f"{expr_text(cons.left)} {cons.op.value} {expr_text(cons.right)}"
    if isinstance(cons, Membership):
        return f"{cons.var.id} in {{{_args(cons.values)}}}"
    assert isinstance(cons, ConsRef)
    return cons.name.id


def cons_text(constraints: tuple[Constraint, ...]) -> str:
    """A conjunction (``true`` when empty)."""
    return " and ".join(constraint_text(c) for c in constraints) or "true"


def _cond(cond: Condition) -> str:
    time = f"[{cond.time}] " if cond.time is not None else ""
    neg = "not " if cond.negated else ""
    return f"{time}{neg}{cond.name}({_args(cond.args)})"


def _tst(tst: TstDef, depth: int, child: bool) -> list[str]:
    pad = INDENT * depth
    head = f"{pad}{tst.name}({', '.join(tst.params)}) ="
    if tst.with_vars:
        head += f" with {', '.join(tst.with_vars)}"
    task = tst.task
    lines: list[str]
    if isinstance(task, ActionTask):
        lines = [f"{head} {task.name}({_args(task.args)})"]
    elif isinstance(task, GoalTask):
        lines = [f"{head} goal {task.name}({_args(task.args)})"]
    elif isinstance(task, CallTask):
        lines = [f"{head} call {task.name}({_args(task.args)})"]
    elif isinstance(task, SequenceTask | ConcurrentTask):
        word = "sequence" if isinstance(task, SequenceTask) else "concurrent"
        lines = [f"{head} {word}"]
        for i, sub in enumerate(task.children):
            sub_lines = _tst(sub, depth + 1, True)
            if i < len(task.children) - 1:
                sub_lines[-1] += ";"
            lines += sub_lines
    elif isinstance(task, IfTask):
        lines = [f"{head} if {_cond(task.cond)} then"]
        lines += _tst(task.then, depth + 1, True)
        lines.append(f"{pad}else")
        lines += _tst(task.orelse, depth + 1, True)
    elif isinstance(task, WhileTask):
        lines = [f"{head} while {_cond(task.cond)}"]
        lines += _tst(task.body, depth + 1, True)
    else:
        assert isinstance(task, ForeachTask)
        lines = [f"{head} foreach {', '.join(task.vars)} where {_cond(task.cond)} do conc"]
        lines += _tst(task.body, depth + 1, True)
    composite = not isinstance(task, ActionTask | GoalTask | CallTask)
    if child and not composite and tst.where:
        raise TstError(f"{tst.name}: an elementary child has no where clause; use its parent's")
    if tst.where or (child and composite):
        lines.append(f"{pad}where {cons_text(tst.where)}")
    return lines


def tst_text(tst: TstDef) -> str:
    """One top-level TST definition."""
    return "\n".join(_tst(tst, 0, False))


def _item(item: Item) -> str:
    if isinstance(item, TstDef):
        return tst_text(item)
    if isinstance(item, WorldDecl):
        return f"world {item.name}"
    if isinstance(item, AgentsDecl):
        return f"agents {', '.join(item.names)}"
    if isinstance(item, AreaDecl):
        pts = ", ".join(f"({number_text(e)}, {number_text(n)})" for e, n in item.vertices)
        return f"area {item.name} = polygon({pts})"
    if isinstance(item, PointDecl):
        if item.xyz is not None:
            return f"point {item.name} = ({', '.join(number_text(v) for v in item.xyz)})"
        return f"point {item.name} = {item.place} at {number_text(item.altitude)}"
    if isinstance(item, PathDecl):
        return f"path {item.name} = ({', '.join(item.points)})"
    assert isinstance(item, ConsDef)
    return f"{item.name} = {cons_text(item.constraints)}"


def file_text(tree: TstFile) -> str:
    """A whole file, one blank line between items."""
    return "\n\n".join(_item(i) for i in tree.items) + "\n"
