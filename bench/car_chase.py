"""A car chase on the real node chain (chapter §6.1 reactive car following; issue 16's target).

Starts ``hdrc3 launch`` (world_sim, world_render, control_kernel, platform_server,
perception_kernel, color_tracker) on a private ROS domain, in a simulated world that is revinge
plus a magenta car parked on pad_track beside the start pad H1. The car sets off at
``--depart`` s of sim time and drives a route through the town on road centre lines (pad_track,
main_street, mid_avenue, south_ring, town_edge, north_ring, west_street: 1.5 km, 3 minutes at
10 m/s with slower corners). Through the ``hdrc3`` command, as an operator would: take off,
climb to 30 m, point the camera at the parked car (``ppcl look_at``), click on it
(``ppcl ip_color_tracker X Y``: the click is the car's projected pixel, the operator's eye), and
``fcl track``; at the end ``fcl cancel``.

Printed (ground truth only scores): the share of the colour images in which the car was inside
the image and in which the tracker had it, its offset from the image's centre, the distance
between aircraft and car (``fcl_track`` keeps 20 m) and how the track ended.

Run: .venv/bin/python bench/car_chase.py [--depart 100] [--domain-id 93]
"""

from __future__ import annotations

import argparse
import math
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np

from sim.drive import DrivePlan
from sim.world_loader import load_world

AGENT = "uav0"
CAR = "chase1"
ROUTE = (
    (-215.0, -112.0),
    (-215.0, 0.0),
    (60.0, 0.0),
    (60.0, -100.0),
    (240.0, -100.0),
    (240.0, 100.0),
    (60.0, 100.0),
    (-40.0, 100.0),
    (-40.0, -100.0),
    (150.0, -100.0),
)
CRUISE = 10.0
HEIGHT = 30.0
NODES = "world_sim,world_render,control_kernel,platform_server,perception_kernel,color_tracker"


def world_text(depart: float) -> str:
    """The chase world: revinge plus the parked car and its route."""
    base = Path(__file__).resolve().parents[1] / "sim" / "worlds" / "revinge.toml"
    return (
        f'[world]\nname = "chase_bench"\nextends = "{base}"\n\n[[object]]\nid = "{CAR}"\n'
        f'type = "car"\nroute = {[list(p) for p in ROUTE]}\nspeed = {CRUISE}\n'
        f"depart = {depart}\npaint = [0.85, 0.05, 0.80]\n"
    )


def stamp(msg: Any) -> float:
    """A message's header stamp, s."""
    return float(msg.header.stamp.sec) + 1e-9 * float(msg.header.stamp.nanosec)


def main() -> int:
    """Run the chase and print its figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--depart", type=float, default=100.0, help="s of sim time")
    parser.add_argument("--domain-id", type=int, default=93)
    args = parser.parse_args()
    os.environ["ROS_DOMAIN_ID"] = str(args.domain_id)
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    with tempfile.TemporaryDirectory() as tmp:
        world = Path(tmp) / "chase_bench.toml"
        world.write_text(world_text(args.depart))
        hdrc3 = os.path.join(os.path.dirname(sys.executable), "hdrc3")
        launch = subprocess.Popen(
            [hdrc3, "launch", "--agents", AGENT, "--speed", "1", "--sim-world", str(world),
             "--nodes", NODES],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True,
            env=dict(os.environ, PYTHONUNBUFFERED="1"),
        )  # fmt: skip
        ready = threading.Event()
        threading.Thread(target=_drain, args=(launch, ready), daemon=True).start()
        try:
            if not ready.wait(180.0):
                print("the nodes did not start", flush=True)
                return 1
            car = next(o for o in load_world(str(world)).objects if o.id == CAR)
            assert car.drive is not None
            return chase(args.depart, args.depart + DrivePlan.of(car.drive).start_time)
        finally:
            os.killpg(launch.pid, signal.SIGINT)
            try:
                launch.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(launch.pid, signal.SIGKILL)


def _drain(proc: subprocess.Popen[bytes], ready: threading.Event) -> None:
    """Read the launcher's output (a full pipe would block it); READY sets ``ready``."""
    assert proc.stdout is not None
    for line in proc.stdout:
        if b"READY" in line:
            ready.set()


