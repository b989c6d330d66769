"""Path planner figures on revinge (issue 13 targets; chapter 7.1: mean below 1000 ms).

Prints: roadmap build time and size (built fresh in a temporary cache); for ``--queries`` random
feasible queries (start and goal clear of obstacles and no-fly zones, 8-45 m up) the PRM query
mean/p95 planning time and success; the same with a random horizontal start direction (a replan
joining the segment in flight; NO_PATH when it cannot be joined); RRT-Connect success within 1 s;
PRM+RRT with a random query-time no-fly zone (a 30-80 m rectangle that leaves start and goal
outside) success and mean; and, on ``--ref-queries`` of them, the ratio of the PRM path length
(smoothed cubic segments) to the best path of a long offline run (OMPL RRT* with the path-length
objective for ``--ref-time`` s, then OMPL's ``simplifyMax``), both under the same world no-fly zone.

Run: .venv/bin/python bench/path_planning.py [--queries 200] [--ref-queries 20] [--ref-time 30]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
from ompl import base as ob
from ompl import geometric as og

from hdrc3_navigation.constraints import ConstraintChecker, Constraints
from hdrc3_navigation.gis import Gis
from hdrc3_navigation.ompl_space import OmplSpace
from hdrc3_navigation.planner import PathPlanner, PlannerKind, PlanRequest, PlanResult
from sim.world_loader import load_world

Vec3 = tuple[float, float, float]


def random_point(gis: Gis, checker: ConstraintChecker, rng: np.random.Generator) -> Vec3:
    """A random configuration clear of the world and its no-fly zones."""
    (e0, n0, _), (e1, n1, _) = gis.bounds
    while True:
        p = (float(rng.uniform(e0, e1)), float(rng.uniform(n0, n1)), float(rng.uniform(8, 45)))
        if gis.point_free(p) and checker.point_ok(p):
            return p


def random_zone(
    rng: np.random.Generator, gis: Gis, a: Vec3, b: Vec3
) -> tuple[tuple[float, float], ...]:
    """A 30-80 m rectangle whose margin-grown footprint leaves a and b outside."""
    (e0, n0, _), (e1, n1, _) = gis.bounds
    m = gis.margin + 1.0
    while True:
        w, h = rng.uniform(30, 80, 2)
        x, y = rng.uniform(e0, e1 - w), rng.uniform(n0, n1 - h)
        if all(not (x - m <= p[0] <= x + w + m and y - m <= p[1] <= y + h + m) for p in (a, b)):
            return ((x, y), (x + w, y), (x + w, y + h), (x, y + h))


def reference_length(gis: Gis, a: Vec3, b: Vec3, seconds: float) -> float | None:
    """Best path length of RRT* (path-length objective) run for ``seconds``, then simplified."""
    checker = ConstraintChecker(gis, Constraints(), 10.0)
    space = OmplSpace(
        gis,
        point_ok=checker.point_ok,
        segment_ok=lambda p, q: checker.polyline_ok(np.array([p, q], float)),
    )
    pdef = ob.ProblemDefinition(space.si)
    start, goal = space.state(a), space.state(b)
    pdef.setStartAndGoalStates(start, goal)
    objective = ob.PathLengthOptimizationObjective(space.si)
    pdef.setOptimizationObjective(objective)
    planner = og.RRTstar(space.si)
    planner.setProblemDefinition(pdef)
    planner.setup()
    planner.solve(seconds)
    if not pdef.hasExactSolution():
        return None
    path = pdef.getSolutionPath()
    og.PathSimplifier(space.si).simplifyMax(path)
    return float(path.length())


def summary(name: str, results: list[PlanResult]) -> None:
    """One line: success, mean and p95 planning time of successful queries."""
    ok = [r for r in results if r.ok]
    ms = sorted(r.planning_time * 1e3 for r in ok)
    p95 = ms[min(len(ms) - 1, int(0.95 * len(ms)))] if ms else float("nan")
    mean = statistics.fmean(ms) if ms else float("nan")
    statuses: dict[str, int] = {}
    for r in results:
        statuses[r.status.value] = statuses.get(r.status.value, 0) + 1
    print(
        f"{name:<34} success {len(ok)}/{len(results)} ({100 * len(ok) / len(results):.1f}%)  "
        f"mean {mean:.1f} ms  p95 {p95:.1f} ms  max {ms[-1] if ms else float('nan'):.1f} ms  "
        f"{statuses}",
        flush=True,
    )


def main() -> None:
    """Build the roadmap, run the queries, print the figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", default="revinge")
    parser.add_argument("--queries", type=int, default=200)
    parser.add_argument("--ref-queries", type=int, default=20)
    parser.add_argument("--ref-time", type=float, default=30.0)
    parser.add_argument("--seed", type=int, default=13)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    world = load_world(args.world)
    with tempfile.TemporaryDirectory() as tmp:
        planner = PathPlanner(Gis(world), Path(tmp))
        t0 = time.perf_counter()
        roadmap, built = planner.roadmap()
        assert built
        print(
            f"roadmap {args.world}: {roadmap.size[0]} nodes, {roadmap.size[1]} edges, built in "
            f"{time.perf_counter() - t0:.1f} s",
            flush=True,
        )
        t0 = time.perf_counter()
        planner.cache.load(roadmap.key)
        print(f"roadmap cache load: {(time.perf_counter() - t0) * 1e3:.0f} ms", flush=True)
        gis = planner.gis
        checker = ConstraintChecker(gis, Constraints(), 10.0)
        pairs = [
            (random_point(gis, checker, rng), random_point(gis, checker, rng))
            for _ in range(args.queries)
        ]
        prm = [
            planner.plan(PlanRequest(a, b, 10.0, planner=PlannerKind.PRM, timeout=5.0))
            for a, b in pairs
        ]
        summary("PRM", prm)
        turn = np.random.default_rng(args.seed + 1)  # the other figures keep their draws
        joined = []
        for a, b in pairs:
            heading = float(turn.uniform(0.0, 2.0 * np.pi))
            direction = (float(np.sin(heading)), float(np.cos(heading)), 0.0)
            request = PlanRequest(
                a, b, 10.0, planner=PlannerKind.PRM, timeout=5.0, start_direction=direction
            )
            joined.append(planner.plan(request))
        summary("PRM, random start direction", joined)
        stops = statistics.fmean(r.hover_stops for r in joined if r.ok)
        print(f"  hover stops per path: {stops:.2f}", flush=True)
        rrt = [
            planner.plan(PlanRequest(a, b, 10.0, planner=PlannerKind.RRT, timeout=1.0))
            for a, b in pairs
        ]
        summary("RRT-Connect (1 s budget)", rrt)
        zoned = []
        for a, b in pairs:
            zone = Constraints(no_fly=(random_zone(rng, gis, a, b),))
            zoned.append(
                planner.plan(PlanRequest(a, b, 10.0, zone, PlannerKind.PRM_RRT, timeout=5.0))
            )
        summary("PRM+RRT, random query no-fly zone", zoned)
        print(
            f"  of which reconnected by RRT: {sum(r.reconnected for r in zoned)}; "
            f"hover stops per path (PRM): "
            f"{statistics.fmean(r.hover_stops for r in prm if r.ok):.2f}",
            flush=True,
        )
        ratios = []
        for (a, b), ours in list(zip(pairs, prm, strict=True))[: args.ref_queries]:
            best = reference_length(gis, a, b, args.ref_time)
            if best is None or not ours.ok:
                print(f"  reference: no solution for {a} -> {b}", flush=True)
                continue
            ratios.append(ours.length / best)
        if ratios:
            within = sum(r <= 1.15 for r in ratios)
            print(
                f"path length / RRT* {args.ref_time:.0f} s + simplifyMax: mean "
                f"{statistics.fmean(ratios):.3f}  max {max(ratios):.3f}  "
                f"<= 1.15 in {within}/{len(ratios)}",
                flush=True,
            )


if __name__ == "__main__":
    main()
