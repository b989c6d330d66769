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
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from hdrc3.demo_mission import MissionError, SurveyMission
from hdrc3.flight_report import build_report, plot_report
from hdrc3.safety_pilot import Switch, set_rc
from hdrc3.survey import SurveyArea, lawn_mower
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import RosProcess
from hdrc3_interfaces.msg import PfcState, SimResult
from hdrc3_platform_server.client import PlatformClient
from hdrc3_platform_server.geo_frame import frame_from_world

READY_TIMEOUT_S = 120.0
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


def _wait_ready(launch: subprocess.Popen[str]) -> None:
    assert launch.stdout is not None
    deadline = time.monotonic() + READY_TIMEOUT_S
    for line in launch.stdout:
        print(f"  | {line.rstrip()}", flush=True)
        if "READY" in line:
            return
        if time.monotonic() > deadline:
            break
    launch.kill()
    raise ConfigError("the system did not come up; see the launcher output above")


def _stop(launch: subprocess.Popen[str]) -> int:
    if launch.poll() is None:
        launch.send_signal(signal.SIGINT)
    remaining, _ = launch.communicate(timeout=30)
    for line in remaining.splitlines():
        print(f"  | {line}")
    return launch.returncode


def _safety_pilot_engages_autonomy(client: PlatformClient) -> None:
    """Act as the safety pilot on the simulated RC: engine on, switch to autonomous (§6.1.1)."""
    code, reason = set_rc(
        client.process, client.node, AGENT, Switch.AUTONOMOUS, Switch.ON, timeout_s=10.0
    )
    if code != SimResult.OK:
        raise MissionError(f"the simulated RC did not accept engine on + autonomous: {reason}")
    print("  safety pilot: engine on, RC switch to autonomous")
    # Take-off is taken once the PFC reports autonomous ground idle: until then the DRC refuses
    # it ("RC switch manual") or the PFC rejects it (its Mode Switch is still leaving Start).
    ready: list[bool] = []

    def on_pfc(msg: PfcState) -> None:
        ready.append(bool(msg.auto_flag) and msg.mode == PfcState.MODE_GROUND_IDLE)

    client.node.create_subscription(PfcState, f"/{AGENT}/pfc/state", on_pfc, 10)
    if not client.process.spin_until(lambda: bool(ready) and ready[-1], 60.0):
        raise MissionError("the control kernel did not report autonomous ground idle in 60 s")


def run(args: argparse.Namespace) -> int:
    """Launch, fly, stop, report; exit 0 only if every step of the mission finished."""
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    recording = out / "run.mcap"
    plot = out / "flight.png"
    frame = frame_from_world(WORLD)
    survey = lawn_mower(SHORT_SURVEY if args.short else SURVEY, leg_speed=8.0, turn_speed=3.0)
    os.environ["ROS_DOMAIN_ID"] = str(args.domain_id)
    hdrc3 = str(Path(sys.executable).parent / "hdrc3")
    command = [hdrc3, "launch", "--agents", AGENT, "--world", WORLD, "--speed", args.speed]
    command += ["--record", str(recording), "--domain-id", str(args.domain_id)]
    print(f"$ {' '.join(command)}", flush=True)
    launch = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=dict(os.environ, PYTHONUNBUFFERED="1"),
    )
    failure = ""
    try:
        _wait_ready(launch)
        with RosProcess() as process:
            client = PlatformClient(process, AGENT)
            mission = SurveyMission(client, frame, survey, log=lambda s: print(f"  {s}"))
            try:
                _safety_pilot_engages_autonomy(client)
                mission.run()
            except MissionError as exc:
                failure = str(exc)
            client.node.destroy_node()
    finally:
        code = _stop(launch)
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
