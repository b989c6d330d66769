"""Planned fly-to: plan, stream, replan on a world change (real planner, scripted platform)."""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np
import pytest

from hdrc3_control.path_segment import PathSegment
from hdrc3_navigation.audit import WorldAudit
from hdrc3_navigation.gis import Zone
from hdrc3_navigation.planner import PathPlanner, PlanRequest, PlanResult, PlanStatus
from hdrc3_navigation.runtime_world import RuntimeWorld
from hdrc3_platform_server.codes import FclCommand
from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_tst.actions import ACTIONS
from hdrc3_tst.executor import ActionContext, Progress, Status, Stepper
from hdrc3_tst.fake_platform import FakePathFollowing, FakePlatform
from hdrc3_tst.navigation_port import LocalNavigation, PlanJob
from hdrc3_tst.planned_flight import ANSWER_WAIT_S, CLIMB_OUT_M
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


def farthest_from_the_ends(segments: tuple[PathSegment, ...]) -> tuple[PathSegment, float]:
    """The point of a path farthest from both its start and its goal (segment, parameter)."""
    candidates = [(seg, float(s)) for seg in segments for s in np.linspace(0.0, 1.0, 21)]
    ends = (np.array(segments[0].start), np.array(segments[-1].end))
    return max(
        candidates, key=lambda c: min(float(np.linalg.norm(c[0].position(c[1]) - e)) for e in ends)
    )


@pytest.mark.parametrize("after", [0, 1, 2])
def test_a_zone_added_in_flight_is_never_entered(
    planner: PathPlanner, small_world: World, after: int
) -> None:
    """Whatever the (random) roadmap's path, a zone across its middle is avoided.

    The zone is declared before segment ``after`` is flown, or the latest segment before it that
    starts at least 15 m from the zone and not after the segment the zone lies on; what is flown
    from then on must stay out of it.
    """
    plan = planner.plan(PlanRequest(WEST, EAST, 8.0, timeout=5.0))
    assert plan.ok, plan.reason
    flight = Flight(LocalNavigation(planner), EAST)
    segment, s = farthest_from_the_ends(plan.segments)
    zone = zone_across(segment, s, 3.0)
    centre = segment.position(s)
    last = plan.segments.index(segment)
    when = max(
        k for k in range(min(after, last) + 1)
        if float(np.linalg.norm(np.array(plan.segments[k].start) - centre)) > 15.0
    )  # fmt: skip
    declared: list[int] = []

    def add_zone(index: int) -> None:
        if index == when and not declared:
            planner.gis.add_no_fly_zone(zone)
            declared.append(index)

    status = flight.fly(add_zone)
    assert status.progress is Progress.SUCCEEDED, (status.reason, flight.notes)
    flown = flight.flown()
    assert flown[-1].end == EAST
    assert declared == [when]
    assert audit(small_world, flown[when:], (zone,)) == []
    assert [n for n in flight.notes if n.startswith(("replan: ", "stop: "))], flight.notes


def straight(*points: tuple[float, float, float]) -> list[PathSegment]:
    """Straight segments through ``points`` at 8 m/s, at rest only at the end."""
    pairs = list(itertools.pairwise(points))
    return [
        PathSegment.straight(a, b, 8.0, 0.0 if i == len(pairs) - 1 else 8.0, i)
        for i, (a, b) in enumerate(pairs)
    ]


class ScriptedNavigation:
    """Answers each query with the next scripted path; the test sets the world model."""

    def __init__(self, *paths: list[PathSegment]) -> None:
        self.paths = list(paths)
        self.requests: list[PlanRequest] = []
        self.runtime = RuntimeWorld()

    def plan(self, request: PlanRequest) -> PlanJob:
        self.requests.append(request)
        segments = tuple(self.paths.pop(0))
        return PlanJob(request, PlanResult(PlanStatus.SOLVED, "", segments, 1.0))

    def world(self) -> RuntimeWorld:
        return self.runtime

    def declare(self, *zones: Zone) -> None:
        self.runtime = RuntimeWorld(self.runtime.revision + 1, 2.0, zones)


A = (-60.0, 0.0, 15.0)
ROUTE = straight(A, (-20.0, 0.0, 15.0), (20.0, 0.0, 15.0), (60.0, 0.0, 15.0))
"""Three straight segments east; the last one crosses (40, 0)."""
AROUND = straight((20.0, 0.0, 15.0), (40.0, 30.0, 15.0), (60.0, 0.0, 15.0))
"""From the end of the second segment, north of (40, 0)."""
FROM_HOVER = straight((-20.0, 0.0, 15.0), (0.0, -30.0, 15.0), (60.0, 0.0, 15.0))
BLOCK_LAST = Zone("late", ((35.0, -5.0), (45.0, -5.0), (45.0, 5.0), (35.0, 5.0)))
BLOCK_SECOND = Zone("near", ((-5.0, -5.0), (5.0, -5.0), (5.0, 5.0), (-5.0, 5.0)))


