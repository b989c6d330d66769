"""The execution engine on fakes: control semantics, timing, binding, abort, goals, queries."""

from __future__ import annotations

import math
from collections.abc import Callable, Generator
from pathlib import Path

import pytest

from hdrc3_platform_server.codes import FclCommand
from hdrc3_platform_server.geo_frame import frame_from_world
from hdrc3_tst.check import CheckStatus, load_file, load_text
from hdrc3_tst.distribution import bind_open_agents
from hdrc3_tst.engine import EngineContext, ExecutionEngine
from hdrc3_tst.executor import SUCCEEDED, ActionContext, ActionExecutor, Status
from hdrc3_tst.fake_platform import FakePlanner, FakePlatform, RecordingSink
from hdrc3_tst.model import NodeRef, NodeState
from hdrc3_tst.platform_port import Command, PlatformState
from hdrc3_tst.resolver import ResolvedTst
from hdrc3_tst.rmax_executors import RMAX_EXECUTORS

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "tst"
FRAME = frame_from_world("revinge")
HEAD = "world revinge\nagents uav0, uav1\npoint Sq = town_square at 30\n"


class Rig:
    """One agent's engine on a fake platform, planner and sink."""

    def __init__(
        self,
        tst: ResolvedTst,
        agent: str = "uav0",
        executors: dict[str, type[ActionExecutor]] | None = None,
    ) -> None:
        self.platform, self.planner, self.sink = FakePlatform(), FakePlanner(), RecordingSink()
        ctx = EngineContext(
            agent, self.platform, self.planner, self.sink, FRAME, executors or dict(RMAX_EXECUTORS)
        )
        self.engine = ExecutionEngine("m", tst, ctx)
        self.t = 1000.0

    def start(self, node: str) -> None:
        assert self.engine.execute(node, self.t, self.t) == ""

    def run(self, seconds: float, on_command: Callable[[Command], None] | None = None) -> None:
        """Tick once a second; every running command is handed to ``on_command``."""
        for _ in range(int(seconds)):
            self.t += 1.0
            self.engine.tick(self.t)
            for command in self.platform.running():
                if on_command is not None:
                    on_command(command)

    def state(self, node: str) -> NodeState:
        return self.engine.records[node].state

    def reason(self, node: str) -> str:
        return self.engine.records[node].reason


def flown(platform: FakePlatform) -> Callable[[Command], None]:
    """Complete every command at once; traj3d segments ask for the next one first."""

    def answer(command: Command) -> None:
        if command.command is FclCommand.TRAJ3D and not command.segment_requested:
            command.segment_requested = True
            return
        platform.complete(command)

    return answer


def mission(body: str) -> ResolvedTst:
    result = load_text(HEAD + body)
    assert result.status is CheckStatus.OK, result.diagnostics
    assert result.tst is not None
    bind_open_agents(result.tst, "uav0")
    return result.tst


def example_6_1() -> ResolvedTst:
    result = load_file(EXAMPLES / "example_6_1.tst", ("uav0", "uav1"))
    assert result.tst is not None
    return result.tst


