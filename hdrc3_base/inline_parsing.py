"""A lark LALR parser that builds the syntax tree while it parses, for the TST and TALF parsers.

lark's default is a parse tree of ``lark.Tree`` objects that a ``Transformer`` then walks a
second time. Given to the ``Lark`` constructor instead (``transformer=``, LALR only), the
builder runs at each reduction: no tree, no second walk, and fewer objects for the garbage
collector (about 30 % less time for the 1,000-node TST of ``bench/tst.py``). The result is
the same.

Two things differ from building after the parse, and are put back here:

* The builder is fixed when the parser is built, but positions name the file being parsed:
  the builder's per-parse state is set under a lock (parses are pure Python under the GIL,
  so serialising them costs nothing).
* A bad value (a number too large for a float) is found during the parse, before a syntax
  error further on; the builder records it and :meth:`InlineParser.parse` raises it only
  when the whole text parsed, so a syntax error is still reported first.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Any

import lark
from lark import Token, Transformer


class BadValue(Exception):
    """A value the grammar accepts but the syntax tree cannot hold (the first one of a text)."""


class InlineBuilder(Transformer[Token, Any]):
    """Base of a builder lark applies at each reduction: the file and the first bad value."""

    def __init__(self) -> None:
        super().__init__()
        self.file = "<string>"
        self.bad_value: str | None = None

    def reject(self, message: str) -> None:
        """Record a bad value; the first one is raised once the whole text parsed."""
        if self.bad_value is None:
            self.bad_value = message


@dataclass(frozen=True)
class InlineParser:
    """An LALR parser with its builder applied inline."""

    lark: lark.Lark
    builder: InlineBuilder
    lock: threading.Lock = field(default_factory=threading.Lock, compare=False)

    @classmethod
    def of(cls, grammar: str, builder: InlineBuilder) -> InlineParser:
        """Analyse ``grammar`` (placeholders for omitted optional parts) with ``builder``."""
        return cls(
            lark.Lark(grammar, parser="lalr", maybe_placeholders=True, transformer=builder),
            builder,
        )

    def parse(self, text: str, file: str) -> Any:
        """What the builder makes of ``text``, its positions in ``file``.

        Raises:
            lark.exceptions.UnexpectedInput: a syntax error.
            BadValue: the text parsed, but with a value the builder rejected.
        """
        with self.lock:
            self.builder.file, self.builder.bad_value = file, None
            out = self.lark.parse(text)
            if self.builder.bad_value is not None:
                raise BadValue(self.builder.bad_value)
        return out
