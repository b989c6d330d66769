"""Loading a ``.tst`` file end to end and describing the result (``hdrc3 tst check``).

Parse, resolve against the world and the agents, propagate the network; then one line per
node with its agent, earliest/latest start and end and its parameters.
"""

from __future__ import annotations

import enum
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from hdrc3_tst.diagnostics import Diagnostic
from hdrc3_tst.model import Node, NodeKind
from hdrc3_tst.parser import ParseStatus, parse_file, parse_text
from hdrc3_tst.resolver import ResolvedTst, ResolveStatus, resolve
from hdrc3_tst.syntax import TstFile
from hdrc3_tst.worlds import WorldCache


class CheckStatus(enum.Enum):
    """Outcome of loading a TST."""

    OK = "ok"
    UNREADABLE = "unreadable"
    SYNTAX_ERROR = "syntax_error"
    INVALID = "invalid"
    INCONSISTENT = "inconsistent"


@dataclass(frozen=True)
class CheckResult:
    """The resolved mission when valid and consistent, and the diagnostics."""

    status: CheckStatus
    tst: ResolvedTst | None
    diagnostics: tuple[Diagnostic, ...] = ()


def _finish(
    tree: TstFile | None,
    diags: tuple[Diagnostic, ...],
    agents: tuple[str, ...],
    file: str,
    worlds: WorldCache | None,
) -> CheckResult:
    if tree is None:
        return CheckResult(CheckStatus.SYNTAX_ERROR, None, diags)
    result = resolve(tree, agents, file, worlds)
    status = {
        ResolveStatus.OK: CheckStatus.OK,
        ResolveStatus.INVALID: CheckStatus.INVALID,
        ResolveStatus.INCONSISTENT: CheckStatus.INCONSISTENT,
    }[result.status]
    return CheckResult(status, result.tst, result.diagnostics)


def load_text(
    text: str,
    file: str = "<string>",
    agents: tuple[str, ...] = (),
    worlds: WorldCache | None = None,
) -> CheckResult:
    """Parse, resolve and propagate TST text (``worlds``: see :func:`resolve`)."""
    parsed = parse_text(text, file)
    return _finish(parsed.tree, parsed.diagnostics, agents, file, worlds)


def load_file(
    path: str | Path, agents: tuple[str, ...] = (), worlds: WorldCache | None = None
) -> CheckResult:
    """Parse, resolve and propagate a ``.tst`` file (never raises on bad input)."""
    parsed = parse_file(path)
    if parsed.status is ParseStatus.UNREADABLE:
        return CheckResult(CheckStatus.UNREADABLE, None, parsed.diagnostics)
    return _finish(parsed.tree, parsed.diagnostics, agents, str(path), worlds)


def _value(tst: ResolvedTst, var: str) -> str:
    value = tst.network.values.get(var)
    if value is None:
        return f"{var} (open)"
    return f"{value:g}" if isinstance(value, float) else str(value)


def node_line(tst: ResolvedTst, node: Node, depth: int) -> str:
    """One node: id, type, agent, time windows and the other parameters."""
    what = node.action if node.kind in (NodeKind.ACTION, NodeKind.GOAL, NodeKind.CALL) else ""
    kind = f"{node.kind.value} {what}".strip() if node.kind is not NodeKind.ACTION else what
    net = tst.network
    parts = [
        f"{'  ' * depth}{node.node_id}: {kind}",
        f"P={_value(tst, node.params['P'])}",
        f"TS {net.window(node.params['TS'])}",
        f"TE {net.window(node.params['TE'])}",
    ]
    parts += [f"{k}={_value(tst, v)}" for k, v in node.params.items() if k not in ("P", "TS", "TE")]
    return "  ".join(parts)


def tree_lines(tst: ResolvedTst) -> Iterator[str]:
    """The tree, one node per line, depth first (a foreach's body as its template)."""
    for depth, node in tst.tree.walk():
        yield node_line(tst, node, depth)
        if node.kind is NodeKind.FOREACH and node.expanded_as is None and node.template:
            for sub_depth, sub in tst.tree.walk(node.template):
                yield node_line(tst, sub, depth + 1 + sub_depth)