def test_example_6_1_on_uav0_runs_its_nodes_and_starts_tau3_on_uav1() -> None:
    tst = example_6_1()
    rig = Rig(tst)
    assert [r.node_id for r in rig.engine.local_records()] == ["tau0", "tau1", "tau2", "tau4"]
    rig.start("tau0")
    assert rig.sink.remote_starts == [NodeRef("uav1", "tau3")]
    rig.run(60, flown(rig.platform))
    assert rig.state("tau2") is NodeState.SUCCEEDED
    assert rig.state("tau1") is NodeState.RUNNING  # tau3 on uav1 still runs
    labels = [c.label for c in rig.platform.sent if c.label.startswith("fcl_")]
    assert labels[:3] == ["fcl_takeoff", "fcl_traj3d_flyto", "fcl_traj3d"]
    # AreaA is 80 m across; the thermal camera's 13.3 m strip at 30 m, 20 % overlap: 8 legs
    assert labels.count("fcl_traj3d") == 15  # 8 legs and 7 turns
    payload = [c.label for c in rig.platform.sent if c.label.startswith("ppcl_")]
    assert payload == ["ppcl_turn_to", "ppcl_ip_saliency", "ppcl_ip_abort"]
    rig.engine.on_remote_status("tau3", NodeState.SUCCEEDED, 1.0, 50.0, "")
    rig.run(10, flown(rig.platform))
    assert [rig.state(n) for n in ("tau1", "tau4", "tau0")] == [NodeState.SUCCEEDED] * 3
    assert rig.platform.sent[-1].label == "fcl_traj3d_flyto"
    values = tst.network.values
    times = {n: (values[f"TS{n}"], values[f"TE{n}"]) for n in "01234"}
    assert times["0"][0] <= times["1"][0] < times["1"][1] <= times["4"][0] < times["4"][1]
    assert times["1"][1] >= times["3"][1] == 50.0  # the remote end went into the replica
    assert values["Speed2"] == 8.0  # the open speed was bound to the preferred value
    assert ("tau2", "scan-area", True) in rig.sink.flags
    assert ("tau2", "scan-area", False) in rig.sink.flags
    # the flags carry the action's arguments (operator-specific monitor formulas bind them)
    assert rig.sink.flag_args["tau2"]["area"] == "AreaA"


def test_a_node_waits_for_its_earliest_start() -> None:
    tst = mission(
        "m(P, TS, TE) = with T1, T2 sequence\n"
        "  w(T1, T2) = wait(T1, T2, 5)\n"
        "where P = uav0 and TS = 0 and T1 >= 20\n"
    )
    rig = Rig(tst)
    rig.start("m")
    rig.run(19)
    assert math.isnan(rig.engine.records["w"].start)
    rig.run(30)
    assert rig.engine.records["w"].start == 20.0
    assert rig.engine.records["w"].end == 25.0
    assert rig.state("m") is NodeState.SUCCEEDED


def test_a_missed_deadline_fails_the_node_and_stops_its_command() -> None:
    tst = mission("m(P, TS, TE) = fly-to(TS, TE, 5, Sq) where P = uav0 and TE - TS <= 20\n")
    rig = Rig(tst)
    rig.platform.sample = PlatformState(0, 0, 30, on_ground=False, autonomous=True)
    rig.start("m")
    rig.run(25)  # the fly-to never finishes
    assert rig.state("m") is NodeState.FAILED
    # one tick of tolerance (TICK_TOLERANCE_S) after the latest end
    assert rig.reason("m").startswith("deadline: not done at 22.0 s, latest end 20.0 s")
    assert [c.label for c, _ in rig.platform.stopped] == ["fcl_traj3d_flyto"]


def test_an_end_seen_a_tick_late_is_recorded_at_its_due_time() -> None:
    """A wait's end is due between two ticks; the engine records it when it was due."""
    rig = Rig(mission("m(P, TS, TE) = wait(TS, TE, 3) where P = uav0\n"))
    rig.start("m")
    for _ in range(5):  # ticks at 0.7, 1.4, ... 3.5 s
        rig.t += 0.7
        rig.engine.tick(rig.t)
    assert rig.state("m") is NodeState.SUCCEEDED
    record = rig.engine.records["m"]
    assert (record.start, record.end) == (0.0, 3.0)
    assert rig.engine.tst.network.values[rig.engine.tst.variable("m", "TE")] == 3.0


class AtOnce(ActionExecutor):
    """Done as soon as it runs: a fly-to to where the aircraft already is, a PTU already there."""

    def run(self, ctx: ActionContext) -> Generator[None, None, Status]:
        return SUCCEEDED
        yield  # a generator that never waits


