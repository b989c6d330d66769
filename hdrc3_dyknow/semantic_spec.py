"""Stream specifications with semantic annotations: an SSL_T-like language (section 8.5).

A specification declares objects of ontology sorts and streams: the feature term a stream's
content is about (its *semantic annotation*), where its samples come from (a field of a ROS
topic, or a function of other streams) and its policy. Example::

    object uav0, uav1 : RMAX;
    stream uav0/position contains Position(uav0)
        from topic "/uav0/helicopter_state" field position with period 40 ms;
    stream uav1/xydist/uav0 contains XYDist[uav1, uav0]
        = xy_dist(uav1/position, uav0/position) with period 100 ms, max_delay 200 ms;

Parsing goes lark grammar (``semantic_spec.lark``) -> frozen dataclasses; errors carry
``source:line:column`` and what was expected. Policy times are in ms.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from dataclasses import dataclass, field
from functools import cache
from importlib import resources
from typing import Any

import lark

from hdrc3_base.errors import Hdrc3Error
from hdrc3_dyknow.policy import LateHandling, MissingHandling, Policy
from hdrc3_dyknow.sample import FeatureTerm, StreamError


class SpecError(Hdrc3Error):
    """A stream specification does not parse or is inconsistent (with its location)."""

    def __init__(self, message: str, source: str, line: int, column: int) -> None:
        super().__init__(f"{source}:{line}:{column}: {message}")
        self.source = source
        self.line = line
        self.column = column


class SpecSyntaxError(SpecError):
    """A stream specification does not parse."""


@dataclass(frozen=True, slots=True)
class ObjectDecl:
    """``object a, b : Sort;``."""

    names: tuple[str, ...]
    sort: str
    line: int = field(default=0, compare=False)
    column: int = field(default=0, compare=False)


@dataclass(frozen=True, slots=True)
class TopicSource:
    """Samples come from ``field`` of each ``message`` on a ROS ``topic``.

    With ``equals``, a sample is whether the field's value equals that text (a tag read by a
    sensor, e.g. the hook's ``object_id``): a boolean stream.
    """

    topic: str
    field: str
    message: str = "HelicopterState"
    """The topic's message type (a key of ``sources.MESSAGE_SOURCES``)."""
    equals: str | None = None


@dataclass(frozen=True, slots=True)
class FunctionSource:
    """Samples are ``function`` of the synchronised streams ``inputs``."""

    function: str
    inputs: tuple[str, ...]


Source = TopicSource | FunctionSource


@dataclass(frozen=True, slots=True)
class StreamDecl:
    """``stream label contains Feature(args) [source] [with policy];``."""

    label: str
    term: FeatureTerm
    source: Source | None
    policy: Policy
    line: int = field(default=0, compare=False)
    column: int = field(default=0, compare=False)

    @property
    def annotation(self) -> str:
        """The semantic annotation as text, e.g. ``XYDist[uav1, uav0]``."""
        return str(self.term)


@dataclass(frozen=True, slots=True)
class StreamSpec:
    """A parsed specification."""

    objects: tuple[ObjectDecl, ...] = ()
    streams: tuple[StreamDecl, ...] = ()
    source: str = field(default="<spec>", compare=False)


# The venv also holds lark-parser 0.12's ``lark-stubs`` (pulled in by rosidl), whose types differ
# from lark 1.x's own; tree nodes and exception details are therefore handled as ``Any`` here so
# the module type-checks against either, while the public API stays fully typed.
_Tree = Any


@cache
def _parser() -> lark.Lark:
    grammar = resources.files("hdrc3_dyknow").joinpath("semantic_spec.lark").read_text()
    return lark.Lark(grammar, parser="lalr", propagate_positions=True)


def parse_spec(text: str, source: str = "<spec>") -> StreamSpec:
    """Parse a stream specification.

    Args:
        text: Specification text.
        source: Name used in error messages (file name).

    Raises:
        SpecSyntaxError: On a syntax error, with line and column and what was expected.
        SpecError: On an invalid policy item, with line and column.

    """
    try:
        tree = _parser().parse(text)
    except lark.UnexpectedToken as error:
        exc: Any = error
        expected = _readable(exc.accepts or exc.expected)
        if exc.token.type == "$END":
            lines = text.split("\n")
            raise SpecSyntaxError(
                f"unexpected end of input; expected one of: {expected}",
                source,
                len(lines),
                len(lines[-1]) + 1,
            ) from None
        raise SpecSyntaxError(
            f"unexpected {str(exc.token)!r}; expected one of: {expected}",
            source,
            exc.line,
            exc.column,
        ) from None
    except lark.UnexpectedCharacters as error:
        exc = error
        raise SpecSyntaxError(
            f"unexpected character {text[exc.pos_in_stream]!r}", source, exc.line, exc.column
        ) from None
    except lark.UnexpectedEOF as error:
        exc = error
        raise SpecSyntaxError(
            f"unexpected end of input; expected one of: {_readable(exc.expected)}",
            source,
            exc.line,
            exc.column,
        ) from None
    return _Builder(source).spec(tree)


