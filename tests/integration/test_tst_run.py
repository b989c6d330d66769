"""TSTs flown on the real node chain (issue 12): two RMAXes, distributed nodes, abort, goals.

``hdrc3 tst run examples/tst/example_6_1.tst --launch`` flies Example 6.1 with uav0 and uav1;
every node's recorded T_S/T_E is checked against the file's own constraints, evaluated here on
the recorded numbers (not through the engine's network). A second system runs the same mission
through the TST client, pauses it mid-scan (both aircraft hover), resumes it (both fly on), aborts
it and watches both aircraft hover; then a goal node is planned by TALplanner on the agent's
``task_planner`` and flown.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from hdrc3_base.stamps import stamp_s
from tests.integration.flight_runs import SEED, recorded

pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.flight]

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tst"
AGENTS = ("uav0", "uav1")
WAIT_S = 240.0
"""Wall-clock bound of one flight phase at --speed max on a loaded 2-core machine."""


def constraint_violations(file: Path, times: dict[str, tuple[float, float]]) -> list[str]:
    """Every temporal constraint of the file that the recorded times break."""
    from hdrc3_tst.check import load_file
    from hdrc3_tst.stn import ORIGIN

    tst = load_file(file, AGENTS).tst
    assert tst is not None
    value: dict[str, float] = {ORIGIN: 0.0}
    for node_id, (start, end) in times.items():
        node = tst.tree.node(node_id)
        for var, t in ((node.params["TS"], start), (node.params["TE"], end)):
            assert math.isclose(value.setdefault(var, t), t, abs_tol=1e-6), (node_id, var)
    broken = []
    for edge in tst.network.stn.edges():
        if edge.source in value and edge.target in value:
            gap = value[edge.target] - value[edge.source]
            bound, strict = edge.bound
            if gap > bound + 1e-6 or (strict < 0 and gap >= bound + 1e-6):
                broken.append(f"{edge.label}: {gap:.3f} vs {bound:g}")
    return broken


@pytest.mark.timeout(900)
def test_example_6_1_flies_with_two_aircraft_and_keeps_its_constraints(
    hdrc3_cli: Callable[..., Any], ros_domain: int, tmp_path: Path
) -> None:
    out = tmp_path / "run"
    file = EXAMPLES / "example_6_1.tst"
    run = hdrc3_cli(
        "tst", "run", str(file), "--launch", "--agents", "uav0,uav1", "--world", "revinge",
        "--out", str(out), "--domain-id", str(ros_domain), "--mission", "ex61", "--seed", SEED,
    )  # fmt: skip
    code = run.finish(timeout=600.0)
    text = "\n".join(run.lines)
    assert code == 0, text
    assert "mission ex61 succeeded" in text
    assert "uav1/tau3 scan-area running" in text  # the distributed node, held by uav1

    messages = recorded(out / "run.mcap", "/tst_status", "/execution_flags")
    statuses, flags = messages["/tst_status"], messages["/execution_flags"]
    final = {s.node_id: s for s in statuses if s.mission == "ex61"}
    assert set(final) == {"tau0", "tau1", "tau2", "tau3", "tau4"}
    assert {s.node_id: s.agent for s in final.values()} == {
        "tau0": "uav0", "tau1": "uav0", "tau2": "uav0", "tau3": "uav1", "tau4": "uav0",
    }  # fmt: skip
    assert all(s.state == "succeeded" for s in final.values()), final
    times = {n: (s.start, s.end) for n, s in final.items()}
    assert constraint_violations(file, times) == []
    assert times["tau2"][1] - times["tau2"][0] > 30.0  # a real scan, not an instant success

    assert {(f.agent, f.node_id, f.executing) for f in flags} >= {
        ("uav0", "tau2", True), ("uav0", "tau2", False), ("uav1", "tau3", True),
        ("uav1", "tau3", False), ("uav0", "tau4", True), ("uav0", "tau4", False),
    }  # fmt: skip
    timeline = (out / "timeline.csv").read_text(encoding="utf-8").splitlines()
    assert len(timeline) == 6 and timeline[0].startswith("node,agent,parent")


class System:
    """Two agents launched with TST managers, task and path planners, a TST client and the DI."""

    def __init__(self, process: Any) -> None:
        from hdrc3_interfaces.msg import HelicopterState
        from hdrc3_platform_server.geo_frame import frame_from_world
        from hdrc3_tst.mission_client import TstClient

        self.process = process
        self.client = TstClient(process)
        self.frame = frame_from_world("revinge")
        self.states: dict[str, list[Any]] = {a: [] for a in AGENTS}
        for agent in AGENTS:
            self.client.node.create_subscription(
                HelicopterState,
                f"/{agent}/helicopter_state",
                lambda m, a=agent: self.states[a].append(m),
                100,
            )

    def wait(self, done: Callable[[], bool], what: str, timeout: float = WAIT_S) -> None:
        assert self.process.spin_until(done, timeout), f"timed out waiting for {what}"

    def state(self, node: str, mission: str) -> str:
        msg = self.client.latest(mission).get(node)
        return "" if msg is None else str(msg.state)

    def sim_time(self, agent: str) -> float:
        return stamp_s(self.states[agent][-1].header.stamp) if self.states[agent] else 0.0

    def sleep_sim(self, seconds: float, what: str) -> None:
        """Wait until every agent's Data Interface is ``seconds`` of sim time further."""
        until = min(self.sim_time(a) for a in AGENTS) + seconds
        self.wait(lambda: min(self.sim_time(a) for a in AGENTS) >= until, what)

    def assert_hovering(self) -> None:
        for agent in AGENTS:
            last = self.states[agent][-1]
            assert not last.on_ground_flag, agent
            assert math.hypot(last.velocity_north, last.velocity_east) < 0.5, agent
            assert abs(last.velocity_up) < 0.3, agent


