"""Generated missions of any size, for the benchmark and the scaling tests.

The mission is a sequence of groups; each group runs two agents' sequences concurrently, each
a fly-to, a hover and a scan; every group and sequence carries where constraints (deadlines,
speeds), so propagation has work to do at every level.
"""

from __future__ import annotations

NODES_PER_GROUP = 11
"""A concurrent group node, two sequence nodes and four actions in each sequence."""

_HEADER = """world revinge
agents uav0, uav1
area Field = polygon((-280, -40), (-160, -40), (-160, 40), (-280, 40))
point Square = town_square at 30
"""


def generated_mission(groups: int) -> str:
    """A mission of ``1 + 11 * groups`` nodes as TST text."""
    lines = [_HEADER]
    with_vars = ", ".join(f"S{g}, E{g}" for g in range(groups))
    lines.append(f"m(P, TS, TE) = with {with_vars} sequence")
    for g in range(groups):
        seq_vars = ", ".join(f"A{g}_{i}, B{g}_{i}" for i in range(2))
        lines.append(f"  g{g}(S{g}, E{g}) = with {seq_vars}, Q{g} concurrent")
        for i in range(2):
            a, b = f"A{g}_{i}", f"B{g}_{i}"
            times = ", ".join(f"X{g}_{i}_{k}, Y{g}_{i}_{k}" for k in range(4))
            head = f"s{g}_{i}(P{g}_{i}, {a}, {b})" if i else f"s{g}_{i}({a}, {b})"
            lines.append(f"    {head} = with {times} sequence")
            t = [f"X{g}_{i}_{k}, Y{g}_{i}_{k}" for k in range(4)]
            lines += [
                f"      f{g}_{i}({t[0]}) = fly-to({t[0]}, V{g}_{i}, Square);",
                f"      h{g}_{i}({t[1]}) = hover({t[1]}, 5);",
                f"      c{g}_{i}({t[2]}) = scan-area({t[2]}, W{g}_{i}, Field);",
                f"      w{g}_{i}({t[3]}) = wait({t[3]}, 2)",
            ]
            extra = f" and P{g}_{i} = uav1" if i else ""
            scan = f"Y{g}_{i}_2 - X{g}_{i}_2 >= 20"
            end = ";" if i == 0 else ""
            lines.append(f"    where {b} - {a} <= 600 and {scan} and V{g}_{i} <= 10{extra}{end}")
        sep = ";" if g < groups - 1 else ""
        lines.append(f"  where E{g} - S{g} <= 900{sep}")
    lines.append(f"where P = uav0 and TS = 0 and TE <= {groups * 900 + 100}")
    return "\n".join(lines) + "\n"