@pytest.mark.parametrize("tick", [0.02, 0.1])  # 0.1: mission times a hair past the ns grid
def test_actions_done_in_the_tick_they_started_end_just_after_their_start(tick: float) -> None:
    """``TS < TE`` holds: such an end is seen in its start's tick, so it lies within that tick."""
    text = "m(TS, TE) = with TS1, TE1, TS2, TE2, TS3, TE3 sequence\n"
    text += "  a(TS1, TE1) = wait(TS1, TE1, 0.05);\n"
    text += "  b(TS2, TE2) = ptu-turn-to(TS2, TE2, 0, 30);\n"
    text += "  c(TS3, TE3) = fly-to(TS3, TE3, 3, Sq)\n"
    text += "where TS <= TS1 and TS1 < TE1 and TE1 <= TS2 and TS2 < TE2 and TE2 <= TS3\n"
    text += "  and TS3 < TE3 and TE3 <= TE\n"
    rig = Rig(mission(text), executors={**RMAX_EXECUTORS, "ptu-turn-to": AtOnce, "fly-to": AtOnce})
    rig.start("m")
    for _ in range(8):
        rig.t += tick
        rig.engine.tick(rig.t)
    for node in ("b", "c"):
        record = rig.engine.records[node]
        assert record.state is NodeState.SUCCEEDED, record.reason
        assert 0.0 < record.end - record.start <= 2e-9
    assert rig.state("m") is NodeState.SUCCEEDED, rig.reason("m")


def test_abort_stops_commands_and_aborts_remote_children() -> None:
    rig = Rig(example_6_1())
    rig.start("tau0")
    rig.run(6, flown(rig.platform))
    aborted = rig.engine.abort("operator")
    assert set(aborted) == {"tau0", "tau1", "tau2"}
    assert all(rig.state(n) is NodeState.ABORTED for n in ("tau0", "tau1", "tau2"))
    assert rig.platform.stopped
    # the aborted scan stops the saliency pipeline it started
    assert [c.label for c in rig.platform.running()] == ["ppcl_ip_abort"]
    assert rig.sink.remote_aborts[0][0] == NodeRef("uav1", "tau3")
    assert rig.state("tau4") is NodeState.CREATED


def test_a_refused_command_fails_the_concurrent_node_and_aborts_the_sibling() -> None:
    rig = Rig(example_6_1())
    rig.platform.refuse[FclCommand.TAKEOFF] = "RC switch manual"
    rig.start("tau0")
    rig.run(2)
    assert rig.reason("tau2") == "fcl_takeoff: refused: RC switch manual"
    assert rig.reason("tau0") == "tau1 failed: tau2 failed: fcl_takeoff: refused: RC switch manual"
    assert [r for r, _ in rig.sink.remote_aborts] == [NodeRef("uav1", "tau3")]


@pytest.mark.parametrize(
    ("where", "speed"),
    [("P = uav0", 8.0), ("P = uav0 and S <= 3", None), ("P = uav0 and S >= 10", None)],
)
def test_open_parameters_are_bound_when_the_action_starts(where: str, speed: float | None) -> None:
    tst = mission(f"m(P, TS, TE) = with S fly-to(TS, TE, S, Sq) where {where}\n")
    rig = Rig(tst)
    rig.platform.sample = PlatformState(0, 0, 30, on_ground=False, autonomous=True)
    rig.start("m")
    bound = rig.platform.sent[0].args["velocity"]
    if speed is not None:
        assert bound == speed
    else:
        assert tst.network.values["S"] == bound
        assert (bound <= 3) if "<=" in where else (bound >= 10)


def test_a_goal_is_planned_attached_and_flown() -> None:
    tst = mission("m(P, TS, TE) = goal at(uav0, Sq) where P = uav0\n")
    rig = Rig(tst)
    rig.platform.sample = PlatformState(-150, 0, 30, on_ground=False, autonomous=True)
    rig.start("m")
    (request,) = rig.planner.requests
    assert "object here_uav0: location @ (-150.000, 0.000, 30.000)" in request.problem
    assert "goal at(uav0, Sq)" in request.problem
    request.answer(True, "", ["(fly-to uav0 here_uav0 Sq)"], ["uav0"], [0.0], [30.0])
    rig.run(2, flown(rig.platform))
    assert rig.state("m/1") is NodeState.SUCCEEDED
    assert rig.state("m") is NodeState.SUCCEEDED
    assert rig.platform.sent[0].label == "fcl_traj3d_flyto"