def chase(depart: float, arrival: float) -> int:
    """Fly the chase on the running nodes; print the figures; 0 if the track ran to the end.

    Args:
        depart: When the car sets off (sim time, s).
        arrival: When it stops at the end of its route (sim time, s).
    """
    import rclpy
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.qos import qos_profile_sensor_data
    from rosgraph_msgs.msg import Clock
    from sensor_msgs.msg import CameraInfo

    from hdrc3.cli.main import main as hdrc3_main
    from hdrc3_interfaces.msg import ColorTrack, PfcState, PtuState, TruthState, WorldObjects
    from hdrc3_perception.camera import CameraPose, Intrinsics, NavPose
    from hdrc3_perception.colour_node import TRACK_QOS, TRACK_TOPIC
    from hdrc3_platform_server.geo_frame import WorldFrame
    from sim.node import LATCHED_QOS

    context = Context()
    rclpy.init(context=context, domain_id=int(os.environ["ROS_DOMAIN_ID"]))
    node = Node("car_chase_bench", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    pfc: list[Any] = []
    truth: list[Any] = []
    ptu: list[Any] = []
    tracks: list[Any] = []
    info: list[Any] = []
    clock: list[float] = []
    cars: list[tuple[float, np.ndarray]] = []
    node.create_subscription(PfcState, f"/{AGENT}/pfc/state", pfc.append, 50)
    node.create_subscription(TruthState, f"/{AGENT}/ground_truth/state", truth.append, 50)
    node.create_subscription(PtuState, f"/{AGENT}/sensors/ptu", ptu.append, 50)
    node.create_subscription(ColorTrack, f"/{AGENT}/{TRACK_TOPIC}", tracks.append, TRACK_QOS)
    node.create_subscription(
        CameraInfo, f"/{AGENT}/camera/color/camera_info", info.append, qos_profile_sensor_data
    )
    node.create_subscription(
        Clock, "/clock", lambda m: clock.append(m.clock.sec + 1e-9 * m.clock.nanosec), 1
    )

    def on_objects(msg: Any) -> None:
        for obj in msg.objects:
            if obj.id == CAR:
                centre = np.array([obj.east, obj.north, obj.up + 0.5 * obj.size[2]])
                cars.append((stamp(msg), centre))

    node.create_subscription(WorldObjects, "/world_sim/objects", on_objects, LATCHED_QOS)

    def spin_until(done: Any, timeout: float) -> bool:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if done():
                return True
            executor.spin_once(timeout_sec=0.05)
        return bool(done())

    def catch_up() -> None:
        ticks = len(clock)
        spin_until(
            lambda: (
                len(clock) > ticks + 1
                and bool(truth and ptu and info)
                and min(stamp(truth[-1]), stamp(ptu[-1])) >= clock[-1] - 0.1
            ),
            30.0,
        )

    def car_at(t: float) -> np.ndarray:
        return min(cars, key=lambda c: abs(c[0] - t))[1]

    def camera_at(t: float) -> CameraPose:
        s = min(truth, key=lambda m: abs(stamp(m) - t))
        p = min(ptu, key=lambda m: abs(stamp(m) - t))
        return CameraPose.of(
            NavPose(tuple(s.position_enu), s.roll, s.pitch, s.heading), p.pan, p.tilt
        )

    def say(text: str) -> None:
        print(f"[{stamp(truth[-1]) if truth else 0.0:7.2f} s] {text}", flush=True)

    world = load_world("revinge")
    frame = WorldFrame(world.origin.latitude, world.origin.longitude, world.origin.altitude)
    if hdrc3_main(["rc", AGENT, "--engine", "on", "--mode", "autonomous"]) != 0:
        return 1
    spin_until(lambda: bool(pfc) and pfc[-1].mode == PfcState.MODE_GROUND_IDLE, 90.0)
    steps = [
        ["fcl", AGENT, "takeoff", "--timeout", "120"],
        ["fcl", AGENT, "climb", f"{world.origin.altitude + HEIGHT:.1f}", "--timeout", "120"],
        *(["ppcl", AGENT, "request", r, "--owner", "bench"] for r in ("ptu", "camera", "ip")),
    ]
    for step in steps:
        if hdrc3_main(step) != 0:
            say(f"failed: hdrc3 {' '.join(step)}")
            return 1
    catch_up()
    lon, lat, alt = frame.to_wgs84(*car_at(stamp(truth[-1])))
    look = ["ppcl", AGENT, "look_at", f"{lon:.9f}", f"{lat:.9f}", f"{alt:.2f}", "--timeout", "60"]
    if hdrc3_main(look) != 0:
        return 1
    catch_up()
    k = info[-1]
    intrinsics = Intrinsics.from_k(int(k.width), int(k.height), list(k.k))
    assert intrinsics is not None
    now = stamp(truth[-1])
    u, v = camera_at(now).project(intrinsics, car_at(now)[None, :])[0]
    say(f"the operator clicks on the parked car at ({u:.0f}, {v:.0f})")
    if hdrc3_main(["ppcl", AGENT, "ip_color_tracker", f"{u:.1f}", f"{v:.1f}"]) != 0:
        return 1
    spin_until(
        lambda: (
            bool(tracks) and tracks[-1].status == ColorTrack.STATUS_TRACKING and tracks[-1].located
        ),
        30.0,
    )
    if hdrc3_main(["fcl", AGENT, "track", "--no-wait"]) != 0:
        return 1
    say("fcl track accepted; waiting for the car to set off")
    wall = time.monotonic()
    arrived = spin_until(lambda: bool(truth) and stamp(truth[-1]) >= arrival, 900.0)
    stop = stamp(truth[-1])
    # fcl_track flies on the path-following loop: the PFC reports TRAJ3D while it runs
    left = [s for s in pfc if depart <= stamp(s) <= stop and s.mode != PfcState.MODE_TRAJ3D]
    say(f"the car {'reached the end of its route' if arrived else 'did not arrive'}")
    hdrc3_main(["fcl", AGENT, "cancel"])
    node.destroy_node()
    context.try_shutdown()

    window = [t for t in tracks if depart <= stamp(t) <= stop]
    tracked = [t for t in window if t.status == ColorTrack.STATUS_TRACKING]
    inside = 0
    for t in window:
        x, y = camera_at(stamp(t)).project(intrinsics, car_at(stamp(t))[None, :])[0]
        inside += int(0 <= x < intrinsics.width and 0 <= y < intrinsics.height)
    off = [math.hypot(t.x - intrinsics.cx, t.y - intrinsics.cy) / intrinsics.width for t in tracked]
    flown = [s for s in truth if depart + 15.0 <= stamp(s) <= stop]
    apart = [math.dist(s.position_enu[:2], car_at(stamp(s))[:2]) for s in flown]
    print(f"chase: {stop - depart:.1f} s of sim time ({time.monotonic() - wall:.0f} s wall), "
          f"{len(window)} colour images", flush=True)  # fmt: skip
    if window:
        print(f"car inside the image: {100 * inside / len(window):.1f} %; tracked: "
              f"{100 * len(tracked) / len(window):.1f} %", flush=True)  # fmt: skip
    if off:
        print(f"off the image centre (fraction of the width): median {np.median(off):.3f}, "
              f"95 % {np.percentile(off, 95):.3f}", flush=True)  # fmt: skip
    if apart:
        print(f"aircraft to car (from 15 s after setting off): mean {np.mean(apart):.1f} m, "
              f"min {min(apart):.1f}, max {max(apart):.1f}", flush=True)  # fmt: skip
    print(f"track ran to the end: {arrived and not left}", flush=True)
    return 0 if arrived and not left else 1


if __name__ == "__main__":
    sys.exit(main())
