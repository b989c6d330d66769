"""The server's memory of first answers by request key."""

from __future__ import annotations

import pytest

from hdrc3_base.answer_memory import (
    MAX_KEY_LENGTH,
    AnswerMemory,
    key_problem,
    new_request_key,
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
