"""Planned fly-to: plan, stream, replan on a world change (real planner, scripted platform)."""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np
import pytest

from hdrc3_control.path_segment import PathSegment
from hdrc3_navigation.audit import WorldAudit
from hdrc3_navigation.gis import Zone
from hdrc3_navigation.planner import PathPlanner, PlanRequest
from hdrc3_navigation.runtime_world import RuntimeWorld
from hdrc3_platform_server.codes import FclCommand
from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_tst.actions import ACTIONS
from hdrc3_tst.executor import ActionContext, Progress, Status, Stepper
from hdrc3_tst.fake_platform import FakePathFollowing, FakePlatform
from hdrc3_tst.navigation_port import LocalNavigation, PlanJob
from hdrc3_tst.planned_flight import ANSWER_WAIT_S
from hdrc3_tst.platform_port import Command, PlatformState
from hdrc3_tst.rmax_executors import RMAX_EXECUTORS
from sim.world import World

WEST, EAST = (-60.0, 0.0, 15.0), (60.0, 0.0, 15.0)
"""Either side of the small world's wall: the path goes around it (tests/unit/conftest.py)."""
FRAME = frame_from_world("revinge")  # only converts straight fly-to goals (not used here)
TICK = 0.5
MARGIN = 6.0


def segment_of(command: Command) -> PathSegment:
    a = command.args
    return PathSegment(
        (a["start_x"], a["start_y"], a["start_z"]),
        (a["end_x"], a["end_y"], a["end_z"]),
        (a["start_direction_x"], a["start_direction_y"], a["start_direction_z"]),
        (a["end_direction_x"], a["end_direction_y"], a["end_direction_z"]),
        a["velocity"],
        a["end_velocity"],
    )


class Flight:
    """A fly-to executor over the real planner and a scripted path-following platform."""

    def __init__(self, nav: LocalNavigation | None, goal: tuple[float, float, float]) -> None:
        self.platform = FakePlatform(PlatformState(*WEST, on_ground=False, autonomous=True))
        self.follow = FakePathFollowing(self.platform)
        self.ctx = ActionContext(
            "go", "uav0", ACTIONS["fly-to"], {"speed": 8.0, "destination": "Goal"},
            {"Goal": (goal,)}, self.platform, FRAME, 0.0, navigation=nav,
        )  # fmt: skip
        self.stepper = Stepper(RMAX_EXECUTORS["fly-to"](), self.ctx)
        self.now = 0.0
        self.notes: list[str] = []

    def step(self) -> Status:
        self.now += TICK
        status = self.stepper.step(self.now)
        self.notes += self.ctx.notes
        self.ctx.notes.clear()
        self.follow.tick()
        return status

    def fly(self, before_segment: Callable[[int], None] = lambda i: None) -> Status:
        """Step; fly one segment every other tick, calling ``before_segment(index)`` first.

        The executor sees what the hook changed for one tick before the segment is flown.
        """
        for tick in range(2000):
            if tick % 2 and self.follow.flying is not None:
                before_segment(len(self.follow.flown))
                status = self.step()
                if status.progress is not Progress.RUNNING:
                    return status
                self.follow.advance()
            status = self.step()
            if status.progress is not Progress.RUNNING:
                return status
        raise AssertionError("the flight did not end")

    def flown(self) -> list[PathSegment]:
        return [segment_of(c) for c in self.follow.flown]

    def traj3d(self) -> list[Command]:
        return [c for c in self.platform.sent if c.command is FclCommand.TRAJ3D]


def audit(world: World, segments: list[PathSegment], zones: tuple[Zone, ...] = ()) -> list:  # type: ignore[type-arg]
    extra = [(z.name, z.polygon, z.floor, z.ceiling) for z in zones]
    return WorldAudit(world, extra).check_segments(segments, MARGIN - 0.05)


def test_a_fly_to_streams_the_planned_path_around_the_wall(
    planner: PathPlanner, small_world: World
) -> None:
    flight = Flight(LocalNavigation(planner), EAST)
    status = flight.fly()
    assert status.progress is Progress.SUCCEEDED, status.reason
    flown = flight.flown()
    assert flown[0].start == WEST and flown[-1].end == EAST
    assert all(np.allclose(a.end, b.start) for a, b in itertools.pairwise(flown))
    assert audit(small_world, flown) == []
    assert len(flight.traj3d()) == len(flown)  # nothing replaced, nothing resent
    assert any(note.startswith("planned ") for note in flight.notes)


