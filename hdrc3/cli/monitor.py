"""``hdrc3 monitor eval``: progress a monitor formula through a recorded trace.

Prints one line per state (time in ms, verdict so far, optionally the residual) and exits 0 if
the final verdict is TRUE or still undecided, 1 if it is FALSE. Traces come from a CSV file
(:mod:`hdrc3_dyknow.trace_csv`) or from an MCAP recording with ``--map FLUENT=/TOPIC.FIELD``
(:mod:`hdrc3_dyknow.trace_mcap`).
"""

from __future__ import annotations

import argparse
from collections.abc import Iterable
from pathlib import Path

from hdrc3_base.errors import ConfigError
from hdrc3_dyknow.formula_parser import FormulaParser
from hdrc3_dyknow.grounding import Scope, quantified_sorts
from hdrc3_dyknow.interpretation import State, parse_atom_key
from hdrc3_dyknow.progression import Progressor, Verdict
from hdrc3_dyknow.trace_csv import read_trace_csv
from hdrc3_dyknow.trace_mcap import parse_fluent_source, read_trace_mcap

EXIT_HOLDS = 0
EXIT_VIOLATED = 1


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``monitor`` command."""
    parser = subparsers.add_parser(
        "monitor", help="execution monitoring with temporal formulas (chapter 9.3)"
    )
    actions = parser.add_subparsers(dest="monitor_command", metavar="ACTION", required=True)
    evaluate = actions.add_parser(
        "eval",
        help="progress a formula through a CSV trace or an MCAP recording",
        description="Exit status: 0 if the formula holds or is undecided, 1 if violated, "
        "2 on bad input.",
    )
    evaluate.add_argument("--formula", required=True, help="monitor formula text")
    source = evaluate.add_mutually_exclusive_group(required=True)
    source.add_argument("--trace", type=Path, help="CSV: time_ms column + one column per fluent")
    source.add_argument("--mcap", type=Path, help="MCAP recording of a flight")
    evaluate.add_argument(
        "--map",
        action="append",
        default=[],
        metavar="FLUENT=/TOPIC.FIELD",
        help="(MCAP) fluent taken from a message field, e.g. altitude(uav0)=/uav0/state.altitude",
    )
    evaluate.add_argument(
        "--period-ms", type=float, help="(MCAP) emit states on this grid, not at message times"
    )
    evaluate.add_argument(
        "--domain",
        action="append",
        default=[],
        metavar="SORT=a,b,c",
        help="objects of a quantified sort (default: every object named in the CSV columns or "
        "the --map fluents)",
    )
    evaluate.add_argument(
        "--bind", action="append", default=[], metavar="VAR=OBJECT", help="bind a free variable"
    )
    evaluate.add_argument("--exec-flag", help="ground fluent that EXEC stands for")
    evaluate.add_argument(
        "--residual", action="store_true", help="also print the residual formula per state"
    )
    evaluate.set_defaults(handler=run_eval)


def run_eval(args: argparse.Namespace) -> int:
    """Handler of ``hdrc3 monitor eval``."""
    formula = FormulaParser().parse(args.formula, source="--formula")
    domains = {
        sort: tuple(obj.strip() for obj in objects.split(",") if obj.strip())
        for sort, objects in _pairs(args.domain, "--domain")
    }
    bindings = dict(_pairs(args.bind, "--bind"))
    states: Iterable[State]
    if args.trace is not None:
        if args.map or args.period_ms is not None:
            raise ConfigError("--map and --period-ms apply to --mcap only")
        trace = read_trace_csv(args.trace)
        states = trace.states
        default_domain = trace.objects
    else:
        sources = [parse_fluent_source(text) for text in args.map]
        states = read_trace_mcap(args.mcap, sources, args.period_ms)
        named = (parse_atom_key(source.fluent)[1] for source in sources)
        default_domain = tuple(dict.fromkeys(obj for args_ in named for obj in args_))
    for sort in quantified_sorts(formula) - domains.keys():
        if not default_domain:
            raise ConfigError(f"the formula quantifies over {sort}: give --domain {sort}=a,b,...")
        domains[sort] = default_domain
    progressor = Progressor(formula, Scope(domains, bindings, args.exec_flag))
    verdict = Verdict.UNDECIDED
    for state in states:
        verdict = progressor.update(state)
        line = f"{_ms_text(state.time_ms)}\t{verdict.name}"
        if args.residual:
            line += f"\t{progressor.residual}"
        print(line, flush=True)
    return EXIT_VIOLATED if verdict == Verdict.FALSE else EXIT_HOLDS


def _ms_text(time_ms: float) -> str:
    """A time in ms without exponent notation or trailing zeros."""
    return str(int(time_ms)) if time_ms == int(time_ms) else f"{time_ms:.6f}".rstrip("0")


def _pairs(texts: list[str], option: str) -> list[tuple[str, str]]:
    pairs = []
    for text in texts:
        name, sep, value = text.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise ConfigError(f"{option} {text!r}: expected NAME=VALUE")
        pairs.append((name.strip(), value.strip()))
    return pairs
