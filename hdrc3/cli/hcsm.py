"""`hdrc3 hcsm`: check, draw and run HCSM models (``.hcsm`` files)."""

from __future__ import annotations

import argparse
from pathlib import Path

from hdrc3_base.errors import ConfigError
from hdrc3_hcsm.conditions import ConditionTable
from hdrc3_hcsm.diagnostics import Severity
from hdrc3_hcsm.event import PostStatus
from hdrc3_hcsm.interpreter import Interpreter, StepStatus
from hdrc3_hcsm.loader import LoadStatus, check_file, load_file
from hdrc3_hcsm.model import Model
from hdrc3_hcsm.render import write_drawing
from hdrc3_hcsm.tables import compile_model
from hdrc3_hcsm.trace import TraceRecorder, read_jsonl, write_jsonl
from hdrc3_hcsm.validation import validate_system

EXIT_OK = 0
EXIT_INVALID = 1


def _check(args: argparse.Namespace) -> int:
    worst = EXIT_OK
    models: list[Model] = []
    for file in args.files:
        result = check_file(file)
        if result.model is not None:
            models.append(result.model)
        for diag in result.diagnostics:
            print(diag)
        errors = sum(d.severity is Severity.ERROR for d in result.diagnostics)
        warnings = len(result.diagnostics) - errors
        if result.status is LoadStatus.OK and result.model is not None:
            m = result.model
            n_trans = sum(len(a.transitions) for a in m.automata)
            print(
                f"{file}: ok ({len(m.automata)} automata, {len(m.events)} events, "
                f"{n_trans} transitions, {warnings} warnings)"
            )
        else:
            print(f"{file}: invalid ({errors} errors, {warnings} warnings)")
            worst = EXIT_INVALID
    if len(models) > 1:
        # Several computers' models: event ids must agree across them.
        system = validate_system(models)
        for diag in system:
            print(diag)
        print(f"system of {len(models)} models: {'ok' if not system else 'invalid'}")
        worst = EXIT_INVALID if system else worst
    return worst


def _render(args: argparse.Namespace) -> int:
    result = check_file(args.file)
    if result.status is not LoadStatus.OK or result.model is None:
        for diag in result.diagnostics:
            print(diag)
        print(f"{args.file}: invalid, not drawn")
        return EXIT_INVALID
    active: tuple[str, ...] = ()
    if args.trace is not None:
        records = read_jsonl(args.trace)
        if not records:
            raise ConfigError(f"trace {args.trace} holds no records")
        index = args.record if args.record is not None else len(records) - 1
        if not -len(records) <= index < len(records):
            raise ConfigError(f"--record {index} outside the trace's {len(records)} records")
        active = records[index].configuration
    write_drawing(result.model, args.output, active)
    print(f"wrote {args.output}")
    return EXIT_OK


def _script(items: list[str], option: str) -> dict[int, list[tuple[str, str]]]:
    """Parse ``STEP:NAME[=VALUE]`` items into ``{step: [(name, value), ...]}``."""
    out: dict[int, list[tuple[str, str]]] = {}
    for item in items:
        step, sep, rest = item.partition(":")
        name, _, value = rest.partition("=")
        if not sep or not step.isdigit() or not name:
            raise ConfigError(f"{option} {item!r}: expected STEP:NAME[=VALUE]")
        out.setdefault(int(step), []).append((name, value))
    return out


def _run(args: argparse.Namespace) -> int:
    compiled = compile_model(load_file(args.file))
    posts = _script(args.post, "--post")
    sets = _script(args.cond, "--cond")
    conds = ConditionTable(compiled.conditions)
    recorder = TraceRecorder(capacity=max(1000, args.steps * 100))
    interp = Interpreter(compiled, conds.callables(), trace=recorder)
    for step in range(args.steps):
        for name, value in sets.get(step, []):
            if name not in compiled.conditions or value not in ("true", "false"):
                raise ConfigError(f"--cond {step}:{name}={value}: unknown condition or value")
            conds.set(name, value == "true")
        for name, data in posts.get(step, []):
            if interp.post_external(name, data.encode() or None) is not PostStatus.ACCEPTED:
                print(f"step {step}: event {name!r} rejected (unknown to the model)")
        first = len(recorder.records())
        result = interp.execute(step * args.period)
        for record in recorder.records()[first:]:
            for fired in record.transitions:
                actions = ", ".join(fired.actions)
                print(
                    f"step {step}: {record.event} -> {fired.tid} {fired.machine}: "
                    f"{fired.source} -> {fired.target}" + (f" / {actions}" if actions else "")
                )
        for event in interp.take_outbox():
            print(f"step {step}: SEND {event.name} to {event.target}")
        for fault in result.faults:
            print(f"step {step}: fault {fault}")
        interp.flags.clear()
        if result.status is not StepStatus.OK:
            print(f"step {step}: {result.status.value}")
            if result.status is StepStatus.LIVELOCK:
                return EXIT_INVALID
    print("configuration: " + " ".join(interp.configuration()))
    if args.trace is not None:
        write_jsonl(recorder.records(), args.trace)
        print(f"wrote {args.trace}")
    return EXIT_OK


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``hcsm`` subcommand with ``check``, ``render`` and ``run``."""
    parser = subparsers.add_parser("hcsm", help="check and draw HCSM state-machine models")
    sub = parser.add_subparsers(dest="hcsm_command", metavar="ACTION", required=True)
    check = sub.add_parser("check", help="validate .hcsm files (exit 1 on errors)")
    check.add_argument("files", nargs="+", type=Path, metavar="FILE")
    check.set_defaults(handler=_check)
    render = sub.add_parser("render", help="draw a model as graphviz .dot (or .svg with dot)")
    render.add_argument("file", type=Path, metavar="FILE")
    render.add_argument("-o", "--output", type=Path, required=True, help="OUT.dot or OUT.svg")
    render.add_argument("--trace", type=Path, help="JSON-lines trace: highlight its configuration")
    render.add_argument(
        "--record", type=int, help="trace record index to highlight (default: the last one)"
    )
    render.set_defaults(handler=_render)
    run = sub.add_parser(
        "run", help="run a model for some macro steps with scripted events and conditions"
    )
    run.add_argument("file", type=Path, metavar="FILE")
    run.add_argument("--steps", type=int, default=10, help="macro steps to run (default 10)")
    run.add_argument("--period", type=float, default=0.02, help="step period in s (default 0.02)")
    run.add_argument(
        "--post",
        action="append",
        default=[],
        metavar="STEP:EVENT[=DATA]",
        help="queue an external event before STEP (repeatable)",
    )
    run.add_argument(
        "--cond",
        action="append",
        default=[],
        metavar="STEP:CONDITION=true|false",
        help="set a condition before STEP; all start false (repeatable)",
    )
    run.add_argument("--trace", type=Path, help="write the JSON-lines trace here")
    run.set_defaults(handler=_run)
