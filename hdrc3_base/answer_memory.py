"""Answers remembered by request key, so that a command sent again is not run twice.

A ROS 2 service answer can be lost although its request arrived: Fast DDS waits at most 100 ms
for the server's response writer to match a new client's response reader and then drops the
answer (ENVIRONMENT.md). A client that got no answer cannot tell a lost request from a lost
answer, and sending a command again blindly could run it twice. FCL/PPCL command requests
therefore carry an optional ``request_key`` (an idempotency key, as in HTTP's
``Idempotency-Key``): the server answers a key it knows with the answer it gave first, and runs
the command only once.

The memory is bounded (the oldest keys are forgotten first) and lives as long as the server
process: a key sent again after a server restart runs the command again (the Platform Server
ends every command of its old incarnation FAILED, see its README).
"""

from __future__ import annotations

import uuid
from collections import OrderedDict
from collections.abc import Callable
from typing import Any, Generic, TypeVar

from hdrc3_base.errors import ConfigError

Answer = TypeVar("Answer")

MAX_KEY_LENGTH = 64
"""Longest accepted ``request_key``; a longer one is refused with NOT_ACCEPTED."""
CAPACITY = 1024
"""Keys remembered per server: far more than the calls a client can have in flight."""
RESEND_S = 2.0
"""How long a client waits for an answer before it sends a keyed request again."""


def keyed(request: Any) -> bool:
    """Whether a service request carries a ``request_key`` (the FCL/PPCL commands do)."""
    return "request_key" in request.get_fields_and_field_types()


def new_request_key() -> str:
    """A fresh request key (random, 32 hex digits)."""
    return uuid.uuid4().hex


def ensure_key(request: Any) -> bool:
    """Give a command request without a key a fresh one; whether the request is keyed."""
    if not keyed(request):
        return False
    request.request_key = request.request_key or new_request_key()
    return True


def key_problem(key: str) -> str | None:
    """Why ``key`` cannot be a request key, or None when it can (the empty key means "none")."""
    if len(key) > MAX_KEY_LENGTH:
        return f"request_key: {len(key)} characters, at most {MAX_KEY_LENGTH}"
    return None


class AnswerMemory(Generic[Answer]):
    """The first answer to each (service, key), for the last ``capacity`` keys."""

    def __init__(self, capacity: int = CAPACITY) -> None:
        if capacity < 1:
            raise ConfigError(f"capacity must be positive, not {capacity}")
        self._capacity = capacity
        self._answers: OrderedDict[tuple[str, str], Answer] = OrderedDict()

    def __len__(self) -> int:
        return len(self._answers)

    def recall(self, service: str, key: str) -> Answer | None:
        """The answer given first to ``key`` on ``service``, or None if the key is new."""
        return self._answers.get((service, key))

    def remember(self, service: str, key: str, answer: Answer) -> None:
        """Keep ``answer`` as the answer to ``key`` on ``service``; forget the oldest if full."""
        self._answers[(service, key)] = answer
        self._answers.move_to_end((service, key))
        while len(self._answers) > self._capacity:
            self._answers.popitem(last=False)


Handler = Callable[[Any, Any], Any]
"""An rclpy service callback: ``(request, response) -> response``."""


def remembering(
    memory: AnswerMemory[Any], service: str, handler: Handler, refuse: Callable[[Any, str], None]
) -> Handler:
    """``handler`` behind ``memory``: a known ``request_key`` gets its first answer again.

    Args:
        memory: The server's answers by key.
        service: The service's name (keys are per service).
        handler: The service callback; it runs once per key.
        refuse: Writes a refusal with a reason into a response (a key that is too long).
    """

    def serve(request: Any, response: Any) -> Any:
        key = str(request.request_key)
        problem = key_problem(key)
        if problem is not None:
            refuse(response, problem)
            return response
        if not key:
            return handler(request, response)
        known = memory.recall(service, key)
        if known is not None:
            return known
        answer = handler(request, response)
        memory.remember(service, key, answer)
        return answer

    return serve
