"""Loading a ``.talf`` file end to end: parse, add the library, check names and capabilities."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from hdrc3_deliberative.talf_check import ElementarySpec, check, check_capabilities
from hdrc3_deliberative.talf_diagnostics import TalfDiagnostic, TalfStatus
from hdrc3_deliberative.talf_expand import expand
from hdrc3_deliberative.talf_library import with_library
from hdrc3_deliberative.talf_parser import ParseResult, parse_file, parse_text
from hdrc3_deliberative.talf_syntax import TalfFile


@dataclass(frozen=True)
class LoadResult:
    """The file with the library's composite action types (when valid) and the diagnostics."""

    status: TalfStatus
    tree: TalfFile | None
    diagnostics: tuple[TalfDiagnostic, ...] = ()


def _finish(
    parsed: ParseResult,
    actions: Mapping[str, ElementarySpec],
    capabilities: Mapping[str, frozenset[str]] | None,
) -> LoadResult:
    if parsed.tree is None:
        return LoadResult(parsed.status, None, parsed.diagnostics)
    tree = with_library(parsed.tree)
    diags = check(tree, actions)
    if diags:
        return LoadResult(TalfStatus.INVALID, None, diags)
    if capabilities is not None:
        # An agent given no capabilities has all the registry's actions need (a gateway's default).
        every = frozenset(c.value for spec in actions.values() for c in spec.needs)
        caps = {a: capabilities.get(a, every) for a in (*tree.agents(), *capabilities)}
        found = tuple(
            d
            for mission in tree.missions()
            for d in check_capabilities(
                mission.name, expand(mission, tree.specs()).body, actions, caps
            )
        )
        if found:
            return LoadResult(TalfStatus.UNSATISFIABLE, tree, found)
    return LoadResult(TalfStatus.OK, tree)


def load_text(
    text: str,
    actions: Mapping[str, ElementarySpec],
    file: str = "<string>",
    capabilities: Mapping[str, frozenset[str]] | None = None,
) -> LoadResult:
    """Parse and check TALF text; ``capabilities`` (agent -> names) also checks what AVs have.

    Agents the file declares and ``capabilities`` leaves out have every capability.
    """
    return _finish(parse_text(text, file), actions, capabilities)


def load_file(
    path: str | Path,
    actions: Mapping[str, ElementarySpec],
    capabilities: Mapping[str, frozenset[str]] | None = None,
) -> LoadResult:
    """Read, parse and check a ``.talf`` file (never raises on bad input)."""
    return _finish(parse_file(path), actions, capabilities)
