"""Shared pytest fixtures: isolated ROS 2 domains and private rclpy contexts.

Also the Hypothesis profiles. ``ci`` (the default, and what ``make test`` selects) is
derandomized with a fixed example count and no example database, so a run on a fresh clone draws
the same inputs every time; ``fuzz`` (``make fuzz``) draws thousands of examples per property
test from random seeds. Property tests carry no example counts of their own: the profile decides.
A bug that fuzzing finds is pinned with ``@example`` so that every ``ci`` run checks it.
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Iterator

import pytest
from hypothesis import HealthCheck, is_hypothesis_test, settings

# Timing must never fail a test: no deadline, no "too slow" health check (a loaded machine).
_UNTIMED = {"deadline": None, "suppress_health_check": [HealthCheck.too_slow]}
settings.register_profile("ci", derandomize=True, database=None, max_examples=300, **_UNTIMED)
settings.register_profile("fuzz", max_examples=2500, **_UNTIMED)
settings.load_profile("ci")  # `--hypothesis-profile=fuzz` on the command line replaces it


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Mark every Hypothesis test ``property`` (``make fuzz`` selects them)."""
    for item in items:
        if is_hypothesis_test(getattr(item, "obj", None)):
            item.add_marker(pytest.mark.property)


# Each xdist worker owns a disjoint block of domain ids so parallel tests never share a graph.
_DOMAIN_BLOCK = 20
# HDRC3_TEST_DOMAIN_BASE moves the whole block, so that two test runs on one machine never meet.
_DOMAIN_BASE = int(os.environ.get("HDRC3_TEST_DOMAIN_BASE", "10"))
_counter = itertools.count()


def _worker_index() -> int:
    worker = os.environ.get("PYTEST_XDIST_WORKER", "gw0")
    return int(worker.removeprefix("gw")) if worker.startswith("gw") else 0


@pytest.fixture
def ros_domain(monkeypatch: pytest.MonkeyPatch) -> int:
    """Give the test its own ROS_DOMAIN_ID and keep discovery on loopback.

    Subprocesses started by the test inherit both variables.
    """
    domain = _DOMAIN_BASE + _worker_index() * _DOMAIN_BLOCK + next(_counter) % _DOMAIN_BLOCK
    monkeypatch.setenv("ROS_DOMAIN_ID", str(domain))
    monkeypatch.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    return domain


@pytest.fixture
def ros_context(ros_domain: int) -> Iterator[object]:
    """A private, initialised rclpy Context on the test's own domain; shut down afterwards."""
    import rclpy
    from rclpy.context import Context

    context = Context()
    rclpy.init(context=context, domain_id=ros_domain)
    try:
        yield context
    finally:
        context.try_shutdown()