@pytest.mark.parametrize(
    ("answer", "reason"),
    [
        ((False, "no plan: unsolvable"), "planning at: no plan: unsolvable"),
        (
            (True, "", ["(land uav0 Sq)"], ["uav0"], [0.0], [20.0]),
            "the plan needs (land uav0 Sq), and no RMAX executor performs land",
        ),
    ],
)
def test_a_goal_fails_when_no_executable_plan_comes(answer: tuple, reason: str) -> None:  # type: ignore[type-arg]
    rig = Rig(mission("m(P, TS, TE) = goal at(uav0, Sq) where P = uav0\n"))
    rig.start("m")
    rig.planner.requests[0].answer(*answer)
    rig.run(1)
    assert rig.state("m") is NodeState.FAILED
    assert rig.reason("m").startswith(reason)


@pytest.mark.parametrize(
    ("condition", "on_ground", "chosen"),
    [("airborne(P)", True, "b"), ("airborne(P)", False, "a"), ("not on-ground(P)", True, "b")],
)
def test_if_asks_its_query_once(condition: str, on_ground: bool, chosen: str) -> None:
    tst = mission(
        f"m(P, TS, TE) = if [TS] {condition} then a(TS, TE) = wait(TS, TE, 1) "
        "else b(TS, TE) = wait(TS, TE, 1) where P = uav0\n"
    )
    rig = Rig(tst)
    rig.platform.sample = PlatformState(0, 0, 0, on_ground=on_ground, autonomous=True)
    rig.start("m")
    rig.run(3)
    assert rig.state("m") is NodeState.SUCCEEDED
    assert rig.state(chosen) is NodeState.SUCCEEDED
    assert rig.state("b" if chosen == "a" else "a") is NodeState.CREATED


def test_a_query_nobody_answers_fails_the_node() -> None:
    tst = mission(
        "m(P, TS, TE) = while [TS] daylight() w(T1, T2) = wait(T1, T2, 1) where P = uav0\n"
    )
    rig = Rig(tst)
    rig.start("m")
    assert rig.state("m") is NodeState.FAILED
    assert rig.reason("m").startswith("no agent answers the query daylight(...)")


def test_while_repeats_its_body_until_the_query_is_false() -> None:
    tst = mission(
        "m(P, TS, TE) = while [TS] on-ground(P) w(T1, T2) = wait(T1, T2, 2) where P = uav0\n"
    )
    rig = Rig(tst)
    rig.start("m")
    rig.run(9)  # rounds end at 2, 5 and 8 s (a round restarts its body on the next tick)
    assert rig.engine.records["m"].rounds == 3
    rig.platform.sample = PlatformState(0, 0, 10, on_ground=False, autonomous=True)
    rig.run(3)
    assert rig.state("m") is NodeState.SUCCEEDED


class _Broken(ActionExecutor):
    def run(self, ctx: ActionContext):  # type: ignore[no-untyped-def]
        raise RuntimeError("bug")
        yield  # pragma: no cover


def test_an_executor_error_fails_its_node_not_the_engine() -> None:
    tst = mission("m(P, TS, TE) = wait(TS, TE, 5) where P = uav0\n")
    rig = Rig(tst, executors={"wait": _Broken})
    rig.start("m")
    assert rig.state("m") is NodeState.FAILED
    assert rig.reason("m") == "executor error: RuntimeError('bug')"


def test_execute_refuses_nodes_held_elsewhere_or_started_twice() -> None:
    rig = Rig(example_6_1())
    assert rig.engine.execute("tau3", 0.0, 0.0) == "uav0 does not hold node 'tau3'"
    rig.start("tau0")
    assert rig.engine.execute("tau0", 0.0, 0.0) == "node tau0 is running"


