"""ROS 2 interface types by name: Python classes and full `ros2msg` definition texts.

MCAP files in the rosbag2 layout carry, per channel, a schema named ``pkg/msg/Type`` whose data is
the message's ``.msg`` text followed by every nested type's text (each after a separator line and
``MSG: pkg/Type``). This module builds that text from the ``share/<pkg>/msg/*.msg`` files installed
in the environment, and resolves type names to the generated Python classes.
"""

from __future__ import annotations

import importlib
import os
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

from hdrc3_base.errors import Hdrc3Error

SEPARATOR = "=" * 80
_PRIMITIVES = frozenset(
    {
        "bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16", "uint16",
        "int32", "uint32", "int64", "uint64", "string", "wstring",
    }
)  # fmt: skip
_TYPE_NAME = re.compile(r"^(?P<pkg>[A-Za-z][\w]*)/(?:msg/)?(?P<name>[A-Za-z][\w]*)$")
_ARRAY_SUFFIX = re.compile(r"(\[[^\]]*\])$")
_BOUND_SUFFIX = re.compile(r"<=\d+$")
_CONSTANT = re.compile(r"^\S+\s+[A-Za-z]\w*\s*=")


class MessageTypeError(Hdrc3Error):
    """A message type name is malformed, or its class or definition cannot be found."""


@dataclass(frozen=True, slots=True)
class MessageTypeName:
    """A message type name split into package and type, e.g. ``std_msgs/msg/String``."""

    package: str
    name: str

    @classmethod
    def parse(cls, text: str) -> MessageTypeName:
        """Parse ``pkg/msg/Type`` or ``pkg/Type``."""
        match = _TYPE_NAME.match(text.strip())
        if match is None:
            raise MessageTypeError(f"not a message type name: {text!r} (expected pkg/msg/Type)")
        return cls(match["pkg"], match["name"])

    def __str__(self) -> str:
        return f"{self.package}/msg/{self.name}"

    @property
    def short(self) -> str:
        """The ``pkg/Type`` form used after ``MSG:`` in definition texts."""
        return f"{self.package}/{self.name}"


def message_class(type_name: str) -> type:
    """Import and return the generated Python class of a message type."""
    parsed = MessageTypeName.parse(type_name)
    try:
        module = importlib.import_module(f"{parsed.package}.msg")
        cls: type = getattr(module, parsed.name)
    except (ImportError, AttributeError) as exc:
        raise MessageTypeError(f"message type {parsed} is not installed ({exc})") from exc
    return cls


def constant_names(cls: type, prefix: str) -> dict[int, str]:
    """A message's constants ``PREFIX_NAME = value`` as value -> readable name.

    E.g. ``PfcState``'s ``MODE_GROUND_IDLE = 2`` -> ``{2: "ground idle", ...}``.
    """
    return {
        getattr(cls, name): name.removeprefix(prefix).lower().replace("_", " ")
        for name in dir(cls)
        if name.startswith(prefix) and isinstance(getattr(cls, name), int)
    }


def share_directories() -> list[Path]:
    """Install prefixes' ``share`` directories, AMENT_PREFIX_PATH first, then this venv."""
    prefixes = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    prefixes.append(sys.prefix)
    seen: list[Path] = []
    for prefix in prefixes:
        share = Path(prefix) / "share"
        if share.is_dir() and share not in seen:
            seen.append(share)
    return seen


@dataclass
class DefinitionResolver:
    """Finds ``.msg`` texts and assembles full definitions; caches what it has read."""

    search_path: list[Path] = field(default_factory=share_directories)
    _texts: dict[MessageTypeName, str] = field(default_factory=dict, init=False, repr=False)

    def own_text(self, type_name: MessageTypeName) -> str:
        """Return the ``.msg`` file text of one type (without nested types)."""
        cached = self._texts.get(type_name)
        if cached is not None:
            return cached
        for share in self.search_path:
            path = share / type_name.package / "msg" / f"{type_name.name}.msg"
            if path.is_file():
                text = path.read_text(encoding="utf-8")
                self._texts[type_name] = text
                return text
        searched = ", ".join(str(s) for s in self.search_path) or "(nothing)"
        raise MessageTypeError(f"no definition file for {type_name} under {searched}")

    def full_definition(self, type_name: str) -> str:
        """Return the rosbag2-style full definition: own text plus every nested type once."""
        root = MessageTypeName.parse(type_name)
        parts = [self.own_text(root).rstrip("\n")]
        seen = {root}
        pending = list(field_types(parts[0], root.package))
        while pending:
            nested = pending.pop(0)
            if nested in seen:
                continue
            seen.add(nested)
            text = self.own_text(nested).rstrip("\n")
            parts.append(f"{SEPARATOR}\nMSG: {nested.short}\n{text}")
            pending.extend(field_types(text, nested.package))
        return "\n".join(parts) + "\n"


def field_types(msg_text: str, package: str) -> list[MessageTypeName]:
    """List the non-primitive field types of a ``.msg`` text, in order of appearance.

    Args:
        msg_text: Contents of one ``.msg`` file.
        package: Package the text belongs to (unqualified type names resolve to it).

    """
    found: list[MessageTypeName] = []
    for raw in msg_text.splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        tokens = line.split()
        if len(tokens) < 2 or _CONSTANT.match(line):
            continue  # a constant, or not a field
        base = _BOUND_SUFFIX.sub("", _ARRAY_SUFFIX.sub("", tokens[0]))
        if base in _PRIMITIVES:
            continue
        if base == "Header":
            found.append(MessageTypeName("std_msgs", "Header"))
        elif "/" in base:
            found.append(MessageTypeName.parse(base))
        else:
            found.append(MessageTypeName(package, base))
    return found
