"""Formula progression throughput, reproducing Figure 28 of the HDRC3 chapter (section 9.3.3).

Formula: ``always(not p_i implies eventually[0,1000] always[0,999] p_i)``, one per proposition
``p_i`` (distinct propositions, so no sub-formula is shared between formulas). A new state every
100 ms; the chapter fit 1,500-3,000 such formulas into the 100 ms budget on a 1.4 GHz Pentium M.

The chapter names its state streams only "best case, worst case and two intermediate cases". For
this formula the work per state is set by whether an obligation ``eventually[0,1000] always[0,999]
p`` is pending, so the streams here are (all without violating the formula):

* best: p always true - no obligation ever opens;
* worst: p false in one state, then true for 10 states (1000 ms), repeated - every obligation is
  met at the last possible moment, so one is pending (with a running ``always[0,999] p`` attempt)
  in every state;
* intermediate-50: p false once then true for 21 states - an obligation pending half the time;
* intermediate-25: p false once then true for 43 states - pending a quarter of the time.

For each stream and formula count the engine progresses all formulas through every state of the
stream; the figure is the mean CPU time of this process per state (CPU rather than wall time,
and the best of ``--repeat`` runs, because the machine is shared with other jobs). States are
prepared beforehand, as DyKnow's state synchronisation would deliver them. Capacity = formulas
per 100 ms from a least-squares line through the measured points.

Run: ``.venv/bin/python bench/progression.py [--counts 1000 5000 ...] [--out out/progression.png]``
"""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from hdrc3_dyknow.formula_parser import FormulaParser
from hdrc3_dyknow.grounding import Scope
from hdrc3_dyknow.interpretation import State
from hdrc3_dyknow.progression import ProgressionEngine, Verdict
from hdrc3_dyknow.residual import NodeTable

FORMULA = "always(not p(i) implies eventually[0,1000] always[0,999] p(i))"
PERIOD_MS = 100.0
BUDGET_MS = 100.0
# Stream name -> number of true states after each false one (None: always true).
STREAMS: dict[str, int | None] = {
    "best": None,
    "intermediate-25": 43,
    "intermediate-50": 21,
    "worst": 10,
}


@dataclass(frozen=True)
class Point:
    """One measurement: mean time per state for a number of formulas on a stream."""

    stream: str
    formulas: int
    ms_per_state: float
    residual_nodes: int  # distinct nodes in all residuals after the last state


def pattern(true_run: int | None, states: int) -> list[bool]:
    """Value of every p_i in each state of a stream."""
    if true_run is None:
        return [True] * states
    return [k % (true_run + 1) != 0 for k in range(states)]


def measure(
    stream: str, count: int, states: int, parser: FormulaParser, repeat: int, intern: bool
) -> Point:
    """Best of ``repeat`` runs of ``count`` formulas through ``states`` states of ``stream``."""
    runs = [run(stream, count, states, parser, intern) for _ in range(repeat)]
    return min(runs, key=lambda point: point.ms_per_state)


def run(stream: str, count: int, states: int, parser: FormulaParser, intern: bool = False) -> Point:
    """Progress ``count`` formulas through ``states`` states of ``stream``."""
    engine = ProgressionEngine(NodeTable(intern_residuals=intern))
    template = parser.parse(FORMULA)
    for i in range(count):
        engine.add(template, Scope(bindings={"i": str(i)}))
    keys = [f"p({i})" for i in range(count)]
    values = pattern(STREAMS[stream], states)
    prepared = [State(k * PERIOD_MS, dict.fromkeys(keys, value)) for k, value in enumerate(values)]
    durations = []
    for state in prepared:
        start = time.process_time()
        decided = engine.update(state)
        durations.append(time.process_time() - start)
        if decided:
            raise AssertionError(f"{stream}: a formula was decided: {decided[0][1]}")
    assert engine.verdict(0) == Verdict.UNDECIDED
    return Point(stream, count, 1000.0 * statistics.fmean(durations), engine.residual_size())


def capacity(points: list[Point]) -> float:
    """Formulas per 100 ms from a least-squares line through (formulas, ms per state)."""
    slope, intercept = statistics.linear_regression(
        [p.formulas for p in points], [p.ms_per_state for p in points]
    )
    return (BUDGET_MS - intercept) / slope


def plot(results: dict[str, list[Point]], out: Path) -> None:
    """Write the Figure 28 style plot: time per state over formulas per state."""
    out.parent.mkdir(parents=True, exist_ok=True)
    figure, axes = plt.subplots(figsize=(7, 4.5))
    for stream, points in results.items():
        axes.plot(
            [p.formulas for p in points],
            [p.ms_per_state for p in points],
            marker="o",
            label=f"{stream} ({capacity(points):,.0f} per 100 ms)",
        )
    axes.axhline(BUDGET_MS, color="grey", linestyle="--", linewidth=1, label="100 ms budget")
    axes.set_xlabel("formulas progressed per state")
    axes.set_ylabel("average CPU time per state (ms)")
    axes.set_title("Progression: always(not p -> eventually[0,1000] always[0,999] p)")
    axes.grid(True, alpha=0.3)
    axes.legend()
    figure.tight_layout()
    figure.savefig(out, dpi=120)
    plt.close(figure)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--counts", type=int, nargs="+", default=[2000, 6000, 10000, 15000])
    # 44 states: the worst stream repeats 4 times, and the intermediate ones have an obligation
    # pending in exactly 50 % / 25 % of the states.
    parser.add_argument("--states", type=int, default=44, help="states per stream (100 ms apart)")
    parser.add_argument("--repeat", type=int, default=2, help="runs per point; the best counts")
    parser.add_argument("--out", type=Path, default=Path("out/progression.png"))
    parser.add_argument(
        "--intern-residuals", action="store_true", help="also hash-cons residuals per state"
    )
    args = parser.parse_args()
    formula_parser = FormulaParser()
    results: dict[str, list[Point]] = {}
    print(f"{'stream':<16} {'formulas':>9} {'ms/state':>9} {'us/formula':>11} {'nodes':>8}")
    for stream in STREAMS:
        results[stream] = []
        for count in args.counts:
            point = measure(
                stream, count, args.states, formula_parser, args.repeat, args.intern_residuals
            )
            results[stream].append(point)
            print(
                f"{stream:<16} {count:>9} {point.ms_per_state:>9.2f} "
                f"{1000 * point.ms_per_state / count:>11.2f} {point.residual_nodes:>8}",
                flush=True,
            )
    print()
    for stream, points in results.items():
        print(f"{stream:<16} capacity: {capacity(points):>9,.0f} formulas per 100 ms")
    plot(results, args.out)
    print(f"plot: {args.out}")


if __name__ == "__main__":
    main()