def test_status_changes_reach_the_sink_in_order() -> None:
    tst = mission("m(P, TS, TE) = wait(TS, TE, 2) where P = uav0\n")
    rig = Rig(tst)
    rig.start("m")
    rig.run(3)
    assert rig.sink.statuses == [("m", NodeState.RUNNING, ""), ("m", NodeState.SUCCEEDED, "")]


def test_pause_stops_the_commands_and_resume_flies_on() -> None:
    tst = mission("m(P, TS, TE) = fly-to(TS, TE, 5, Sq) where P = uav0 and TE - TS <= 100\n")
    rig = Rig(tst)
    rig.platform.sample = PlatformState(0, 0, 30, on_ground=False, autonomous=True)
    rig.start("m")
    assert rig.engine.pause() == ["m"]
    assert rig.state("m") is NodeState.PAUSED
    assert [c.label for c, r in rig.platform.stopped] == ["fcl_traj3d_flyto"]
    assert ("m", "fly-to", False) in rig.sink.flags
    rig.run(10)
    assert len(rig.platform.sent) == 1  # nothing flies while paused
    assert rig.engine.resume() == ["m"]
    assert rig.state("m") is NodeState.RUNNING
    rig.run(1, flown(rig.platform))
    rig.run(1)
    assert rig.state("m") is NodeState.SUCCEEDED
    assert [c.label for c in rig.platform.sent] == ["fcl_traj3d_flyto"] * 2
    assert rig.engine.records["m"].start == 0.0


def test_a_paused_node_still_misses_its_deadline() -> None:
    tst = mission("m(P, TS, TE) = fly-to(TS, TE, 5, Sq) where P = uav0 and TE - TS <= 20\n")
    rig = Rig(tst)
    rig.platform.sample = PlatformState(0, 0, 30, on_ground=False, autonomous=True)
    rig.start("m")
    rig.engine.pause()
    rig.run(25)
    assert rig.state("m") is NodeState.FAILED
    assert rig.reason("m").startswith("deadline")


def test_an_executors_notes_reach_the_sink_and_fly_to_uses_the_agents_planner() -> None:
    from hdrc3_control.path_segment import PathSegment
    from hdrc3_navigation.planner import PlanRequest, PlanResult, PlanStatus
    from hdrc3_navigation.runtime_world import RuntimeWorld
    from hdrc3_tst.navigation_port import PlanJob

    class OneSegment:
        """A planner answering every query with one straight segment to the goal."""

        def __init__(self) -> None:
            self.requests: list[PlanRequest] = []

        def plan(self, request: PlanRequest) -> PlanJob:
            self.requests.append(request)
            segment = PathSegment.straight(request.start, request.goal, 8.0, 0.0)
            return PlanJob(request, PlanResult(PlanStatus.SOLVED, "", (segment,), 1.0))

        def world(self) -> RuntimeWorld:
            return RuntimeWorld()

    rig = Rig(mission("m(TS, TE) = fly-to(TS, TE, 8, Sq)\n"))
    nav = OneSegment()
    rig.engine.ctx.navigation = nav
    rig.platform.sample = PlatformState(0.0, 0.0, 30.0, on_ground=False, autonomous=True)
    rig.start("m")

    def arrive(command: Command) -> None:  # the one segment is flown to its end
        rig.platform.move_to(nav.requests[0].goal)
        rig.platform.complete(command)

    rig.run(5, arrive)
    assert rig.state("m") is NodeState.SUCCEEDED, rig.reason("m")
    assert [c.command for c in rig.platform.sent] == [FclCommand.TRAJ3D]
    assert nav.requests[0].start == (0.0, 0.0, 30.0)
    assert [(n, t.split(" ")[0]) for n, t in rig.sink.notes] == [("m", "planned")]
    assert [(n, len(p)) for n, p in rig.sink.paths] == [("m", 1)]


