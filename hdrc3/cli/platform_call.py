"""One FCL/PPCL call and the wait for its completion, shared by ``hdrc3 fcl`` and ``hdrc3 ppcl``.

Prints ``LABEL: CODE (command N)[: reason]`` for the answer, then one such line per progress
event and for the terminal event.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from hdrc3_base.errors import ConfigError
from hdrc3_platform_server.codes import EventKind
from hdrc3_platform_server.completion import CompletionEvent

if TYPE_CHECKING:  # the client pulls in rclpy: not at import time of the CLI's argument parsing
    from hdrc3_platform_server.client import PlatformClient

ANSWER_WAIT_S = 30.0
"""Longest wall-clock wait for the immediate answer (the --timeout is for the completion).

A server that is up answers within milliseconds, but a new client on 2 cores loaded by the
simulator, the renderer and other jobs has waited more than 10 s (seen in the image tests).
"""


def numbers(command: str, texts: Sequence[str]) -> tuple[float, ...]:
    """The command's words as numbers (ConfigError naming the command otherwise)."""
    try:
        return tuple(float(t) for t in texts)
    except ValueError:
        raise ConfigError(f"{command}: arguments must be numbers, got {list(texts)}") from None


def check_timeout(seconds: float) -> None:
    """ConfigError unless ``--timeout`` is a positive finite number of seconds."""
    if not (math.isfinite(seconds) and seconds > 0):
        raise ConfigError(f"--timeout must be > 0, got {seconds}")


def _line(label: str, name: str, command_id: int, reason: str) -> None:
    print(f"{label}: {name} (command {command_id}){': ' + reason if reason else ''}", flush=True)


def call(
    client: PlatformClient,
    label: str,
    service: tuple[Any, str, Any],
    codes: type[enum.IntEnum],
    prefix: str,
    timeout: float,
) -> Any | None:
    """Call ``(type, name, request)``, print the answer named from ``codes``; None: no answer."""
    srv, name, request = service
    response = client.call(srv, name, request, min(timeout, ANSWER_WAIT_S))
    if response is None:
        print(f"{label}: no answer from the platform server", flush=True)
        return None
    result = response.result
    try:
        name = prefix + codes(int(result.code)).name
    except ValueError:  # a code of a newer server: shown as its number
        name = str(result.code)
    _line(label, name, result.command_id, result.reason)
    return response


def wait(
    client: PlatformClient,
    label: str,
    command_id: int,
    timeout: float,
    kind_name: Callable[[EventKind], str],
) -> int:
    """Print the events of ``command_id`` until its terminal one: exit 0 only if it finished."""

    def show(event: CompletionEvent) -> None:
        _line(label, kind_name(event.kind), command_id, event.reason)

    final = client.wait_final(command_id, timeout, show)
    if final is None:
        print(f"{label}: no completion event within {timeout:g} s", flush=True)
        return 1
    show(final)
    return 0 if final.kind is EventKind.FINISHED else 1