def zone_across(segment: PathSegment, s: float = 0.5, half: float = 4.0) -> Zone:
    """A square no-fly zone (all heights) centred on ``segment`` at parameter ``s``."""
    e, n, _ = segment.position(s)
    return Zone("new", ((e - half, n - half), (e + half, n - half), (e + half, n + half),
                        (e - half, n + half)))  # fmt: skip


@pytest.mark.parametrize(
    ("where", "expect"),
    [
        # a zone on a segment after the queued one: the replan joins the segment in flight
        ("later", "replan: "),
        # a zone on the segment in flight: brake to a hover, plan anew from there
        ("in_flight", "stop: "),
    ],
)
def test_a_zone_added_in_flight_is_never_entered(
    planner: PathPlanner, small_world: World, where: str, expect: str
) -> None:
    plan = planner.plan(PlanRequest(WEST, EAST, 8.0, timeout=5.0))
    assert plan.ok and len(plan.segments) >= 3, plan.reason
    flight = Flight(LocalNavigation(planner), EAST)
    added: list[Zone] = []

    def add_zone(index: int) -> None:
        if index == 1 and not added:  # segment 1 is about to be flown, segment 2 is queued
            target = flight.follow.flying if where == "in_flight" else None
            if target is None:  # on the last segment, well after the queued one's start
                added.append(zone_across(plan.segments[-1], 0.6))
            else:
                added.append(zone_across(segment_of(target)))
            planner.gis.add_no_fly_zone(added[0])

    status = flight.fly(add_zone)
    assert status.progress is Progress.SUCCEEDED, status.reason
    assert added and any(note.startswith(expect) for note in flight.notes), flight.notes
    flown = flight.flown()
    assert audit(small_world, flown, tuple(added)) == []
    assert flown[-1].end == EAST


def test_a_replacement_goes_out_while_a_segment_is_queued(
    planner: PathPlanner,
) -> None:
    plan = planner.plan(PlanRequest(WEST, EAST, 8.0, timeout=5.0))
    flight = Flight(LocalNavigation(planner), EAST)

    def add_zone(index: int) -> None:
        if index == 1 and flight.follow.queued is not None and not planner.gis.no_fly_zones[1:]:
            planner.gis.add_no_fly_zone(zone_across(plan.segments[-1], 0.6))

    assert flight.fly(add_zone).progress is Progress.SUCCEEDED
    replaced = [c for c in flight.traj3d() if "replaced by segment" in c.reason]
    assert len(replaced) == 1  # the queued segment was replaced, not braked for


@pytest.mark.parametrize(
    ("goal", "zone", "reason"),
    [
        ((0.0, 0.0, 15.0), None, "goal_in_obstacle"),  # inside the wall
        ((60.0, -60.0, 15.0), None, "goal_in_no_fly_zone"),  # the world's zone
        (
            EAST,
            Zone("late", ((50.0, -10.0), (70.0, -10.0), (70.0, 10.0), (50.0, 10.0))),
            "goal_in_no_fly_zone",
        ),  # a zone declared around the goal during the flight
    ],
)
def test_an_unreachable_goal_fails_the_node_with_the_planners_reason(
    planner: PathPlanner, goal: tuple[float, float, float], zone: Zone | None, reason: str
) -> None:
    flight = Flight(LocalNavigation(planner), goal)

    def add_zone(index: int) -> None:
        if zone is not None and index == 1 and zone not in planner.gis.no_fly_zones:
            planner.gis.add_no_fly_zone(zone)

    status = flight.fly(add_zone)
    assert status.progress is Progress.FAILED and reason in status.reason, status.reason
    assert flight.follow.flying is None or flight.follow.flying.state.ended


class SilentNavigation:
    """A planner that never answers."""

    def plan(self, request: PlanRequest) -> PlanJob:
        return PlanJob(request)

    def world(self) -> RuntimeWorld:
        return RuntimeWorld()


def test_a_planner_that_never_answers_fails_the_node_at_its_bound() -> None:
    flight = Flight(None, EAST)
    flight.ctx.navigation = SilentNavigation()
    status = flight.fly()
    assert status.progress is Progress.FAILED and "did not answer" in status.reason
    assert ANSWER_WAIT_S <= flight.now <= ANSWER_WAIT_S + 2 * TICK
    assert flight.traj3d() == []


def test_without_a_path_planner_fly_to_goes_straight() -> None:
    flight = Flight(None, EAST)
    flight.step()
    assert [c.command for c in flight.platform.sent] == [FclCommand.TRAJ3D_FLYTO]
