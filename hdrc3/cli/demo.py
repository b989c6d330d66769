"""`hdrc3 demo`: the main job: the emergency-services mission (chapter 11.1) with two RMAXes.

By default it flies the flagship (``hdrc3.flagship``) from a TALF mission file (``--mission``,
default ``hdrc3/missions/emergency.talf``; a file refused by the TALF checks exits 4 before
anything starts): leg I scans the fields south-west of revinge's town with both aircraft and
builds the saliency map; TALplanner allocates a food and a
medicine box per body found; leg II delivers them under execution monitoring and lands. Products
go to ``--out``: the recording, both TSTs, the planning problem and plan, the map, the timelines.
``--short`` flies ``emergency_short.talf``, a small rectangle next to the pads, with one box per
body (``make flights`` runs it).

``--basic`` is the first demo: one RMAX surveys a field through FCL alone (take-off, fly-to, a
lawn-mower survey streamed as traj3d segments, landing) and a PNG of track, speed profile and
command timeline is written beside the recording; ``--basic --short`` flies a smaller survey.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from importlib.resources import files
from pathlib import Path

from hdrc3.demo_mission import MissionError, SurveyMission
from hdrc3.emergency_mission import box_drops
from hdrc3.emergency_report import evaluate, write_page
from hdrc3.emergency_spec import load_mission
from hdrc3.flagship import Flagship, flagship_summary
from hdrc3.flight_report import build_report, plot_report
from hdrc3.launched_system import LaunchedSystem
from hdrc3.safety_pilot import hand_over
from hdrc3.survey import SurveyArea, lawn_mower
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import RosProcess
from hdrc3_platform_server.client import PlatformClient
from hdrc3_platform_server.geo_frame import frame_from_world

MISSIONS = files("hdrc3.missions")
"""The flagship's TALF mission files (``hdrc3/missions/``)."""
FULL_KITS = ("food", "medicine")
SHORT_KITS = ("food",)
FLAGSHIP_SEED = 2
"""The flagship's default seed (sensor noise and GPS outages): the one its figures come from."""
AGENT = "uav0"
WORLD = "revinge"
# Open fields west of the town, clear of buildings; legs run south, turns to the east.
SURVEY = SurveyArea(
    corner_east=-280.0,
    corner_north=120.0,
    leg_length=220.0,
    spacing=40.0,
    legs=3,
    altitude=30.0,
    heading=math.pi,
)
# Two 100 m legs in the field beside pad H1, lower: still a streamed path (three segments, two
# segment requests), with a short fly-to and a short descent. Legs run north, the turn west.
SHORT_SURVEY = SurveyArea(
    corner_east=-250.0,
    corner_north=-100.0,
    leg_length=100.0,
    spacing=40.0,
    legs=2,
    altitude=20.0,
    heading=0.0,
)


EXIT_INVALID = 4
"""The mission file was refused (syntax, names, capabilities): nothing flew."""


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the `demo` subcommand."""
    parser = subparsers.add_parser("demo", help="fly the demo survey mission and report on it")
    parser.add_argument("--out", default="out/demo", help="output directory (default out/demo)")
    parser.add_argument("--domain-id", type=int, default=42, help="ROS domain (default 42)")
    parser.add_argument("--speed", default="max", help="real-time factor or 'max' (default)")
    parser.add_argument(
        "--short",
        action="store_true",
        help="a smaller mission: a small rectangle and one box per body (--basic: 2 legs of 100 m)",
    )
    parser.add_argument(
        "--basic", action="store_true", help="the single-aircraft FCL survey demo instead"
    )
    parser.add_argument(
        "--mission",
        default=None,
        help="the flagship's TALF mission file (default: hdrc3/missions/emergency.talf, "
        "--short: emergency_short.talf)",
    )
    parser.add_argument(
        "--seed",
        type=int,
        default=None,
        help=f"simulation seed: sensor noise and outages (default {FLAGSHIP_SEED}; --basic: 0)",
    )
    parser.set_defaults(handler=run)


def _echo(line: str) -> None:
    print(line, flush=True)


def run(args: argparse.Namespace) -> int:
    """The flagship, or with ``--basic`` the FCL survey; exit 0 only if the mission succeeded."""
    if not args.basic:
        return run_flagship(args)
    return run_basic(args)


def run_flagship(args: argparse.Namespace) -> int:
    """Fly the emergency-services mission; print the summary."""
    out = Path(args.out)
    default = "emergency_short.talf" if args.short else "emergency.talf"
    path = Path(args.mission) if args.mission else Path(str(MISSIONS.joinpath(default)))
    spec = load_mission(path, SHORT_KITS if args.short else FULL_KITS)
    for diag in spec.diagnostics:
        print(diag, flush=True)
    if spec.mission is None:
        print(f"{path}: {spec.status.value}; nothing flew", file=sys.stderr, flush=True)
        return EXIT_INVALID
    mission = spec.mission
    print(f"mission {path}: {', '.join(mission.agents)} in {mission.world}", flush=True)
    seed = FLAGSHIP_SEED if args.seed is None else args.seed
    started = time.monotonic()
    result = Flagship(mission, out, _echo).run(args.speed, args.domain_id, seed)
    wall = time.monotonic() - started
    summary = flagship_summary(result, out)
    recording = out / "run.mcap"
    if recording.exists():
        drops = box_drops(result.kits, result.depot) if result.kits else {}
        evaluation = evaluate(recording, mission.world, mission.region, result.bodies, drops)
        summary[1:1] = evaluation.summary()
        summary += ["targets (issue 18):"] + [
            f"  [{'met' if met else 'NOT MET'}] {what}" for what, met in evaluation.targets(wall)
        ]
        page = write_page(
            out / "report", recording, evaluation, mission.region, result.bodies, summary
        )
        summary.append(f"  report: {page}")
    print()
    for line in summary:
        print(line, flush=True)
    if not result.succeeded:
        print(f"MISSION FAILED: {result.failure or 'a leg failed'}", file=sys.stderr, flush=True)
        return 1
    print("mission completed", flush=True)
    return 0


def run_basic(args: argparse.Namespace) -> int:
    """Launch, fly, stop, report; exit 0 only if every step of the mission finished."""
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    recording = out / "run.mcap"
    plot = out / "flight.png"
    frame = frame_from_world(WORLD)
    survey = lawn_mower(SHORT_SURVEY if args.short else SURVEY, leg_speed=8.0, turn_speed=3.0)
    failure = ""
    seed = 0 if args.seed is None else args.seed
    system = LaunchedSystem(
        [AGENT], WORLD, args.speed, args.domain_id, record=recording, log=_echo, seed=seed
    )
    with system, RosProcess() as process:
        client = PlatformClient(process, AGENT)
        mission = SurveyMission(client, frame, survey, log=lambda s: print(f"  {s}"))
        try:
            hand_over(process, client.node, AGENT)
            print("  safety pilot: engine on, RC switch to autonomous", flush=True)
            mission.run()
        except (MissionError, ConfigError) as exc:
            failure = str(exc)
        client.node.destroy_node()
    code = system.returncode
    report = build_report(recording, AGENT, (frame.latitude, frame.longitude, frame.altitude))
    path_events = [e.time for e in report.events if e.command == "fcl_traj3d"]
    if path_events:
        report.measure_cross_track(survey, (min(path_events), max(path_events)))
    plot_report(report, plot, survey)
    print()
    print("\n".join(report.summary()))
    print(f"\nrecording: {recording}\nplot:      {plot}")
    if failure:
        print(f"MISSION FAILED: {failure}", file=sys.stderr)
        return 1
    print("mission completed")
    return 0 if code == 0 else 1