def _readable(terminals: Iterable[str]) -> str:
    """Show anonymous terminals as their text (``"with"``) rather than lark's names."""
    shown = []
    for name in terminals:
        try:
            pattern = _parser().get_terminal(name).pattern
        except KeyError:
            shown.append(name)
            continue
        shown.append(repr(pattern.value) if isinstance(pattern, lark.lexer.PatternStr) else name)
    return ", ".join(sorted(shown))


class _Builder:
    """Walk the lark tree into dataclasses."""

    def __init__(self, source: str) -> None:
        self._source = source

    def spec(self, tree: _Tree) -> StreamSpec:
        objects: list[ObjectDecl] = []
        streams: list[StreamDecl] = []
        for decl in tree.children:
            assert isinstance(decl, lark.Tree)
            if decl.data == "object_decl":
                objects.append(self._object(decl))
            else:
                streams.append(self._stream(decl))
        return StreamSpec(tuple(objects), tuple(streams), self._source)

    def _error(self, message: str, node: _Tree | lark.Token) -> SpecError:
        line = node.line if isinstance(node, lark.Token) else node.meta.line
        column = node.column if isinstance(node, lark.Token) else node.meta.column
        return SpecError(message, self._source, line or 0, column or 0)

    def _object(self, decl: _Tree) -> ObjectDecl:
        names, sort = decl.children
        assert isinstance(names, lark.Tree) and isinstance(sort, lark.Token)
        return ObjectDecl(_names(names), str(sort), decl.meta.line, decl.meta.column)

    def _stream(self, decl: _Tree) -> StreamDecl:
        label_tree, feature, *rest = decl.children
        assert isinstance(label_tree, lark.Tree) and isinstance(feature, lark.Tree)
        source: Source | None = None
        policy = Policy()
        for part in rest:
            assert isinstance(part, lark.Tree)
            if part.data == "policy":
                policy = self._policy(part)
            elif part.data == "topic_source":
                topic, *middle = part.children
                message = "HelicopterState"
                equals: str | None = None
                field_name = ""
                for child in middle:
                    if isinstance(child, lark.Token):
                        field_name = str(child)
                    elif child.data == "message_type":
                        message = str(child.children[0])
                    else:
                        equals = json.loads(str(child.children[0]))
                source = TopicSource(json.loads(str(topic)), field_name, message, equals)
            else:
                function, *labels = part.children
                inputs = tuple(_label(lbl) for lbl in labels if isinstance(lbl, lark.Tree))
                source = FunctionSource(str(function), inputs)
        return StreamDecl(
            _label(label_tree), _feature(feature), source, policy, decl.meta.line, decl.meta.column
        )

    def _policy(self, tree: _Tree) -> Policy:
        settings: dict[str, object] = {}
        for item in tree.children:
            assert isinstance(item, lark.Tree)
            token = item.children[0] if item.children else None
            kind = str(item.data)
            if kind in ("ordered", "unordered"):
                settings["ordered"] = kind == "ordered"
            elif kind == "change_only":
                settings["change_only"] = True
                settings["change_threshold"] = float(str(token)) if token is not None else 0.0
            elif kind == "period":
                settings["sample_period_ms"] = int(str(token))
            elif kind == "max_delay":
                settings["max_delay_ms"] = int(str(token))
            else:
                assert isinstance(token, lark.Token)
                settings[kind] = self._choice(kind, token)
        try:
            return Policy(**settings)  # type: ignore[arg-type]
        except StreamError as exc:
            raise self._error(str(exc), tree) from None

    def _choice(self, kind: str, token: lark.Token) -> MissingHandling | LateHandling:
        options = MissingHandling if kind == "missing" else LateHandling
        try:
            return options(str(token))
        except ValueError:
            allowed = ", ".join(o.value for o in options)
            raise self._error(
                f"unknown {kind} handling {str(token)!r}; use {allowed}", token
            ) from None


def _names(tree: _Tree) -> tuple[str, ...]:
    return tuple(str(token) for token in tree.children)


def _label(tree: _Tree) -> str:
    token = tree.children[0]
    assert isinstance(token, lark.Token)
    return json.loads(str(token)) if token.type == "ESCAPED_STRING" else str(token)


def _feature(tree: _Tree) -> FeatureTerm:
    name, *rest = tree.children
    args = _names(rest[0]) if rest and isinstance(rest[0], lark.Tree) else ()
    return FeatureTerm(str(name), args)