@pytest.fixture
def system(hdrc3_cli: Callable[..., Any], ros_domain: int) -> Iterator[System]:
    from hdrc3.safety_pilot import hand_over
    from hdrc3_base.ros_runtime import RosProcess

    launch = hdrc3_cli(
        "launch", "--agents", ",".join(AGENTS), "--world", "revinge", "--speed", "max",
        "--nodes", "world_sim,control_kernel,platform_server,perception_kernel,tst_manager,"
        "task_planner,path_planner",  # scan-area turns the PTU through the PPC
        "--seed", SEED,
    )  # fmt: skip
    launch.wait_for_line("READY", timeout=120)
    with RosProcess(domain_id=ros_domain, handle_signals=False) as process:
        rig = System(process)
        try:
            for agent in AGENTS:
                hand_over(process, rig.client.node, agent)
            yield rig
        finally:
            rig.client.node.destroy_node()
            launch.interrupt()
            print("\n".join(launch.lines[-40:]))  # shown by pytest when the test failed


@pytest.mark.timeout(900)
def test_pause_resume_and_abort_mid_scan_leave_both_aircraft_hovering_then_a_goal_is_flown(
    system: System, hdrc3_cli: Callable[..., Any]
) -> None:
    def tst_command(*words: str) -> None:
        done = hdrc3_cli("tst", *words, "abort-me", "--agents", ",".join(AGENTS))
        assert done.finish(timeout=60.0) == 0, "\n".join(done.lines)

    text = (EXAMPLES / "example_6_1.tst").read_text(encoding="utf-8")
    created = system.client.create("abort-me", text, "example_6_1.tst", AGENTS)
    assert created.ok, created.replies
    assert system.client.execute("abort-me", "uav0", "tau0").ok

    def scanning() -> bool:
        return (
            all(
                system.states[a] and system.states[a][-1].altitude - system.frame.altitude > 25.0
                for a in AGENTS
            )
            and system.state("tau3", "abort-me") == "running"
        )

    system.wait(scanning, "both aircraft at scan altitude")
    system.sleep_sim(10.0, "10 s of scanning")

    tst_command("pause")
    system.wait(lambda: system.state("tau3", "abort-me") == "paused", "uav1's node paused")
    assert system.state("tau2", "abort-me") == "paused"
    system.sleep_sim(20.0, "20 s paused")
    system.assert_hovering()
    tst_command("resume")
    system.wait(lambda: system.state("tau3", "abort-me") == "running", "uav1's node resumed")

    def moving() -> bool:
        return all(
            math.hypot(s.velocity_north, s.velocity_east) > 2.0
            for s in (system.states[a][-1] for a in AGENTS)
        )

    system.wait(moving, "both aircraft flying again after resume")
    tst_command("abort")
    system.wait(lambda: system.state("tau0", "abort-me") == "aborted", "the root aborted")
    assert system.state("tau2", "abort-me") == "aborted"
    system.wait(lambda: system.state("tau3", "abort-me") == "aborted", "uav1's node aborted")

    system.sleep_sim(20.0, "20 s after abort")
    system.assert_hovering()

    goal = (
        "world revinge\nagents uav0, uav1\npoint Dest4 = town_square at 40\n"
        "g(P, TS, TE) = goal at(uav0, Dest4) where P = uav0\n"
    )
    created = system.client.create("goal", goal, "goal.tst", AGENTS)
    assert created.ok, created.replies
    assert system.client.execute("goal", "uav0", "g").ok
    system.wait(lambda: system.client.finished("goal", "g") is not None, "the goal node")
    latest = system.client.latest("goal")
    assert latest["g"].state == "succeeded", latest["g"].reason
    assert latest["g/1"].kind == "fly-to" and latest["g/1"].state == "succeeded"
    from hdrc3_tst.check import load_text

    resolved = load_text(goal, "goal.tst", AGENTS).tst
    assert resolved is not None
    (dest,) = resolved.places["Dest4"].coords
    last = system.states["uav0"][-1]
    here = system.frame.to_enu(last.longitude, last.latitude, last.altitude)
    assert math.dist(here, dest) < 5.0, (here, dest)
