"""`hdrc3 demo`: the main job: one RMAX in revinge surveys a field through FCL and lands.

Launches the agent's nodes with recording, flies take-off, a fly-to, a lawn-mower survey
streamed as traj3d segments and a landing through the Platform Server, stops the system, and
writes a PNG of track, speed profile and command timeline beside the recording. ``--short``
flies the same mission over a smaller survey next to the pad (two short legs and one turn: three
streamed segments), which the test suite runs.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from hdrc3.demo_mission import MissionError, SurveyMission
from hdrc3.flight_report import build_report, plot_report
from hdrc3.launched_system import LaunchedSystem
from hdrc3.safety_pilot import hand_over
from hdrc3.survey import SurveyArea, lawn_mower
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import RosProcess
from hdrc3_platform_server.client import PlatformClient
from hdrc3_platform_server.geo_frame import frame_from_world

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


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the `demo` subcommand."""
    parser = subparsers.add_parser("demo", help="fly the demo survey mission and report on it")
    parser.add_argument("--out", default="out/demo", help="output directory (default out/demo)")
    parser.add_argument("--domain-id", type=int, default=42, help="ROS domain (default 42)")
    parser.add_argument("--speed", default="max", help="real-time factor or 'max' (default)")
    parser.add_argument(
        "--short",
        action="store_true",
        help="a smaller survey next to the pad: 2 legs of 100 m, not 3 of 220 m",
    )
    parser.set_defaults(handler=run)


def _echo(line: str) -> None:
    print(line, flush=True)


def run(args: argparse.Namespace) -> int:
    """Launch, fly, stop, report; exit 0 only if every step of the mission finished."""
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    recording = out / "run.mcap"
    plot = out / "flight.png"
    frame = frame_from_world(WORLD)
    survey = lawn_mower(SHORT_SURVEY if args.short else SURVEY, leg_speed=8.0, turn_speed=3.0)
    failure = ""
    system = LaunchedSystem([AGENT], WORLD, args.speed, args.domain_id, record=recording, log=_echo)
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
