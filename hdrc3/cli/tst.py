"""`hdrc3 tst`: Task Specification Trees (chapter section 6.3).

``check FILE`` parses the file, resolves it against its world and agents and propagates its
constraint network, then prints the tree with each node's earliest/latest start and end.
Exit codes: 0 ok, 4 invalid input (syntax, unknown names, inconsistent constraints).
"""

from __future__ import annotations

import argparse

from hdrc3_base.agents import parse_agents
from hdrc3_tst.check import CheckStatus, load_file, tree_lines

EXIT_OK = 0
EXIT_INVALID = 4


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``tst`` subcommand."""
    parser = subparsers.add_parser("tst", help="task specification trees: check")
    actions = parser.add_subparsers(dest="tst_action", metavar="ACTION", required=True)
    check = actions.add_parser(
        "check",
        help="parse, resolve and propagate a .tst file; print the tree with its time windows",
        description="Exit codes: 0 ok, 4 invalid input (errors as FILE:LINE:COLUMN).",
    )
    check.add_argument("file", help="a .tst file (examples/tst/)")
    check.add_argument(
        "--agents", default=None, help="agents in addition to the file's own, e.g. uav0,uav1"
    )
    check.set_defaults(handler=_check)


def _check(args: argparse.Namespace) -> int:
    agents = parse_agents(args.agents) if args.agents is not None else ()
    result = load_file(args.file, agents)
    for diag in result.diagnostics:
        print(diag, flush=True)
    if result.status is not CheckStatus.OK or result.tst is None:
        print(f"{args.file}: {result.status.value}", flush=True)
        return EXIT_INVALID
    for line in tree_lines(result.tst):
        print(line, flush=True)
    tst = result.tst
    net = tst.network
    n_cons = len(net.finite.linear) + len(net.finite.symbolic)
    print(
        f"{args.file}: ok ({len(tst.tree.nodes)} nodes, {len(net.stn.variables)} time "
        f"variables, {net.stn.edge_count} temporal and {n_cons} other constraints)",
        flush=True,
    )
    return EXIT_OK
