"""What a flight executor may ask of navigation: a path, and the world model's runtime changes (§7).

The TST manager node gives executors a port over the agent's ``path_planner`` node
(``hdrc3_tst.ros_navigation``); tests and single-process tools use :class:`LocalNavigation`, the
same planner in-process. A query is asynchronous: :meth:`NavigationPort.plan` returns a
:class:`PlanJob` whose result arrives later, so an executor keeps yielding while it waits.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from hdrc3_navigation.planner import PathPlanner, PlanRequest, PlanResult
from hdrc3_navigation.runtime_world import RuntimeWorld


@dataclass
class PlanJob:
    """One path query; ``result`` is set when the planner answered."""

    request: PlanRequest
    result: PlanResult | None = None

    @property
    def done(self) -> bool:
        """The planner answered."""
        return self.result is not None


class NavigationPort(Protocol):
    """One agent's path planner, as executors use it."""

    def plan(self, request: PlanRequest) -> PlanJob:
        """Ask for a path; the job's result arrives later (or at once)."""

    def world(self) -> RuntimeWorld:
        """The runtime changes of the planner's world model known now (revision 0: none)."""


class LocalNavigation:
    """:class:`NavigationPort` over an in-process :class:`PathPlanner` (answers at once)."""

    def __init__(self, planner: PathPlanner) -> None:
        self.planner = planner

    def plan(self, request: PlanRequest) -> PlanJob:
        """Plan now."""
        return PlanJob(request, self.planner.plan(request))

    def world(self) -> RuntimeWorld:
        """The planner's GIS now."""
        return RuntimeWorld.of(self.planner.gis)
