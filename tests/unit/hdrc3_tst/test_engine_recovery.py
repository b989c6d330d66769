"""Recovery in a planned goal node (chapter 9.3.1) on the fake platform with real TALplanner."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from hdrc3_platform_server.codes import FclCommand
from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_platform_server.hook_api import HookAction
from hdrc3_tst.check import CheckStatus, load_text
from hdrc3_tst.distribution import bind_open_agents
from hdrc3_tst.engine import EngineContext, ExecutionEngine
from hdrc3_tst.fake_platform import FakePlatform, RecordingSink, SolvingPlanner
from hdrc3_tst.goal_planning import Load
from hdrc3_tst.model import NodeState
from hdrc3_tst.payload_executors import PICK_ATTEMPTS
from hdrc3_tst.platform_port import Command, PlatformState, Sighting
from hdrc3_tst.recovery import RecoveryStep, Violation, default_recovery
from hdrc3_tst.recovery_spec import RecoverySpec, RecoverySpecParser
from hdrc3_tst.rmax_executors import RMAX_EXECUTORS

FRAME = frame_from_world("revinge")
MISSION = """world revinge
agents uav0
point box1 = box1 at 0
point Depot = supply_depot at 20
point Field = west_field at 20
m(P, TS, TE) = goal at(box1, Field) where P = uav0
"""
LOADS = (Load("box1", "food-box", "Depot", 5.0),)
BOX_LOST = Violation("held@m/3", "box-lost", True, {"av": "uav0", "box": "box1"})
MISSED = "FAILED the magnet gripped nothing"


class Rig:
    """One engine on the fake platform; the planner is TALplanner itself."""

    def __init__(
        self,
        recovery: RecoverySpec | None = None,
        misses: int = 0,
        mission: str = MISSION,
        loads: tuple[Load, ...] = LOADS,
    ) -> None:
        """``misses``: how many attaches of the magnet grip nothing, the first ones."""
        loaded = load_text(mission)
        assert loaded.status is CheckStatus.OK, loaded.diagnostics
        assert loaded.tst is not None
        bind_open_agents(loaded.tst, "uav0")
        self.platform, self.planner, self.sink = FakePlatform(), SolvingPlanner(), RecordingSink()
        self.platform.sample = PlatformState(-50.0, 0.0, 20.0, on_ground=False, autonomous=True)
        ctx = EngineContext(
            "uav0",
            self.platform,
            self.planner,
            self.sink,
            FRAME,
            RMAX_EXECUTORS,
            loads=loads,
            recovery=recovery or default_recovery(),
        )
        self.misses = misses
        self.engine = ExecutionEngine("m", loaded.tst, ctx)
        self.t = 1000.0
        assert self.engine.execute("m", self.t, self.t) == ""
        self.run_until(lambda: bool(self.engine.tst.tree.node("m").children))

    def run_until(self, done: Callable[[], bool], limit: int = 600) -> None:
        """Tick once a second, completing every command (the hook camera sees every load
        below)."""
        loads = [load.name for load in self.engine.ctx.loads]
        for _ in range(limit):
            if done():
                return
            self.t += 1.0
            for tag in loads:
                self.platform.sightings[tag] = Sighting((0.0, 0.0, -5.0), self.t)
            self.engine.tick(self.t)
            for command in self.platform.running():
                self.complete(command)
        raise AssertionError(f"not done after {limit} s: {self.sink.statuses[-3:]}")

    def complete(self, command: Command) -> None:
        if command.command is FclCommand.TRAJ3D and not command.segment_requested:
            command.segment_requested = True
            return
        if command.command is HookAction.ATTACH and self.misses > 0:
            self.misses -= 1
            self.platform.complete(command, ok=False, reason=MISSED)
            return
        self.platform.complete(command)

    def state(self, node: str) -> NodeState:
        return self.engine.records[node].state

    def steps(self) -> list[RecoveryStep]:
        return [r.step for r in self.sink.recoveries]

    def running_step(self) -> str:
        """The planned step running now ("" for none)."""
        running = (
            r.node_id
            for r in self.engine.records.values()
            if r.node_id.startswith("m/") and r.state is NodeState.RUNNING
        )
        return next(running, "")


def actions(rig: Rig, prefix: str) -> list[str]:
    goal = rig.engine.tst.tree.node("m")
    tree = rig.engine.tst.tree
    return [tree.node(c.node_id).action for c in goal.children if c.node_id.startswith(prefix)]


def test_a_lost_box_is_picked_up_again_and_delivered() -> None:
    rig = Rig()
    assert actions(rig, "m/") == ["fly-to", "pick-up-box", "fly-to", "drop-box"]
    assert rig.planner.requests[0].control  # load goals plan with the control rules
    rig.run_until(lambda: rig.state("m/3") is NodeState.RUNNING)
    rig.platform.move_to((10.0, 5.0, 20.0))  # where the aircraft's estimate is at the drop
    report = rig.engine.on_violation(BOX_LOST, "m/3")
    assert report.step is RecoveryStep.APPLY_OPERATOR
    assert report.changes == ("at(box1, recover_uav0_1)",)
    assert rig.state("m/3") is NodeState.ABORTED
    assert rig.state("m") is NodeState.RUNNING
    brake = rig.platform.sent[-1]
    assert brake.command is FclCommand.EMERGENCY_BRAKE
    assert len(rig.planner.requests) == 1  # planning waits for the brake to end
    rig.run_until(lambda: len(rig.planner.requests) == 2)
    assert "init at(box1, recover_uav0_1)" in rig.planner.requests[1].problem
    rig.run_until(lambda: rig.steps()[-1] is RecoveryStep.REPLAN)
    assert rig.steps() == [
        RecoveryStep.SUSPEND,
        RecoveryStep.BRAKE,
        RecoveryStep.HOVER,
        RecoveryStep.APPLY_OPERATOR,
        RecoveryStep.REPLAN,
    ]
    assert rig.sink.recoveries[-1].plan == (
        "(pick-up-box uav0 box1 recover_uav0_1)",
        "(fly-to uav0 recover_uav0_1 Field)",
        "(drop-box uav0 box1 Field)",
    )
    assert actions(rig, "m/2.") == ["pick-up-box", "fly-to", "drop-box"]
    assert rig.engine.tst.places["box1"].coords == ((10.0, 5.0, 20.0),)
    rig.run_until(lambda: rig.state("m").finished)
    assert rig.state("m") is NodeState.SUCCEEDED, rig.engine.records["m"].reason
    assert rig.state("m/2.3") is NodeState.SUCCEEDED


def test_the_goal_gives_up_after_repeated_failures_on_the_same_fault() -> None:
    rig = Rig()
    rig.run_until(lambda: rig.state("m/3") is NodeState.RUNNING)
    for attempt in range(1, 4):
        report = rig.engine.on_violation(BOX_LOST, rig.running_step())
        assert (report.step, report.attempt) == (RecoveryStep.APPLY_OPERATOR, attempt)
        rig.run_until(lambda: rig.steps()[-1] is RecoveryStep.REPLAN)
        rig.run_until(lambda: bool(rig.running_step()))
    report = rig.engine.on_violation(BOX_LOST, "")
    assert report.step is RecoveryStep.GIVE_UP
    assert rig.state("m") is NodeState.FAILED
    reason = rig.engine.records["m"].reason
    assert "failed 4 times on the same fault (box-lost recovers from 3)" in reason


def test_a_violation_outside_any_planned_goal_is_ignored() -> None:
    rig = Rig()
    report = rig.engine.on_violation(BOX_LOST, "elsewhere")
    assert report.step is RecoveryStep.IGNORED
    assert rig.state("m") is NodeState.RUNNING
    assert all(c.command is not FclCommand.EMERGENCY_BRAKE for c in rig.platform.sent)
    assert rig.sink.recoveries == [report]


@pytest.mark.parametrize(
    ("failed_pick_ups", "outcome", "recoveries", "reason"),
    [
        # all lowerings of the first pick-up missed: planned again, picked up, delivered
        (1, NodeState.SUCCEEDED, 1, ""),
        (2, NodeState.SUCCEEDED, 2, ""),
        # the operator plans again twice; the third failed pick-up fails the goal, saying why
        (
            3,
            NodeState.FAILED,
            3,
            "failed 3 times on the same fault (step-failed recovers from 2); "
            "last: m/3.2 (pick-up-box) failed: ppcl_hook: FAILED the magnet gripped nothing",
        ),
    ],
)
def test_a_failed_step_is_planned_again_until_the_operator_gives_up(
    failed_pick_ups: int, outcome: NodeState, recoveries: int, reason: str
) -> None:
    rig = Rig(misses=failed_pick_ups * PICK_ATTEMPTS)
    rig.run_until(lambda: rig.state("m").finished)
    assert rig.state("m") is outcome, rig.engine.records["m"].reason
    assert reason in rig.engine.records["m"].reason
    suspended = [r for r in rig.sink.recoveries if r.step is RecoveryStep.SUSPEND]
    assert [r.monitor_id.split("@")[0] for r in suspended] == ["step-failed"] * recoveries
    assert all(c.command is not FclCommand.EMERGENCY_BRAKE for c in rig.platform.sent)
    if outcome is NodeState.SUCCEEDED:
        # planned from where the aircraft hovers: to the depot again, the box, the field
        assert actions(rig, f"m/{recoveries + 1}.") == actions(rig, "m/")[:4]


def test_without_a_step_failed_operator_a_failed_step_fails_its_goal() -> None:
    rig = Rig(RecoverySpecParser().parse("recovery retry: replan;"), misses=PICK_ATTEMPTS)
    rig.run_until(lambda: rig.state("m").finished)
    assert rig.state("m") is NodeState.FAILED
    assert rig.engine.records["m"].reason == f"m/2 failed: ppcl_hook: {MISSED}"
    assert rig.sink.recoveries == []


CARRIER_MISSION = """world revinge
agents uav0
point carrier3 = carrier3 at 0
point box7 = box7 at 0
point box8 = box8 at 0
point Depot = carrier_depot at 20
point Field = west_field at 20
m(P, TS, TE) = with T1, T2, T3, T4 sequence
  first(T1, T2) = goal at(box7, Field);
  second(T3, T4) = goal at(box8, Field)