SCAN_ALL = (
    "m(P, TS, TE) = foreach Av where [TS] can-scan(Av) do conc\n"
    "  s(Av, U1, U2) = wait(U1, U2, {seconds})\n"
    "where P = uav0\n"
)


def test_foreach_runs_one_instance_per_answer_across_agents() -> None:
    """Section 9.4's scan-with-all-uavs: one instance per agent, each held by its agent."""
    text = SCAN_ALL.format(seconds=5)
    owner, other = Rig(mission(text)), Rig(mission(text), agent="uav1")
    owner.start("m")
    children = [c.node_id for c in owner.engine.tst.tree.node("m").children]
    assert children == ["m[uav0]/s", "m[uav1]/s"]
    assert owner.sink.remote_starts == [NodeRef("uav1", "m[uav1]/s")]
    assert ("m", "2 instances: uav0, uav1") in owner.sink.notes
    # uav1's manager resolves the instance from its id alone
    assert other.engine.execute("m[uav1]/s", owner.t, other.t) == ""
    owner.run(6)
    assert owner.state("m[uav0]/s") is NodeState.SUCCEEDED
    assert owner.state("m") is NodeState.RUNNING  # uav1's instance is not reported yet
    other.run(6)
    assert other.state("m[uav1]/s") is NodeState.SUCCEEDED
    rec = other.engine.records["m[uav1]/s"]
    owner.engine.on_remote_status("m[uav1]/s", rec.state, rec.start, rec.end, "")
    owner.run(1)
    assert owner.state("m") is NodeState.SUCCEEDED
    assert owner.state("m[*]/s") is NodeState.CREATED  # the template never runs
    values = owner.engine.tst.network.values
    assert values["m[uav0]/U2"] - values["m[uav0]/U1"] == 5.0  # each instance has its own times


@pytest.mark.parametrize(
    ("condition", "body", "state", "reason"),
    [
        ("area(X)", "wait(U1, U2, 1)", NodeState.SUCCEEDED, ""),  # no area declared: no instance
        ("seen(X)", "wait(U1, U2, 1)", NodeState.FAILED, "no agent answers seen(...) over X"),
        ("not agent(X)", "wait(U1, U2, 1)", NodeState.FAILED, "not agent(X) has no finite set"),
        ("on-ground(P)", "wait(U1, U2, 1)", NodeState.FAILED, "the query on-ground(...) binds"),
        (
            "agent(X)",
            "sequence w(U3, U4) = wait(U3, U4, 1) where X != uav1",
            NodeState.FAILED,
            "foreach instance: <string>:5:60: X != uav1; m[uav1].X = uav1",
        ),
    ],
)
def test_foreach_answers_and_refusals(
    condition: str, body: str, state: NodeState, reason: str
) -> None:
    tst = mission(
        f"m(P, TS, TE) = foreach X where [TS] {condition} do conc\n"
        f"  s(U1, U2) = {body}\nwhere P = uav0\n"
    )
    rig = Rig(tst)
    rig.platform.sample = PlatformState(0, 0, 0, on_ground=True, autonomous=True)
    rig.start("m")
    rig.run(3)
    assert rig.state("m") is state
    assert rig.reason("m").startswith(reason)


def test_a_sibling_ordered_after_another_waits_for_its_end() -> None:
    """``where T3 >= T2`` in a concurrent node: b starts when a has ended, not at once."""
    rig = Rig(
        mission(
            "m(P, TS, TE) = with T1, T2, T3, T4 concurrent\n"
            "  a(T1, T2) = fly-to(T1, T2, 5, Sq);\n"
            "  b(T3, T4) = wait(T3, T4, 2)\n"
            "where P = uav0 and T3 >= T2\n"
        )
    )
    rig.platform.sample = PlatformState(0, 0, 30, on_ground=False, autonomous=True)
    rig.start("m")
    rig.run(5)  # the fly-to has not ended
    b = rig.engine.records["b"]
    assert b.state is NodeState.RUNNING and math.isnan(b.start)
    assert b.reason == "waiting for uav0/a.TE"
    assert ("b", NodeState.RUNNING, "waiting for uav0/a.TE") in rig.sink.statuses  # said once
    rig.run(1, flown(rig.platform))
    rig.run(4)
    assert rig.state("m") is NodeState.SUCCEEDED, rig.reason("m")
    assert b.start >= rig.engine.records["a"].end and b.reason == ""


