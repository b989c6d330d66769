"""Benchmark TALF -> TST: parse, check, expand and translate a generated 200-action mission.

The mission is a concurrency of branches, one per agent, each a sequence of deliver-box calls
(the library's composite action: four elementary actions each), so the translation expands
50 composite action terms into 200 elementary action nodes. Target (issue 18): the whole
TALF -> TST translation (parse, check, expansion, TST tree and text) <= 100 ms. Prints wall
and CPU time per stage, the median over the repeats (the machine is shared: CPU time is the
figure less disturbed by other processes); the TST text is checked once with hdrc3_tst.

Usage: .venv/bin/python bench/talf.py [--actions 200] [--agents 5] [--repeat 20]
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable
from functools import partial
from typing import TypeVar

from hdrc3_deliberative.talf_check import check
from hdrc3_deliberative.talf_expand import expand
from hdrc3_deliberative.talf_library import with_library
from hdrc3_deliberative.talf_parser import parse_text
from hdrc3_deliberative.talf_syntax import TalfFile
from hdrc3_tst.actions import ACTIONS
from hdrc3_tst.check import CheckStatus, load_text
from hdrc3_tst.printer import file_text
from hdrc3_tst.talf_translation import to_tst

T = TypeVar("T")
ACTIONS_PER_CALL = 4


def timed(fn: Callable[[], T]) -> tuple[T, float, float]:
    """The result of ``fn()`` with its wall and CPU time in milliseconds."""
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn()
    return out, (time.perf_counter() - wall) * 1e3, (time.process_time() - cpu) * 1e3


def generated_mission(actions: int, agents: int) -> str:
    """A TALF mission of ``actions`` elementary actions (deliver-box calls) over ``agents``."""
    calls = actions // ACTIONS_PER_CALL
    names = [f"uav{i}" for i in range(agents)]
    lines = [
        "world revinge",
        f"agents {', '.join(names)}",
        "point Depot = supply_depot at 20",
        "point Above = west_field at 20",
        "point Field = west_field at 0",
        "point box1 = box1 at 0",
        "mission generated:",
    ]
    outer = ", ".join(f"P{a}, b{a}, c{a}" for a in range(agents))
    lines.append(f"  [TS, TE] with {outer} do (")
    for a in range(agents):
        mine = range(a, calls, agents)
        times = ", ".join(f"s{k}, e{k}" for k in mine)
        lines.append(f"    [b{a}, c{a}] by P{a} with {times} do (")
        steps = [
            f"      [s{k}, e{k}] deliver-box(P{a}, box1, Depot, Above, Field, 6)" for k in mine
        ]
        lines.append(" ;\n".join(steps))
        sep = " ||" if a < agents - 1 else ""
        lines.append(f"    ) where P{a} = {names[a]}{sep}")
    lines.append("  ) where TS = 0 and TE <= 36000")
    return "\n".join(lines) + "\n"


def _to_text(tree: TalfFile) -> str:
    return file_text(to_tst(tree))


def translate(text: str) -> str:
    """The whole pipeline: TALF text -> TST text."""
    parsed = parse_text(text, "generated.talf")
    assert parsed.tree is not None, parsed.diagnostics
    tree = with_library(parsed.tree)
    diags = check(tree, ACTIONS)
    assert not diags, diags
    return file_text(to_tst(tree))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--actions", type=int, default=200)
    ap.add_argument("--agents", type=int, default=5)
    ap.add_argument("--repeat", type=int, default=20)
    args = ap.parse_args()
    text = generated_mission(args.actions, args.agents)
    tst_text = translate(text)  # warm the parser cache (grammar analysis is once per process)
    checked = load_text(tst_text, "generated.tst")
    assert checked.status is CheckStatus.OK and checked.tst is not None, checked.diagnostics
    n_actions = sum(1 for n in checked.tst.tree.nodes.values() if n.action in ACTIONS)
    stages: dict[str, list[tuple[float, float]]] = {}
    for _ in range(args.repeat):
        parsed, wall, cpu = timed(lambda: parse_text(text, "generated.talf"))
        stages.setdefault("parse", []).append((wall, cpu))
        assert parsed.tree is not None
        tree = with_library(parsed.tree)
        _, wall, cpu = timed(partial(check, tree, ACTIONS))
        stages.setdefault("check", []).append((wall, cpu))
        mission = tree.missions()[0]
        _, wall, cpu = timed(partial(expand, mission, tree.specs()))
        stages.setdefault("expand", []).append((wall, cpu))
        _, wall, cpu = timed(partial(_to_text, tree))
        stages.setdefault("to-tst (expand, tree, text)", []).append((wall, cpu))
        _, wall, cpu = timed(lambda: translate(text))
        stages.setdefault("total TALF -> TST", []).append((wall, cpu))
    print(
        f"generated TALF mission: {len(text)} characters, {args.actions // ACTIONS_PER_CALL} "
        f"deliver-box calls over {args.agents} agents -> TST of {len(checked.tst.tree.nodes)} "
        f"nodes, {n_actions} elementary actions (hdrc3 tst check: ok); median of {args.repeat}"
    )
    for name, rows in stages.items():
        wall = statistics.median(r[0] for r in rows)
        cpu = statistics.median(r[1] for r in rows)
        print(f"  {name:30s} wall {wall:7.2f} ms   cpu {cpu:7.2f} ms")
    rows = stages["total TALF -> TST"]
    for what, total in (
        ("wall", statistics.median(r[0] for r in rows)),
        ("cpu", statistics.median(r[1] for r in rows)),
    ):
        verdict = "met" if total <= 100 else "NOT met"
        print(f"target total <= 100 ms ({what}): {verdict} ({total:.1f} ms)")


if __name__ == "__main__":
    main()