@pytest.mark.parametrize(
    ("zone", "paths", "replan_start", "direction", "flown_ends", "note"),
    [
        # the zone lies after the queued segment: the replan leaves the end of the segment in
        # flight with its tangent and replaces the queued segment
        (BLOCK_LAST, (ROUTE, AROUND), (20.0, 0.0, 15.0), (40.0, 0.0, 0.0),
         [(-20.0, 0.0, 15.0), (20.0, 0.0, 15.0), (40.0, 30.0, 15.0), (60.0, 0.0, 15.0)],
         "replan: "),
        # the zone lies on the segment in flight: brake to a hover, plan from where it holds
        (BLOCK_SECOND, (ROUTE, FROM_HOVER), (-20.0, 0.0, 15.0), None,
         [(-20.0, 0.0, 15.0), (0.0, -30.0, 15.0), (60.0, 0.0, 15.0)], "stop: "),
    ],
)  # fmt: skip
def test_a_world_change_replans_where_the_chapter_says(
    zone: Zone,
    paths: tuple[list[PathSegment], ...],
    replan_start: tuple[float, float, float],
    direction: tuple[float, float, float] | None,
    flown_ends: list[tuple[float, float, float]],
    note: str,
) -> None:
    nav = ScriptedNavigation(*paths)
    flight = Flight(None, (60.0, 0.0, 15.0))
    flight.ctx.navigation = nav

    def declare(index: int) -> None:
        if index == 1 and not nav.runtime.no_fly_zones:  # segment 1 flies, segment 2 queued
            nav.declare(zone)

    status = flight.fly(declare)
    assert status.progress is Progress.SUCCEEDED, (status.reason, flight.notes)
    assert [r.start for r in nav.requests] == [A, replan_start]
    assert nav.requests[1].start_direction == direction
    assert [s.end for s in flight.flown()] == flown_ends
    assert any(n.startswith(note) for n in flight.notes), flight.notes
    replaced = [c for c in flight.traj3d() if "replaced by segment" in c.reason]
    stopped = [c for c, _ in flight.platform.stopped]
    if note == "replan: ":
        assert len(replaced) == 1 and stopped == []  # no braking: the queued one was replaced
    else:
        assert replaced == [] and len(stopped) == 2  # the one in flight and the queued one


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


def test_a_refused_replacement_brakes_and_plans_from_the_hover_point() -> None:
    nav = ScriptedNavigation(ROUTE, AROUND, AROUND)
    flight = Flight(None, (60.0, 0.0, 15.0))
    flight.ctx.navigation = nav
    flight.follow.replace = False

    def declare(index: int) -> None:
        if index == 1 and not nav.runtime.no_fly_zones:
            nav.declare(BLOCK_LAST)

    status = flight.fly(declare)
    assert status.progress is Progress.SUCCEEDED, (status.reason, flight.notes)
    assert [r.start for r in nav.requests] == [A, (20.0, 0.0, 15.0), (20.0, 0.0, 15.0)]
    assert any("replacement of the queued segment was refused" in n for n in flight.notes)
    assert (40.0, 0.0, 15.0) not in [s.end for s in flight.flown()]


def test_a_fly_to_where_the_aircraft_already_is_succeeds_without_a_flight() -> None:
    flight = Flight(None, (WEST[0] + 0.3, WEST[1], WEST[2]))
    flight.ctx.navigation = SilentNavigation()  # it must not even ask
    status = flight.fly()
    assert status.progress is Progress.SUCCEEDED
    assert flight.traj3d() == [] and flight.now <= 2 * TICK


def test_a_flight_from_a_hover_too_low_to_plan_from_climbs_straight_up_first(
    planner: PathPlanner,
) -> None:
    low = (WEST[0], WEST[1], FRAME.ground_up(WEST[0], WEST[1]) + 4.0)  # over a load it lifted
    flight = Flight(LocalNavigation(planner), EAST)
    flight.platform.move_to(low)
    for _ in range(4):  # the planner refuses the start
        flight.step()
    (climb,) = flight.platform.sent
    assert climb.command is FclCommand.TRAJ3D_FLYTO
    up = FRAME.to_wgs84(low[0], low[1], FRAME.ground_up(low[0], low[1]) + CLIMB_OUT_M)
    assert (climb.args["longitude"], climb.args["latitude"]) == pytest.approx(up[:2])
    assert climb.args["altitude"] == pytest.approx(up[2])
    flight.platform.move_to((low[0], low[1], low[2] - 4.0 + CLIMB_OUT_M))
    flight.platform.complete(climb)
    status = flight.fly()
    assert status == Status(Progress.SUCCEEDED), status.reason
    assert flight.flown()[-1].end == pytest.approx(EAST)
