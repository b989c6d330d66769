"""Benchmark TALplanner on generated problems of the shipped domains.

Logistics table, for every instance: concurrent TALplanner with control rules (plan validated
by unified-planning), the same in sequential mode, TALplanner without control rules (small
instances only) and pyperplan through unified-planning (``up-pyperplan``, run in a child
process with a hard time limit because pyperplan ignores timeouts).

Per-domain table: for each shipped domain with control rules, generated instances of growing
size: solved, median/max wall and CPU time, median plan length, all plans validated by
unified-planning, and Fast Downward ``lama-first`` (``up-fast-downward``) on the same
instances in a child process with a hard time limit. The peak memory (max RSS) of the
benchmark process is printed after each domain.

Usage: .venv/bin/python bench/talplanner.py [--quick] [--domains-only | --no-domains]
       [--only DOMAIN ...] [--seeds N] [--fd-limit S] [--png out/talplanner.png]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import signal
import statistics
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from hdrc3_deliberative.generators import (
    BLOCKS_CONTROL,
    BLOCKS_DOMAIN,
    DEPOTS_CONTROL,
    DEPOTS_DOMAIN,
    DRIVERLOG_CONTROL,
    DRIVERLOG_DOMAIN,
    LOGISTICS_CONTROL,
    LOGISTICS_DOMAIN,
    ROVERS_CONTROL,
    ROVERS_DOMAIN,
    SATELLITE_CONTROL,
    SATELLITE_DOMAIN,
    UAV_CONTROL,
    UAV_DOMAIN,
    UAV_SCENARIO,
    ZENOTRAVEL_CONTROL,
    ZENOTRAVEL_DOMAIN,
    ZENOTRAVEL_NUMERIC_CONTROL,
    ZENOTRAVEL_NUMERIC_DOMAIN,
    DepotsSize,
    DriverLogSize,
    LogisticsSize,
    RoversSize,
    SatelliteSize,
    UavSize,
    ZenoSize,
    blocks_problem,
    depots_problem,
    driverlog_problem,
    logistics_problem,
    rovers_problem,
    satellite_problem,
    uav_problem,
    zenotravel_problem,
)
from hdrc3_deliberative.planner import PlanRequest, TaskPlanner
from hdrc3_deliberative.validation import validate_pddl_plan, widen_either

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
WALL_FACTOR = 15  # wall-clock guard on a child: this many times its CPU limit


PLANNERS: dict[str, tuple[str, dict[str, str]]] = {
    "pyperplan": ("pyperplan", {}),
    "lama-first": ("fast-downward", {"fast_downward_alias": "lama-first"}),
}


def planner_worker(planner_name: str, domain_path: str, problem_path: str, cpu_limit: str) -> None:
    """Child process: solve with a unified-planning engine, print JSON (time, plan length).

    ``seconds`` is CPU time (this process and the planner processes it starts), each
    process limited to ``cpu_limit`` CPU seconds: on a loaded machine wall time would
    measure the load.
    """
    import warnings

    limit = int(float(cpu_limit))
    resource.setrlimit(resource.RLIMIT_CPU, (limit, limit + 5))

    from unified_planning.io import PDDLReader
    from unified_planning.shortcuts import OneshotPlanner, get_environment

    warnings.simplefilter("ignore")
    get_environment().credits_stream = None
    text = Path(domain_path).read_text()
    engine, params = PLANNERS[planner_name]
    with tempfile.TemporaryDirectory() as tmp:  # unified-planning cannot read (either ...)
        widened = Path(tmp) / "domain.pddl"
        widened.write_text(widen_either(text))
        problem = PDDLReader().parse_problem(str(widened), str(Path(problem_path).resolve()))
        os.chdir(tmp)  # Fast Downward writes its translation (output.sas) to the working dir
        start = _cpu_seconds()
        with OneshotPlanner(name=engine, params=params) as planner:
            result = planner.solve(problem)
        elapsed = _cpu_seconds() - start
    length = len(result.plan.actions) if result.plan is not None else -1
    print(json.dumps({"status": result.status.name, "seconds": elapsed, "length": length}))


def _cpu_seconds() -> float:
    """CPU seconds of this process and of its finished children."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def run_planner(
    planner_name: str, domain: Path, problem_text: str, limit: float
) -> dict[str, float] | str:
    """Run a planner in a child process; its figures, or why there are none."""
    with tempfile.NamedTemporaryFile("w", suffix=".pddl", delete=False) as f:
        f.write(problem_text)
        path = f.name
    # own session: on timeout the whole group goes. unified-planning starts Fast Downward in a
    # session of its own, which the CPU limit the worker sets (inherited) bounds instead.
    proc = subprocess.Popen(
        [sys.executable, __file__, "--worker", planner_name, str(domain), path, str(limit)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        stdout, _ = proc.communicate(timeout=limit * WALL_FACTOR)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        return f">{limit * WALL_FACTOR:.0f}w"
    finally:
        Path(path).unlink()
    try:
        data: dict[str, float] = json.loads(stdout.strip().splitlines()[-1])
    except (IndexError, json.JSONDecodeError):
        return "error"
    if data["length"] < 0 and data["seconds"] >= limit - 1:
        return f">{limit:.0f}s"  # the CPU limit stopped the planner
    return data


def run_pyperplan(problem_text: str) -> str:
    data = run_planner("pyperplan", LOGISTICS_DOMAIN, problem_text, PYPERPLAN_LIMIT_S)
    return data if isinstance(data, str) else f"{data['seconds']:.2f}s/{data['length']:.0f}"


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


@dataclass(frozen=True)
class DomainRun:
    """One shipped domain: files and generated instances (label, problem text)."""

    name: str
    domain: Path
    control: Path
    instances: list[tuple[str, str]]


def domain_runs(quick: bool, seeds: int, only: list[str] | None = None) -> list[DomainRun]:
    """Instances of growing size per domain; the last size is the largest we run."""
    seed_list = range(1, (1 if quick else seeds) + 1)
    blocks = [10, 20] if quick else [10, 20, 30, 50]
    zeno = [ZenoSize(5, 2, 5), ZenoSize(10, 3, 10)]
    if not quick:
        zeno += [ZenoSize(20, 5, 25), ZenoSize(30, 8, 40)]
    logistics = SIZES[:3] if quick else SIZES[:6]
    depots = [DepotsSize(1, 2, 2, 3, 3, 6), DepotsSize(3, 3, 4, 8, 8, 15)]
    if not quick:
        depots += [DepotsSize(5, 5, 5, 15, 15, 30), DepotsSize(10, 10, 5, 30, 20, 60)]
    satellite = [SatelliteSize(1, 1, 3, 3, 3), SatelliteSize(3, 2, 3, 10, 10)]
    if not quick:
        satellite += [SatelliteSize(5, 3, 5, 20, 30), SatelliteSize(10, 3, 5, 50, 100)]
    driverlog = [DriverLogSize(3, 1, 2, 1), DriverLogSize(8, 3, 6, 2)]
    if not quick:
        driverlog += [DriverLogSize(15, 5, 15, 4), DriverLogSize(30, 8, 30, 6)]
    rovers = [RoversSize(1, 4, 2, 1, 3), RoversSize(2, 8, 3, 2, 6)]
    if not quick:
        rovers += [RoversSize(4, 20, 6, 5, 15), RoversSize(14, 100, 11, 13, 40)]
    runs = [
        DomainRun(
            "driverlog",
            DRIVERLOG_DOMAIN,
            DRIVERLOG_CONTROL,
            [
                (f"{d.junctions}/{d.drivers}/{d.packages}/{d.trucks}", driverlog_problem(d, s))
                for d in driverlog
                for s in seed_list
            ],
        ),
        DomainRun(
            "rovers",
            ROVERS_DOMAIN,
            ROVERS_CONTROL,
            [
                (
                    f"{r.rovers}/{r.waypoints}/{r.objectives}/{r.cameras}/{r.goals}",
                    rovers_problem(r, s),
                )
                for r in rovers
                for s in seed_list
            ],
        ),
        DomainRun(
            "depots",
            DEPOTS_DOMAIN,
            DEPOTS_CONTROL,
            [
                (
                    f"{d.depots}/{d.distributors}/{d.trucks}/{d.pallets}/{d.hoists}/{d.crates}",
                    depots_problem(d, s),
                )
                for d in depots
                for s in seed_list
            ],
        ),
        DomainRun(
            "satellite",
            SATELLITE_DOMAIN,
            SATELLITE_CONTROL,
            [
                (
                    f"{z.satellites}/{z.instruments}/{z.modes}/{z.targets}/{z.observations}",
                    satellite_problem(z, s),
                )
                for z in satellite
                for s in seed_list
            ],
        ),
        DomainRun(
            "blocks",
            BLOCKS_DOMAIN,
            BLOCKS_CONTROL,
            [(f"{n} blocks", blocks_problem(n, s)) for n in blocks for s in seed_list],
        ),
        DomainRun(
            "zenotravel",
            ZENOTRAVEL_DOMAIN,
            ZENOTRAVEL_CONTROL,
            [
                (f"{z.cities}c/{z.planes}a/{z.people}p", zenotravel_problem(z, s))
                for z in zeno
                for s in seed_list
            ],
        ),
        DomainRun(
            "zeno-num",
            ZENOTRAVEL_NUMERIC_DOMAIN,
            ZENOTRAVEL_NUMERIC_CONTROL,
            [
                (
                    f"{z.cities}c/{z.planes}a/{z.people}p",
                    zenotravel_problem(z, s, numeric=True),
                )
                for z in zeno
                for s in seed_list
            ],
        ),
        DomainRun(
            "logistics",
            LOGISTICS_DOMAIN,
            LOGISTICS_CONTROL,
            [
                (f"{z.packages}p/{z.cities}c/{z.airplanes}a", logistics_problem(z, s))
                for z in logistics
                for s in seed_list
            ],
        ),
    ]
    return [r for r in runs if only is None or r.name in only]


def domains_section(
    planner: TaskPlanner, runs: list[DomainRun], fd_limit: float, timeout: float = 60.0
) -> bool:
    """Per-domain table: TALplanner with control rules beside Fast Downward lama-first."""
    print("\nPer-domain: TALplanner + control rules (validated by unified-planning) vs lama-first")
    header = (
        f"{'domain':>10} {'instance':>18} | {'status':>7} {'wall':>6} {'cpu':>5} {'len':>4} "
        f"{'valid':>5} | {'FD t':>7} {'FD len':>6}"
    )
    print(header)
    print("-" * len(header))
    all_ok = True
    summary = []
    for run in runs:
        domain = run.domain.read_text()
        control = run.control.read_text()
        walls, cpus, lengths, fd_times, fd_lengths = [], [], [], [], []
        solved = fd_solved = 0
        for label, problem in run.instances:
            result = planner.plan(PlanRequest(domain, problem, control), timeout=timeout)
            wall = result.stats.grounding_seconds + result.stats.search_seconds
            valid = False
            if result.solved:
                valid = validate_pddl_plan(domain, problem, result.plan).valid
                solved += valid
                walls.append(wall)
                cpus.append(result.stats.cpu_seconds)
                lengths.append(len(result.plan))
            all_ok &= valid
            fd = run_planner("lama-first", run.domain, problem, fd_limit)
            if isinstance(fd, str):
                fd_text, fd_len = fd, "-"
            else:
                fd_solved += fd["length"] >= 0
                fd_times.append(fd["seconds"])
                fd_lengths.append(fd["length"])
                fd_text, fd_len = f"{fd['seconds']:.2f}", f"{fd['length']:.0f}"
            print(
                f"{run.name:>10} {label:>18} | {result.status.value[:7]:>7} {wall:>6.2f} "
                f"{result.stats.cpu_seconds:>5.2f} {len(result.plan):>4} {valid!s:>5} | "
                f"{fd_text:>7} {fd_len:>6}",
                flush=True,
            )
        rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        print(f"{run.name:>10} peak memory (max RSS of this process so far): {rss:.0f} MB")
        summary.append((run, solved, walls, cpus, lengths, fd_solved, fd_times, fd_lengths))
    print(
        f"\n{'domain':>10} | {'solved':>7} {'wall med/max':>13} {'cpu med/max':>12} "
        f"{'len med':>7} | {'FD solved':>9} {'FD t med/max':>13} {'FD len med':>10}"
    )
    for run, solved, walls, cpus, lengths, fd_solved, fd_times, fd_lengths in summary:
        n = len(run.instances)
        print(
            f"{run.name:>10} | {solved:>3}/{n:<3} {_med_max(walls):>13} {_med_max(cpus):>12} "
            f"{_median(lengths):>7} | {fd_solved:>4}/{n:<4} {_med_max(fd_times):>13} "
            f"{_median(fd_lengths):>10}",
            flush=True,
        )
    print(
        f"columns: wall = parse+ground+search seconds, cpu = process CPU seconds of the "
        f"planning call; len = actions; FD = Fast Downward lama-first through unified-planning "
        f"(child process, CPU limit {fd_limit:.0f} s per process, CPU seconds including its "
        f"translator; >Nw: stopped by the wall-clock guard)."
    )
    return all_ok


def _median(values: list[float] | list[int]) -> str:
    return f"{statistics.median(values):.0f}" if values else "-"


def _med_max(values: list[float]) -> str:
    return f"{statistics.median(values):.2f}/{max(values):.2f}" if values else "-"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="only the first four sizes, one seed")
    parser.add_argument("--seeds", type=int, default=2, help="seeds per size (100-package: 1)")
    parser.add_argument("--png", type=Path, default=None, help="write nodes-vs-length plot here")
    parser.add_argument("--domains-only", action="store_true", help="only the per-domain table")
    parser.add_argument("--no-domains", action="store_true", help="skip the per-domain table")
    parser.add_argument("--fd-limit", type=float, default=60.0, help="Fast Downward CPU limit (s)")
    parser.add_argument("--timeout", type=float, default=60.0, help="TALplanner limit (s)")
    parser.add_argument("--only", nargs="*", default=None, help="per-domain table: these domains")
    parser.add_argument("--worker", nargs=4, default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        planner_worker(*args.worker)
        return 0
    planner = TaskPlanner()
    if args.domains_only:
        return (
            0
            if domains_section(
                planner,
                domain_runs(args.quick, args.seeds, args.only),
                args.fd_limit,
                args.timeout,
            )
            else 1
        )
    sizes = SIZES[:4] if args.quick else SIZES
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
    if not args.no_domains:
        all_ok &= domains_section(
            planner, domain_runs(args.quick, args.seeds, args.only), args.fd_limit, args.timeout
        )
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
