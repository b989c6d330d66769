"""Benchmark TALplanner on generated IPC-2000-size Logistics problems.

For every instance: concurrent TALplanner with control rules (plan validated by
unified-planning), the same in sequential mode, TALplanner without control rules (small
instances only) and pyperplan through unified-planning (``up-pyperplan``, run in a child
process with a hard time limit because pyperplan ignores timeouts).

Usage: .venv/bin/python bench/talplanner.py [--quick] [--png out/talplanner.png]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from hdrc3_deliberative.generators import (
    LOGISTICS_CONTROL,
    LOGISTICS_DOMAIN,
    UAV_CONTROL,
    UAV_DOMAIN,
    UAV_SCENARIO,
    LogisticsSize,
    UavSize,
    logistics_problem,
    uav_problem,
)
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.validation import validate_pddl_plan

SIZES = [
    LogisticsSize(6, 2, 1),
    LogisticsSize(10, 4, 2),
    LogisticsSize(15, 5, 2),
    LogisticsSize(20, 7, 2),
    LogisticsSize(30, 10, 3),
    LogisticsSize(42, 14, 4),
    LogisticsSize(100, 20, 6),
    LogisticsSize(100, 30, 8),
]
NO_CONTROL_MAX_PACKAGES = 10
PYPERPLAN_LIMIT_S = 20.0


def pyperplan_worker(problem_path: str) -> None:
    """Child process: solve with up-pyperplan, print JSON (time, plan length)."""
    import warnings

    from unified_planning.io import PDDLReader
    from unified_planning.shortcuts import OneshotPlanner, get_environment

    warnings.simplefilter("ignore")
    get_environment().credits_stream = None
    problem = PDDLReader().parse_problem(str(LOGISTICS_DOMAIN), problem_path)
    start = time.perf_counter()
    with OneshotPlanner(name="pyperplan") as planner:
        result = planner.solve(problem)
    elapsed = time.perf_counter() - start
    length = len(result.plan.actions) if result.plan is not None else -1
    print(json.dumps({"status": result.status.name, "seconds": elapsed, "length": length}))


def run_pyperplan(problem_text: str) -> str:
    with tempfile.NamedTemporaryFile("w", suffix=".pddl", delete=False) as f:
        f.write(problem_text)
        path = f.name
    try:
        proc = subprocess.run(
            [sys.executable, __file__, "--pyperplan-worker", path],
            capture_output=True,
            text=True,
            timeout=PYPERPLAN_LIMIT_S,
            check=False,
        )
    except subprocess.TimeoutExpired:
        return f">{PYPERPLAN_LIMIT_S:.0f}s"
    finally:
        Path(path).unlink()
    try:
        data = json.loads(proc.stdout.strip().splitlines()[-1])
    except (IndexError, json.JSONDecodeError):
        return "error"
    return f"{data['seconds']:.2f}s/{data['length']}"


def uav_section(planner: TaskPlanner) -> bool:
    """UAV logistics (§11.1.2): shipped scenario and a generated larger one."""
    print("\nUAV logistics (TAL language, flights from straight-line motion-plan-info)")
    print(
        f"{'problem':>22} | {'time':>6} {'acts':>4} {'conc mkspan':>11} "
        f"{'seq mkspan':>10} {'nodes':>5}"
    )
    domain, control = UAV_DOMAIN.read_text(), UAV_CONTROL.read_text()
    problems = [
        ("scenario.tal (leg II)", UAV_SCENARIO.read_text()),
        ("generated 3h/6b/12box", uav_problem(UavSize(3, 6, 12, 2), 1)),
    ]
    ok = True
    for name, text in problems:
        request = PlanRequest(domain, text, control)
        conc = planner.plan(request, timeout=60.0)
        seq = planner.plan(request, timeout=60.0, sequential=True)
        ok &= conc.solved and seq.solved
        total = conc.stats.grounding_seconds + conc.stats.search_seconds
        print(
            f"{name:>22} | {total:>6.2f} {len(conc.plan):>4} {conc.makespan:>11.1f} "
            f"{seq.makespan:>10.1f} {conc.stats.nodes_expanded:>5}"
        )
    return ok


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="only the first four sizes, one seed")
    parser.add_argument("--seeds", type=int, default=2, help="seeds per size (100-package: 1)")
    parser.add_argument("--png", type=Path, default=None, help="write nodes-vs-length plot here")
    parser.add_argument("--pyperplan-worker", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.pyperplan_worker:
        pyperplan_worker(args.pyperplan_worker)
        return 0
    sizes = SIZES[:4] if args.quick else SIZES
    planner = TaskPlanner()
    domain = LOGISTICS_DOMAIN.read_text()
    control = LOGISTICS_CONTROL.read_text()
    header = (
        f"{'pkgs':>4} {'cit':>3} {'apn':>3} {'seed':>4} | {'ground':>6} {'search':>6} {'total':>6} "
        f"{'cpu':>5} {'acts':>4} {'mkspan':>6} {'nodes':>5} {'valid':>5} | "
        f"{'seq len':>7} {'seq t':>6} | "
        f"{'no-ctl':>14} | {'pyperplan t/len':>15}"
    )
    print(header)
    print("-" * len(header))
    points: list[tuple[int, int]] = []
    pyperplan_max_packages = 42  # lowered to the first size where pyperplan times out
    all_ok = True
    for size in sizes:
        seeds = 1 if size.packages > 42 or args.quick else args.seeds
        for seed in range(1, seeds + 1):
            problem = logistics_problem(size, seed)
            request = PlanRequest(domain, problem, control)
            conc = planner.plan(request, timeout=60.0)
            total = conc.stats.grounding_seconds + conc.stats.search_seconds
            valid = validate_pddl_plan(domain, problem, conc.plan).valid if conc.solved else False
            all_ok &= valid
            seq = planner.plan(request, timeout=60.0, sequential=True)
            seq_valid = validate_pddl_plan(domain, problem, seq.plan).valid if seq.solved else False
            all_ok &= seq_valid
            no_ctl = "-"
            if size.packages <= NO_CONTROL_MAX_PACKAGES:
                free = planner.plan(PlanRequest(domain, problem), timeout=10.0)
                if free.solved:
                    ok = validate_pddl_plan(domain, problem, free.plan).valid
                    all_ok &= ok
                    no_ctl = f"{free.stats.search_seconds:.2f}s/{len(free.plan)}{'' if ok else '!'}"
                else:
                    no_ctl = free.status.value
            pyp = "-"
            if size.packages <= pyperplan_max_packages:
                pyp = run_pyperplan(problem)
                if pyp.startswith(">"):
                    pyperplan_max_packages = size.packages
            points.append((len(conc.plan), conc.stats.nodes_expanded))
            print(
                f"{size.packages:>4} {size.cities:>3} {size.airplanes:>3} {seed:>4} | "
                f"{conc.stats.grounding_seconds:>6.2f} {conc.stats.search_seconds:>6.2f} "
                f"{total:>6.2f} {conc.stats.cpu_seconds:>5.2f} "
                f"{len(conc.plan):>4} {conc.makespan:>6.0f} {conc.stats.nodes_expanded:>5} "
                f"{valid!s:>5} | {len(seq.plan):>7} "
                f"{seq.stats.grounding_seconds + seq.stats.search_seconds:>6.2f} | "
                f"{no_ctl:>14} | {pyp:>15}",
                flush=True,
            )
    print(
        "\ncolumns: times in s (ground = parse+ground+compile control; total = wall clock; "
        "cpu = process CPU time of the planning call); acts = actions of the "
        "concurrent plan; mkspan = its makespan (unit durations); nodes = nodes expanded; "
        "valid = unified-planning SequentialPlanValidator; seq len = length of the sequential "
        "plan; no-ctl = TALplanner without control rules (search s/plan length); pyperplan = "
        "up-pyperplan via unified-planning (s/plan length)."
    )
    all_ok &= uav_section(planner)
    if args.png is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(5, 4))
        ax.plot([p[0] for p in points], [p[1] for p in points], "o")
        ax.set_xlabel("plan length (actions)")
        ax.set_ylabel("nodes expanded")
        ax.set_title("TALplanner with control rules, Logistics")
        args.png.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(args.png, dpi=100)
        print(f"plot: {args.png}")
    return 0 if all_ok else 1


if __name__ == "__main__":
    sys.exit(main())
