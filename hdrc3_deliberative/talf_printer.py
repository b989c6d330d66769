"""Printer: TALF syntax tree -> ``.talf`` text that parses back to an equal tree.

One C-ACT per line (sequences and concurrencies open a parenthesis, their children indented).
A where clause binds to the innermost C-ACT that can take it, so a C-ACT ending another one
(an else branch, a loop body) gets ``where true`` when an enclosing C-ACT has a where clause.
"""

from __future__ import annotations

from hdrc3_deliberative.mission_syntax import AgentsDecl, AreaDecl, PathDecl, PointDecl, WorldDecl
from hdrc3_deliberative.talf_formulas import args_text, formula_text, number_text
from hdrc3_deliberative.talf_syntax import (
    ActionTerm,
    CAct,
    CompositeSpec,
    Concurrent,
    ConstraintDef,
    Foreach,
    If,
    Interval,
    Item,
    Mission,
    OpenDecl,
    Sequence,
    TalfFile,
    While,
)

INDENT = "  "


def _interval(interval: Interval) -> str:
    return f"[{interval.start}, {interval.end}]"


def term_text(term: ActionTerm) -> str:
    """An action term with its own interval when it has one."""
    head = f"{_interval(term.interval)} " if term.interval is not None else ""
    return f"{head}{term.name}({args_text(term.args)})"


def _cact(cact: CAct, depth: int, close: bool) -> list[str]:
    """Lines of one C-ACT; ``close``: an enclosing C-ACT's where clause follows this one."""
    pad = INDENT * depth
    head = pad + (f"{cact.label}: " if cact.label else "") + _interval(cact.interval)
    if cact.agent is not None:
        head += f" by {cact.agent}"
    if cact.with_vars:
        head += f" with {', '.join(cact.with_vars)} do"
    task = cact.task
    inner_close = close or cact.where is not None
    ends_with_child = False
    if isinstance(task, ActionTerm):
        lines = [f"{head} {term_text(task)}"]
    elif isinstance(task, Sequence | Concurrent):
        sep = " ;" if isinstance(task, Sequence) else " ||"
        lines = [f"{head} ("]
        for i, child in enumerate(task.children):
            sub = _cact(child, depth + 1, False)
            if i < len(task.children) - 1:
                sub[-1] += sep
            lines += sub
        lines.append(f"{pad})")
    elif isinstance(task, If):
        lines = [f"{head} if {formula_text(task.cond)} then"]
        lines += _cact(task.then, depth + 1, False)
        lines.append(f"{pad}else")
        lines += _cact(task.orelse, depth + 1, inner_close)
        ends_with_child = True
    elif isinstance(task, While):
        lines = [f"{head} while {formula_text(task.cond)} do"]
        lines += _cact(task.body, depth + 1, inner_close)
        ends_with_child = True
    else:
        assert isinstance(task, Foreach)
        cond = formula_text(task.cond)
        lines = [f"{head} foreach {', '.join(task.vars)} where {cond} do conc"]
        lines += _cact(task.body, depth + 1, inner_close)
        ends_with_child = True
    where = formula_text(cact.where) if cact.where is not None else ("true" if close else None)
    if where is not None:
        if ends_with_child:
            lines.append(f"{pad}where {where}")
        else:
            lines[-1] += f" where {where}"
    return lines


def cact_text(cact: CAct, depth: int = 0) -> str:
    """One composite action."""
    return "\n".join(_cact(cact, depth, False))


def _item(item: Item) -> str:
    if isinstance(item, Mission):
        body = _cact(item.body, 1, False)
        return "\n".join([f"mission {item.name}:", *body])
    if isinstance(item, CompositeSpec):
        head = f"{_interval(item.interval)} {item.name}({', '.join(item.params)}) ~>"
        return "\n".join([head, *_cact(item.body, 1, False)])
    if isinstance(item, ConstraintDef):
        return f"constraint {item.name} = {formula_text(item.formula)}"
    if isinstance(item, OpenDecl):
        return f"open {', '.join(item.names)}"
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
    assert isinstance(item, PathDecl)
    return f"path {item.name} = ({', '.join(item.points)})"


def file_text(tree: TalfFile) -> str:
    """A whole file, one blank line between items."""
    return "\n\n".join(_item(i) for i in tree.items) + "\n"
