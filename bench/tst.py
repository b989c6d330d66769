"""Benchmark the TST core: parse, resolve and propagate a generated 1,000-node mission.

Also the incremental update when one parameter is fixed (mixed initiative, ``hdrc3 tst set``).

Targets (issue 12): parse + full propagation <= 50 ms; one parameter fixed -> incremental
update <= 1 ms median. Prints wall and CPU time (the machine is shared: CPU time is the
figure less disturbed by other processes).

Usage: .venv/bin/python bench/tst.py [--groups 91] [--fixes 200]
"""

from __future__ import annotations

import argparse
import random
import statistics
import time
from collections.abc import Callable
from functools import partial
from typing import TypeVar

from hdrc3_tst.check import CheckStatus, load_text
from hdrc3_tst.generate import NODES_PER_GROUP, generated_mission
from hdrc3_tst.network import FixStatus
from hdrc3_tst.parser import parse_text
from hdrc3_tst.resolver import resolve
from hdrc3_tst.worlds import WorldCache

T = TypeVar("T")


def timed(fn: Callable[[], T]) -> tuple[T, float, float]:
    """The result of ``fn()`` with its wall and CPU time in milliseconds."""
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn()
    return out, (time.perf_counter() - wall) * 1e3, (time.process_time() - cpu) * 1e3


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--groups", type=int, default=91, help="11 nodes each (+1 root)")
    ap.add_argument("--fixes", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    text = generated_mission(args.groups)
    nodes = 1 + NODES_PER_GROUP * args.groups
    # The world's facts are loaded once and kept (a long-lived caller's WorldCache); the text
    # is parsed and the mission resolved and propagated from scratch at every repetition.
    worlds = WorldCache()
    load_text(text, worlds=worlds)
    rows = []
    for _ in range(args.repeat):
        parsed, p_wall, p_cpu = timed(lambda: parse_text(text))
        assert parsed.tree is not None
        resolved, r_wall, r_cpu = timed(partial(resolve, parsed.tree, worlds=worlds))
        assert resolved.tst is not None
        stn = resolved.tst.network.stn
        _, s_wall, s_cpu = timed(stn.propagate)
        rows.append((p_wall, p_cpu, r_wall, r_cpu, s_wall, s_cpu))
    best = [min(col) for col in zip(*rows, strict=True)]
    print(
        f"generated TST: {nodes} nodes, {len(text)} characters, {len(stn.variables)} time "
        f"variables, {stn.edge_count} distance-graph edges (best of {args.repeat})"
    )
    print(f"  parse (lark LALR + syntax tree)         {best[0]:8.1f} ms wall {best[1]:8.1f} ms cpu")
    print(f"  resolve + full propagation (STN+CP-SAT) {best[2]:8.1f} ms wall {best[3]:8.1f} ms cpu")
    print(f"    of which STN full propagation         {best[4]:8.1f} ms wall {best[5]:8.1f} ms cpu")
    print(
        f"  parse + resolve + propagate             {best[0] + best[2]:8.1f} ms wall "
        f"{best[1] + best[3]:8.1f} ms cpu   (target <= 50 ms)",
        flush=True,
    )

    result = load_text(text, worlds=worlds)
    assert result.status is CheckStatus.OK and result.tst is not None
    tst = result.tst
    rng = random.Random(7)
    leaves = [n for n in tst.tree.nodes.values() if not n.children]
    walls, cpus, outcomes = [], [], {s: 0 for s in FixStatus}
    for _ in range(args.fixes):
        node = rng.choice(leaves)
        param = rng.choice(("TS", "TE"))
        window = tst.network.window(node.params[param])
        value = round(window.earliest + rng.random() * min(window.latest - window.earliest, 50), 3)
        fix, wall, cpu = timed(partial(tst.set, node.node_id, param, value))
        outcomes[fix.status] += 1
        walls.append(wall)
        cpus.append(cpu)
    ok = ", ".join(f"{n} {s.value}" for s, n in outcomes.items() if n)
    print(f"fix one time parameter of a random leaf ({args.fixes} fixes in a row: {ok})")
    print(
        f"  incremental STN update   median {statistics.median(walls):6.3f} ms wall "
        f"{statistics.median(cpus):6.3f} ms cpu, p90 {statistics.quantiles(walls, n=10)[-1]:6.3f} "
        "ms wall   (target <= 1 ms median)"
    )
    speeds = [n for n in leaves if "speed" in n.params][:20]
    walls = []
    for node in speeds:
        _, wall, _ = timed(partial(tst.set, node.node_id, "speed", 5.0))
        walls.append(wall)
    print(
        f"fix one speed (CP-SAT re-solve of the {len(tst.network.finite.linear)} linear and "
        f"{len(tst.network.finite.symbolic)} symbolic constraints)  median "
        f"{statistics.median(walls):6.1f} ms wall",
        flush=True,
    )


if __name__ == "__main__":
    main()