@pytest.mark.parametrize(("released", "waiting"), [(False, "waiting for uav1/a.TE"), (True, "")])
def test_a_released_node_does_not_wait_for_other_agents_events(
    released: bool, waiting: str
) -> None:
    """A delegator that saw uav1's a end releases b; a replica on another host never hears it."""
    rig = Rig(
        mission(
            "m(P, TS, TE) = with P1, T1, T2, P2, T3, T4 concurrent\n"
            "  a(P1, T1, T2) = wait(T1, T2, 2);\n"
            "  b(P2, T3, T4) = wait(T3, T4, 2)\n"
            "where P = uav1 and P1 = uav1 and P2 = uav0 and T3 >= T2\n"
        )
    )
    assert rig.engine.execute("b", rig.t, rig.t, released) == ""
    rig.run(3)  # past b's earliest start (a takes 2 s)
    b = rig.engine.records["b"]
    assert b.reason == waiting
    assert math.isfinite(b.start) is released
    rig.run(3)
    assert (b.state is NodeState.SUCCEEDED) is released


SYNCHRONISED = (
    "m(P, TS, TE) = with P1, A1, A2, P2, B1, B2, S3, U3 concurrent\n"
    "  a(P1, A1, A2) = with S1, S2, S4 sequence\n"
    "    a1(S1, S2) = fly-to(S1, S2, 5, Sq);\n"
    "    a2(S3, S4) = with T1, T2, T3, T4 concurrent\n"
    "      a3(T1, T2) = wait(T1, T2, 3);\n"
    "      a4(T3, T4) = wait(T3, T4, 3)\n"
    "    where T1 = S3 and T3 = S3\n"
    "  where P1 = uav0;\n"
    "  b(P2, B1, B2) = with U1, U2, U4 sequence\n"
    "    b1(U1, U2) = wait(U1, U2, 2);\n"
    "    b2(U3, U4) = with V1, V2, V3, V4 concurrent\n"
    "      b3(V1, V2) = wait(V1, V2, 3);\n"
    "      b4(V3, V4) = wait(V3, V4, 3)\n"
    "    where V1 = U3 and V3 = U3\n"
    "  where P2 = uav1\n"
    "where P = uav0 and S3 = U3{deadline}\n"
)
"""Section 9.4's monitor-pattern in small: uav0 flies, uav1 waits 2 s; then both start together
a concurrent node whose children start with it (monitor-single's hover, measurement, look-at)."""


def _relay(source: Rig, target: Rig, seen: int) -> int:
    """Hand ``source``'s new statuses to ``target``'s replica (the status topic); how many seen."""
    for node_id, state, reason in source.sink.statuses[seen:]:
        rec = source.engine.records[node_id]
        target.engine.on_remote_status(node_id, state, rec.start, rec.end, reason)
    return len(source.sink.statuses)


def _fly_both(owner: Rig, other: Rig, seconds: int, land_at: float) -> None:
    """Tick both managers a second at a time, relaying statuses; the fly-to ends at ``land_at``."""
    seen = [0, 0]
    for _ in range(seconds):
        for rig in (owner, other):
            rig.t += 1.0
            rig.engine.tick(rig.t)
        if owner.t - 1000.0 >= land_at:
            for command in owner.platform.running():
                flown(owner.platform)(command)
        seen[0] = _relay(owner, other, seen[0])
        seen[1] = _relay(other, owner, seen[1])


