"""The shipped library of composite actions (``composite_actions.talf``, section 9.4).

Every TALF file may use the library's composite action types; a type the file declares itself
is the file's (the library's of the same name is not added).
"""

from __future__ import annotations

from functools import cache
from importlib import resources

from hdrc3_base.errors import DataError
from hdrc3_deliberative.talf_diagnostics import TalfStatus
from hdrc3_deliberative.talf_parser import parse_text
from hdrc3_deliberative.talf_syntax import CompositeSpec, TalfFile

LIBRARY_FILE = "composite_actions.talf"


def library_text() -> str:
    """The library's source."""
    return resources.files("hdrc3_deliberative").joinpath(LIBRARY_FILE).read_text("utf-8")


@cache
def library() -> TalfFile:
    """The parsed library; DataError if the shipped file does not parse (a packaging bug)."""
    path = str(resources.files("hdrc3_deliberative").joinpath(LIBRARY_FILE))
    parsed = parse_text(library_text(), path)
    if parsed.status is not TalfStatus.OK or parsed.tree is None:
        raise DataError("; ".join(str(d) for d in parsed.diagnostics))
    return parsed.tree


def with_library(tree: TalfFile) -> TalfFile:
    """``tree`` with the library's composite action types it does not declare, appended."""
    own = tree.specs()
    extra: tuple[CompositeSpec, ...] = tuple(
        spec for name, spec in library().specs().items() if name not in own
    )
    return TalfFile((*tree.items, *extra))