where P = uav0
"""
CARRIER_LOADS = (
    Load("carrier3", "carrier", "Depot", 28.0),
    Load("box7", "food-box", "Depot", 5.0, on="carrier3"),
    Load("box8", "food-box", "Depot", 5.0, on="carrier3"),
)
"""carrier3 with box7, box8 and two more boxes: 28 kg."""


def test_a_carrier_that_did_not_lift_leaves_boxes_behind_and_later_goals_know_it() -> None:
    rig = Rig(mission=CARRIER_MISSION, loads=CARRIER_LOADS)
    rig.run_until(lambda: bool(rig.engine.tst.tree.node("first").children))
    goal = rig.engine.tst.tree.node("first")
    planned = [rig.engine.tst.tree.node(c.node_id).action for c in goal.children]
    assert planned[:2] == ["fly-to", "attach-carrier"]  # 28 kg <= the assumed 30 kg
    rig.run_until(lambda: rig.state("first/2") is NodeState.RUNNING)
    stalled = Violation(
        "carrier_lifted@first/2", "carrier-too-heavy", False, {"carrier": "carrier3"}
    )
    report = rig.engine.on_violation(stalled, "first/2")
    assert report.changes == ("lift-capacity(uav0) = 22.4", "release(carrier3)")
    # the magnet lets go and the hook winds in before the goal is planned again
    assert rig.platform.sent[-1].command is HookAction.RELEASE
    assert len(rig.planner.requests) == 1
    rig.run_until(lambda: len(rig.planner.requests) == 2)
    hook = [c.command for c in rig.platform.sent if isinstance(c.command, HookAction)]
    assert hook[-2:] == [HookAction.RELEASE, HookAction.RAISE]
    rig.run_until(lambda: rig.steps()[-1] is RecoveryStep.REPLAN)
    replanned = [a.split()[0].strip("(") for a in rig.sink.recoveries[-1].plan]
    assert replanned[:2] == ["fly-to", "take-from-carrier"]  # back over it; box7 on the hook
    assert "attach-carrier" not in replanned
    rig.run_until(lambda: len(rig.planner.requests) == 3)  # the second goal
    second = rig.planner.requests[2].problem
    assert "lift-capacity(uav0) = 22.4" in second
    assert "init at(carrier3, Depot), load(carrier3) = 23, slots(carrier3) = 1" in second
    assert "init at(box7, Field), weight(box7) = 5" in second  # delivered by the first goal
    rig.run_until(lambda: rig.state("m").finished)
    assert rig.state("m") is NodeState.SUCCEEDED, rig.engine.records["m"].reason