def test_starts_tied_across_agents_wait_for_each_other() -> None:
    text = SYNCHRONISED.format(deadline="")
    owner, other = Rig(mission(text)), Rig(mission(text), agent="uav1")
    owner.platform.sample = PlatformState(0, 0, 30, on_ground=False, autonomous=True)
    owner.start("m")
    assert owner.sink.remote_starts == [NodeRef("uav1", "b")]
    assert other.engine.execute("b", owner.t, other.t) == ""
    _fly_both(owner, other, 8, land_at=math.inf)
    b2 = other.engine.records["b2"]
    assert other.state("b1") is NodeState.SUCCEEDED and math.isnan(b2.start)
    assert b2.reason == "waiting for uav0/a1.TE, uav0/a2.TS"
    _fly_both(owner, other, 20, land_at=10.0)
    a2 = owner.engine.records["a2"]
    assert (a2.state, b2.state) == (NodeState.SUCCEEDED, NodeState.SUCCEEDED)
    # the fly-to ended at 10 s and was seen at the 11 s tick; uav1 saw a2 start a tick later
    # and recorded b2's start at a2's
    assert a2.start == b2.start == 11.0
    children = [owner.engine.records[n] for n in ("a3", "a4")]
    children += [other.engine.records[n] for n in ("b3", "b4")]
    assert {c.start for c in children} == {11.0}  # each began with its parent
    assert owner.state("m") is NodeState.SUCCEEDED, owner.reason("m")


def test_a_start_waited_for_past_its_latest_time_fails() -> None:
    text = SYNCHRONISED.format(deadline=" and U3 <= 6")
    owner, other = Rig(mission(text)), Rig(mission(text), agent="uav1")
    owner.platform.sample = PlatformState(0, 0, 30, on_ground=False, autonomous=True)
    owner.start("m")
    assert other.engine.execute("b", owner.t, other.t) == ""
    _fly_both(owner, other, 10, land_at=math.inf)
    assert other.state("b2") is NodeState.FAILED
    assert other.reason("b2") == (
        "not started by its latest start 6.0 s: waiting for uav0/a1.TE, uav0/a2.TS"
    )


def test_concurrent_children_with_one_start_begin_together_without_waiting() -> None:
    """monitor-single's hover, measurement and look-at share a T_S: none waits for another."""
    rig = Rig(
        mission(
            "m(P, TS, TE) = with T1, T2, T3, T4, T5, T6 concurrent\n"
            "  a(T1, T2) = wait(T1, T2, 3);\n"
            "  b(T3, T4) = wait(T3, T4, 3);\n"
            "  c(T5, T6) = wait(T5, T6, 3)\n"
            "where P = uav0 and T1 = T3 and T3 = T5\n"
        )
    )
    rig.start("m")
    assert [rig.engine.records[n].start for n in "abc"] == [0.0, 0.0, 0.0]
    assert not [s for s in rig.sink.statuses if s[2].startswith("waiting")]
    rig.run(4)
    assert rig.state("m") is NodeState.SUCCEEDED


def test_a_start_pinned_by_what_happened_is_not_waited_for() -> None:
    """uav1 hears that a2 began but not yet of a3/a4, tied to a2's start: b2 begins anyway."""
    text = SYNCHRONISED.format(deadline="")
    owner, other = Rig(mission(text)), Rig(mission(text), agent="uav1")
    owner.platform.sample = PlatformState(0, 0, 30, on_ground=False, autonomous=True)
    owner.start("m")
    assert other.engine.execute("b", owner.t, other.t) == ""
    _fly_both(owner, other, 8, land_at=math.inf)
    for command in owner.platform.running():
        flown(owner.platform)(command)
    owner.t = other.t = 1010.0
    owner.engine.tick(owner.t)
    a2 = owner.engine.records["a2"]
    assert a2.start == 10.0 and owner.engine.records["a3"].start == 10.0
    other.engine.on_remote_status("a1", NodeState.SUCCEEDED, 0.0, 10.0, "")
    other.engine.on_remote_status("a2", NodeState.RUNNING, a2.start, math.nan, "")
    other.engine.tick(other.t)
    assert other.engine.records["b2"].start == 10.0, other.reason("b2")
