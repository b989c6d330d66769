"""The server's memory of first answers by request key."""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from hdrc3_base.answer_memory import (
    MAX_KEY_LENGTH,
    AnswerMemory,
    ensure_key,
    key_problem,
    new_request_key,
    remembering,
)
from hdrc3_base.errors import ConfigError


@pytest.mark.parametrize(
    ("key", "problem"),
    [
        ("", None),  # no key: the request is not remembered
        ("k" * MAX_KEY_LENGTH, None),
        ("k" * (MAX_KEY_LENGTH + 1), f"request_key: 65 characters, at most {MAX_KEY_LENGTH}"),
        ("0123456789abcdef0123456789abcdef", None),  # as new_request_key() makes them
    ],
)
def test_key_problem(key: str, problem: str | None) -> None:
    assert key_problem(key) == problem


def test_new_keys_differ_and_are_accepted() -> None:
    keys = {new_request_key() for _ in range(100)}
    assert len(keys) == 100 and all(key_problem(k) is None and len(k) == 32 for k in keys)


@pytest.mark.parametrize(
    ("remembered", "asked", "expected"),
    [
        ([("fcl/takeoff", "a", 1)], ("fcl/takeoff", "a"), 1),
        ([("fcl/takeoff", "a", 1), ("fcl/takeoff", "a", 2)], ("fcl/takeoff", "a"), 2),
        ([("fcl/takeoff", "a", 1)], ("fcl/land", "a"), None),  # keys are per service
        ([("fcl/takeoff", "a", 1)], ("fcl/takeoff", "b"), None),
        ([], ("fcl/takeoff", "a"), None),
    ],
)
def test_recall(
    remembered: list[tuple[str, str, int]], asked: tuple[str, str], expected: int | None
) -> None:
    memory: AnswerMemory[int] = AnswerMemory()
    for service, key, answer in remembered:
        memory.remember(service, key, answer)
    assert memory.recall(*asked) == expected


def test_the_oldest_keys_are_forgotten_first() -> None:
    memory: AnswerMemory[int] = AnswerMemory(capacity=3)
    for i in range(5):
        memory.remember("fcl/yaw", str(i), i)
    assert len(memory) == 3
    assert [memory.recall("fcl/yaw", str(i)) for i in range(5)] == [None, None, 2, 3, 4]


def test_capacity_must_be_positive() -> None:
    with pytest.raises(ConfigError, match="capacity"):
        AnswerMemory(capacity=0)


@dataclass
class _Request:
    request_key: str = ""


@dataclass
class _Response:
    reason: str = ""
    run: int = 0


@pytest.mark.parametrize(
    ("keys", "runs", "reasons"),
    [
        (["", ""], [1, 2], ["", ""]),  # no key: every request runs
        (["a", "a", "a"], [1, 1, 1], ["", "", ""]),  # one key: runs once, first answer thrice
        (["a", "b"], [1, 2], ["", ""]),
        (["k" * 65], [0], ["request_key: 65 characters, at most 64"]),
    ],
)
def test_remembering_runs_a_keyed_request_once(
    keys: list[str], runs: list[int], reasons: list[str]
) -> None:
    calls: list[int] = []

    def handler(request: _Request, response: _Response) -> _Response:
        calls.append(1)
        response.run = len(calls)
        return response

    def refuse(response: _Response, reason: str) -> None:
        response.reason = reason

    serve = remembering(AnswerMemory(), "fcl/takeoff", handler, refuse)
    answers = [serve(_Request(key), _Response()) for key in keys]
    assert [a.run for a in answers] == runs
    assert [a.reason for a in answers] == reasons


@dataclass
class _Query:
    """A request type without a key (``get_fields_and_field_types`` as rosidl generates it)."""

    @classmethod
    def get_fields_and_field_types(cls) -> dict[str, str]:
        return {}


@dataclass
class _Command:
    request_key: str = ""

    @classmethod
    def get_fields_and_field_types(cls) -> dict[str, str]:
        return {"request_key": "string"}


def test_ensure_key_keys_commands_once_and_leaves_queries() -> None:
    command = _Command()
    assert ensure_key(command) and key_problem(command.request_key) is None
    first = command.request_key
    assert ensure_key(command) and command.request_key == first  # a resend keeps its key
    given = _Command("mine")
    assert ensure_key(given) and given.request_key == "mine"
    assert not ensure_key(_Query())
