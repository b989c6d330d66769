"""Recovery replanning figures (issue 15 item 6, chapter 9.3.1).

For goal problems of one helicopter delivering N boxes from a depot to fields (N = 1, 2, 4, 6),
a box is lost in flight after the first pick-up; prints the time of the recovery decision
(``Recovery.decide``: progress the plan, apply ``box-lost``, build the new problem) and of
TALplanner planning the new problem with the UAV logistics control rules (the planner core,
no ROS service), mean and max over ``--runs`` runs, and the new plan's length.

Then the issue's target size, a leg-II sized replan within 1 s: 2 helicopters, 10 boxes and
2 carriers (``generators.uav_problem``, seeds 0..``--seeds``-1), planned with helicopter heli1's
lift capacity lowered as ``lower-lift-capacity`` does after a failed lift of a 6 kg box
(0.8 x 6 = 4.8 kg): TALplanner's time with the control rules, mean and max, and the plan's
length. (A goal node's own recovery plans for its one helicopter, as in the first table.)

Run: .venv/bin/python bench/recovery_replan.py [--runs 5]
"""

from __future__ import annotations

import argparse
import statistics
import time

from hdrc3_deliberative.generators import UavSize, uav_problem
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.result import PlanStatus
from hdrc3_tst.goal_planning import GoalProblem, Load, PlannedStep, control_text, domain_text
from hdrc3_tst.recovery import Recovery, Violation, default_recovery

FIELDS = {f"Field{i}": (150.0 * (i + 1), 60.0 * i, 20.0) for i in range(3)}


def problem(boxes: int) -> GoalProblem:
    """N boxes at the depot, box i to field i mod 3."""
    locations = {"here_uav0": (-50.0, 0.0, 20.0), "Depot": (0.0, 0.0, 20.0), **FIELDS}
    loads = tuple(Load(f"box{i}", "food-box", "Depot", 5.0) for i in range(boxes))
    goal = " and ".join(f"at(box{i}, Field{i % 3})" for i in range(boxes))
    return GoalProblem("bench", "uav0", locations, "here_uav0", goal, loads)


def main() -> None:
    """Print the figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--seeds", type=int, default=10)
    args = parser.parse_args()
    planner = TaskPlanner()
    done = (
        PlannedStep("fly-to", "uav0", {"destination": "Depot"}, 0.0, 1.0),
        PlannedStep("pick-up-box", "uav0", {"box": "box0"}, 1.0, 20.0),
    )
    lost = Violation("held@g/3", "box-lost", True, {"av": "uav0", "box": "box0"})
    print("boxes  decide_mean_ms  decide_max_ms  plan_mean_ms  plan_max_ms  actions", flush=True)
    for boxes in (1, 2, 4, 6):
        decide_s: list[float] = []
        plan_s: list[float] = []
        actions = 0
        for _ in range(args.runs):
            t0 = time.perf_counter()
            decision = Recovery(default_recovery()).decide(
                lost, problem(boxes), done, (60.0, 5.0, 20.0)
            )
            t1 = time.perf_counter()
            assert decision.problem is not None, decision.reason
            request = PlanRequest(
                domain_text(), decision.problem.text(), decision.problem.control()
            )
            result = planner.plan(request, timeout=60.0)
            t2 = time.perf_counter()
            assert result.status is PlanStatus.SOLVED, result.reason
            decide_s.append(t1 - t0)
            plan_s.append(t2 - t1)
            actions = len(result.plan)
        print(
            f"{boxes:5d}  {1e3 * statistics.mean(decide_s):14.2f}  {1e3 * max(decide_s):13.2f}"
            f"  {1e3 * statistics.mean(plan_s):12.1f}  {1e3 * max(plan_s):11.1f}  {actions:7d}",
            flush=True,
        )
    leg_ii(planner, args.seeds)


def leg_ii(planner: TaskPlanner, seeds: int) -> None:
    """Print the leg-II sized replan figures (2 helicopters, 10 boxes, 2 carriers)."""
    times: list[float] = []
    actions: list[int] = []
    for seed in range(seeds):
        text = uav_problem(UavSize(helicopters=2, bodies=5, boxes=10, carriers=2), seed)
        lowered = text.replace("lift-capacity(heli1) = 30", "lift-capacity(heli1) = 4.8")
        assert lowered != text
        t0 = time.perf_counter()
        result = planner.plan(PlanRequest(domain_text(), lowered, control_text()), timeout=60.0)
        times.append(time.perf_counter() - t0)
        assert result.status is PlanStatus.SOLVED, result.reason
        actions.append(len(result.plan))
    print(
        f"leg-II sized replan (2 helicopters, 10 boxes, 2 carriers; heli1 lifts 4.8 kg),"
        f" {seeds} seeds: mean {1e3 * statistics.mean(times):.0f} ms, max"
        f" {1e3 * max(times):.0f} ms (target <= 1000 ms), {min(actions)}-{max(actions)} actions",
        flush=True,
    )


if __name__ == "__main__":
    main()
