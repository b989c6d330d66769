"""`hdrc3 talf`: TALF mission specifications (chapter section 9.4).

``check FILE`` parses a ``.talf`` file, adds the library of composite actions and checks every
name, action and arity (with ``--capabilities``, also that some AV has what each action needs).
``to-tst FILE`` translates a mission into a Task Specification Tree (its composite actions
expanded), checks it as ``hdrc3 tst check`` does and prints or writes it. ``from-tst FILE.tst``
translates a TST into TALF. ``semantics FILE`` prints a mission's TAL narrative: the
definitions of the composite actions it uses and its translation, loops as least fixpoints.

Exit codes: 0 ok, 2 invalid input (errors as FILE:LINE:COLUMN: error CODE: reason, or a
construct the other language has no counterpart for).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from hdrc3_base.errors import ConfigError
from hdrc3_deliberative.talf_load import LoadResult, load_file
from hdrc3_deliberative.talf_printer import file_text as talf_text
from hdrc3_deliberative.talf_semantics import narrative
from hdrc3_tst.actions import ACTIONS, Capability
from hdrc3_tst.check import CheckStatus
from hdrc3_tst.check import load_text as check_tst
from hdrc3_tst.parser import parse_file as parse_tst
from hdrc3_tst.printer import file_text as tst_text
from hdrc3_tst.talf_translation import TranslationError, from_tst, pick_mission, to_tst

EXIT_OK = 0
EXIT_INVALID = 2


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``talf`` subcommand."""
    parser = subparsers.add_parser(
        "talf", help="TALF mission specifications: check, to-tst, from-tst, semantics"
    )
    actions = parser.add_subparsers(dest="talf_action", metavar="ACTION", required=True)
    epilog = "Exit codes: 0 ok, 2 invalid input (errors as FILE:LINE:COLUMN)."
    check = actions.add_parser("check", help="parse and check a .talf file", description=epilog)
    to = actions.add_parser("to-tst", help="translate a mission into a TST", description=epilog)
    for sub in (check, to):
        sub.add_argument("file", help="a .talf file (examples/talf/)")
        sub.add_argument(
            "--capabilities",
            metavar="AGENT=CAP+CAP",
            action="append",
            default=None,
            help="what an agent offers, e.g. uav2=flight+hook (others: everything)",
        )
    check.set_defaults(handler=_check)
    to.add_argument("--mission", default=None, help="the mission (default: the file's first)")
    to.add_argument("-o", "--output", default=None, help="write the .tst here (default: print)")
    to.set_defaults(handler=_to_tst)
    back = actions.add_parser("from-tst", help="translate a .tst file into TALF")
    back.add_argument("file", help="a .tst file (examples/tst/)")
    back.add_argument("-o", "--output", default=None, help="write the .talf here")
    back.set_defaults(handler=_from_tst)
    sem = actions.add_parser("semantics", help="print a mission's TAL narrative")
    sem.add_argument("file", help="a .talf file")
    sem.add_argument("--mission", default=None, help="the mission (default: the file's first)")
    sem.set_defaults(handler=_semantics)


def parse_capabilities(items: list[str] | None) -> dict[str, frozenset[str]] | None:
    """``uav0=flight+camera`` items -> agent -> capability names; ConfigError if malformed."""
    if items is None:
        return None
    known = {c.value for c in Capability}
    out: dict[str, frozenset[str]] = {}
    for item in items:
        agent, sep, caps = item.partition("=")
        names = frozenset(c.strip() for c in caps.split("+") if c.strip())
        if not sep or not agent.strip() or not names <= known:
            raise ConfigError(
                f"--capabilities {item!r}: expected AGENT=CAP+CAP with CAP one of "
                f"{', '.join(sorted(known))}"
            )
        out[agent.strip()] = names
    return out


def _load(args: argparse.Namespace) -> LoadResult:
    result = load_file(args.file, ACTIONS, parse_capabilities(getattr(args, "capabilities", None)))
    for diag in result.diagnostics:
        print(diag, flush=True)
    if result.tree is None or result.diagnostics:
        print(f"{args.file}: {result.status.value}", flush=True)
    return result


def _output(text: str, output: str | None) -> None:
    if output is None:
        print(text, end="", flush=True)
    else:
        Path(output).write_text(text, encoding="utf-8")


def _check(args: argparse.Namespace) -> int:
    result = _load(args)
    if result.tree is None or result.diagnostics:
        return EXIT_INVALID
    missions, specs = len(result.tree.missions()), len(result.tree.specs())
    print(
        f"{args.file}: ok ({missions} missions, {specs} composite action types with the library)",
        flush=True,
    )
    return EXIT_OK


def _to_tst(args: argparse.Namespace) -> int:
    result = _load(args)
    if result.tree is None or result.diagnostics:
        return EXIT_INVALID
    try:
        tst = to_tst(result.tree, args.mission)
    except TranslationError as exc:
        print(exc, flush=True)
        return EXIT_INVALID
    text = tst_text(tst)
    checked = check_tst(text, args.output or f"{args.file}.tst")
    for diag in checked.diagnostics:
        print(diag, flush=True)
    if checked.status is not CheckStatus.OK:
        print(f"{args.file}: the TST is {checked.status.value}", flush=True)
        return EXIT_INVALID
    _output(text, args.output)
    return EXIT_OK


def _from_tst(args: argparse.Namespace) -> int:
    parsed = parse_tst(args.file)
    for diag in parsed.diagnostics:
        print(diag, flush=True)
    if parsed.tree is None:
        return EXIT_INVALID
    try:
        talf = from_tst(parsed.tree)
    except TranslationError as exc:
        print(exc, flush=True)
        return EXIT_INVALID
    _output(talf_text(talf), args.output)
    return EXIT_OK


def _semantics(args: argparse.Namespace) -> int:
    result = _load(args)
    if result.tree is None or result.diagnostics:
        return EXIT_INVALID
    try:
        mission = pick_mission(result.tree, args.mission)
    except TranslationError as exc:
        print(exc, flush=True)
        return EXIT_INVALID
    print(narrative(result.tree, mission).text(), flush=True)
    return EXIT_OK
