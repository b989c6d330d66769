"""Colour tracking and car following on the real node chain (chapter §6.1, §6.2.2, §6.2.3).

``hdrc3 launch`` with the cameras and a simulated world that is revinge plus one magenta car
(``chase1``) parked on pad_track, 32 m north-east of the start pad H1, that sets off at
``DEPART`` s of sim time, drives north along pad_track, turns east onto main_street and stops at
its end (287 m). The stack's nodes hold plain revinge: nothing but the images tells them about
the car.

Through the ``hdrc3`` command the aircraft takes off and climbs to 30 m; the operator points the
camera at the parked car (``ppcl look_at``), clicks on it (``ppcl ip_color_tracker X Y`` with the
car's pixel in the latest image: the operator's eye is the test's projection of the car's true
position) and engages car following (``fcl track --no-wait``: accepted, it runs until
cancelled). The color_tracker node follows the car in every colour image, the perception
kernel's pan-tilt visual servoing keeps it in the image's centre, and the control kernel's Track
mode holds the aircraft ``DISTANCE`` m behind it on the tracker's ground points. ``fcl cancel``
ends it once the car stood still for a while.

Checked over the drive (the ground truth only scores): the car is tracked in at least 95 % of
the images (the issue's car-following target), the tracked pixel lies on the car (within half
the tracked region's size of its projected centre), the servo keeps it near the image's centre
(median within ``CENTRE_BOUND`` of the width), each ground position is as close to the car as
the navigation solution allows (the GPS's 3 sigma plus the height errors of the barometer and of
the car's visible centre above the road, stretched along the ray by range / height), and the
aircraft flew with the car (at least ``MIN_TRAVEL`` m), ``DISTANCE_BAND`` m from it once both
were under way, ``DISTANCE`` +- 5 m on average.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from rosgraph_msgs.msg import Clock

from hdrc3.cli.main import main as hdrc3_main
from hdrc3_perception.camera import CameraPose, Intrinsics, NavPose
from hdrc3_perception.colour_node import TRACK_QOS, TRACK_TOPIC
from hdrc3_platform_server.geo_frame import WorldFrame
from sim.world_loader import load_world
from tests.integration.ros_wait import spin_until

# `make flights`: the simulator waits for the renderer, not for the tracker, the PTU servo and the
# PFC, so on a machine running several test workers per core they fall behind sim time
pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.flight]

AGENT = "uav0"
CAR = "chase1"
DEPART = 100.0
"""s of sim time the car sets off (the aircraft hovers by then)."""
ROUTE = ((-215.0, -112.0), (-215.0, 0.0), (-40.0, 0.0))
PARKED_AGAIN = 5.0
"""s the scoring goes on after the car stopped at the route's end."""
DISTANCE = 20.0
"""m: fcl_track's standoff (CarFollowingConfig.distance)."""
SETTLE = 15.0
"""s of driving before the following distance is checked (the car speeds up, the aircraft too)."""
DISTANCE_BAND = (5.0, 35.0)
MIN_TRAVEL = 200.0
PIXEL_SLACK = 4.0
"""px beyond half the tracked region's size that its centre may be off the car's centre."""
CENTRE_BOUND = 0.15
GPS_BOUND_H = 4.5
"""m: 3 sigma of the simulated GPS's horizontal error per axis (1.5 m)."""
BARO_BOUND_V = 1.5
CAR_CENTRE_UP = 0.75
"""m: the tracked region's centre above the road (half the car's height)."""
HOVER_HEIGHT = 30.0
"""m above the origin (H1 lies at its height)."""
CLOCK_LAG = 0.1
"""s: states this close to the latest sim clock count as current."""
SEED_LEAD = 3.0
"""s the seed takes to reach the tracker (the click must be on the parked car)."""
WORLD = f"""[world]
name = "chase_near_h1"
extends = "{Path(__file__).resolve().parents[2] / "sim" / "worlds" / "revinge.toml"}"

[[object]]
id = "{CAR}"
type = "car"
route = {[list(p) for p in ROUTE]}
speed = 8.0
depart = {DEPART}
paint = [0.85, 0.05, 0.80]
"""


def _stamp_of(stamp: Any) -> float:
    return float(stamp.sec) + 1e-9 * float(stamp.nanosec)


def _stamp(msg: Any) -> float:
    return _stamp_of(msg.header.stamp)


def _nearest(samples: list[Any], time: float) -> Any:
    return min(samples, key=lambda m: abs(_stamp(m) - time))


def test_a_driving_car_is_tracked_and_followed(
    hdrc3_cli: Any, ros_context: Any, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from sensor_msgs.msg import CameraInfo

    from hdrc3_interfaces.msg import ColorTrack, PfcState, PtuState, TruthState, WorldObjects
    from sim.node import LATCHED_QOS

    world_file = tmp_path / "chase_near_h1.toml"
    world_file.write_text(WORLD)
    world = load_world("revinge")
    frame = WorldFrame(world.origin.latitude, world.origin.longitude, world.origin.altitude)
    launch = hdrc3_cli(
        "launch", "--agents", AGENT, "--speed", "1", "--sim-world", str(world_file),
        "--nodes", "world_sim,world_render,control_kernel,platform_server,perception_kernel,"
        "color_tracker",
    )  # fmt: skip
    launch.wait_for_line("READY", timeout=120)
    node = Node("color_tracking_test", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    pfc: list[Any] = []
    truth: list[Any] = []
    ptu: list[Any] = []
    tracks: list[Any] = []
    cars: list[tuple[float, tuple[float, float, float]]] = []
    info: list[Any] = []
    node.create_subscription(PfcState, f"/{AGENT}/pfc/state", pfc.append, 50)
    node.create_subscription(TruthState, f"/{AGENT}/ground_truth/state", truth.append, 50)
    node.create_subscription(PtuState, f"/{AGENT}/sensors/ptu", ptu.append, 50)
    node.create_subscription(ColorTrack, f"/{AGENT}/{TRACK_TOPIC}", tracks.append, TRACK_QOS)
    clock: list[float] = []
    node.create_subscription(Clock, "/clock", lambda m: clock.append(_stamp_of(m.clock)), 1)
    node.create_subscription(
        CameraInfo, f"/{AGENT}/camera/color/camera_info", info.append, qos_profile_sensor_data
    )

    def on_objects(msg: Any) -> None:
        for obj in msg.objects:
            if obj.id == CAR:
                centre = (obj.east, obj.north, obj.up + 0.5 * obj.size[2])
                cars.append((_stamp(msg), centre))

    node.create_subscription(WorldObjects, "/world_sim/objects", on_objects, LATCHED_QOS)

    def car_at(time: float) -> np.ndarray:
        """The car's centre at ``time``, between the objects messages (10 Hz while it moves)."""
        times = [c[0] for c in cars]
        return np.array([np.interp(time, times, [c[1][i] for c in cars]) for i in range(3)])

    def pixel_of_car(time: float) -> np.ndarray:
        """Where the car's centre is in the colour image taken at ``time`` (ground truth)."""
        t = _nearest(truth, time)
        nav = NavPose(tuple(t.position_enu), t.roll, t.pitch, t.heading)
        times = [_stamp(m) for m in ptu]
        pan = float(np.interp(time, times, [m.pan for m in ptu]))
        tilt = float(np.interp(time, times, [m.tilt for m in ptu]))
        intrinsics = Intrinsics.from_k(info[-1].width, info[-1].height, list(info[-1].k))
        assert intrinsics is not None
        return CameraPose.of(nav, pan, tilt).project(intrinsics, car_at(time)[None, :])[0]

    def catch_up() -> None:
        """Take what arrived while a command ran: the states up to a fresh sim clock."""
        ticks = len(clock)
        assert spin_until(
            executor,
            lambda: (
                len(clock) > ticks + 1
                and bool(truth and ptu and info)
                and min(_stamp(truth[-1]), _stamp(ptu[-1])) >= clock[-1] - CLOCK_LAG
            ),
            30.0,
        ), (clock[-1:], truth[-1:], ptu[-1:])

    def ground_bound(time: float) -> float:
        """How far off a ground point may be: the navigation solution's GPS error, and the
        height errors (barometer; the car's visible centre above the ground) stretched along
        the ray by range / height."""
        t = _nearest(truth, time)
        reach = math.dist(t.position_enu[:2], car_at(time)[:2]) / t.height_above_ground
        return GPS_BOUND_H + (BARO_BOUND_V + CAR_CENTRE_UP) * reach

    assert hdrc3_main(["rc", AGENT, "--engine", "on", "--mode", "autonomous"]) == 0
    ready = spin_until(
        executor,
        lambda: bool(pfc) and pfc[-1].auto_flag and pfc[-1].mode == PfcState.MODE_GROUND_IDLE,
        90.0,
    )
    assert ready, pfc[-1:] or "no pfc/state"
    assert hdrc3_main(["fcl", AGENT, "takeoff", "--timeout", "120"]) == 0
    climb = f"{world.origin.altitude + HOVER_HEIGHT:.1f}"
    assert hdrc3_main(["fcl", AGENT, "climb", climb, "--timeout", "120"]) == 0
    catch_up()
    print(f"hovering {HOVER_HEIGHT:.0f} m up at {_stamp(truth[-1]):.2f} s")
    lon, lat, alt = frame.to_wgs84(*car_at(_stamp(truth[-1])))
    for command in (
        ["request", "ptu"], ["request", "camera"], ["request", "ip"],
        ["look_at", f"{lon:.9f}", f"{lat:.9f}", f"{alt:.2f}", "--timeout", "60"],
    ):  # fmt: skip
        assert hdrc3_main(["ppcl", AGENT, *command, "--owner", "test"]) == 0, command
    catch_up()
    assert info, "no camera_info"
    now = _stamp(truth[-1])
    u, v = pixel_of_car(now)
    assert now < DEPART - SEED_LEAD, f"the car must be parked when clicked on: {now} s"
    assert 0 <= u < info[-1].width and 0 <= v < info[-1].height, (u, v)
    assert hdrc3_main(["ppcl", AGENT, "ip_color_tracker", f"{u:.1f}", f"{v:.1f}"]) == 0
    # the operator engages track once the tracker shows the car on the ground (the PFC
    # refuses it without a recent ground fix)
    assert spin_until(
        executor,
        lambda: (
            bool(tracks) and tracks[-1].status == ColorTrack.STATUS_TRACKING and tracks[-1].located
        ),
        30.0,
    ), [(round(_stamp(t), 2), t.status, t.reason) for t in tracks[:3] + tracks[-2:]]
    seeded = next(_stamp(t) for t in tracks if t.status == ColorTrack.STATUS_TRACKING)
    capsys.readouterr()
    assert hdrc3_main(["fcl", AGENT, "track", "--no-wait"]) == 0
    assert "FCL_OK" in capsys.readouterr().out
    route_end = np.array(ROUTE[-1])
    assert spin_until(
        executor,
        lambda: bool(cars) and float(np.hypot(*(np.array(cars[-1][1][:2]) - route_end))) < 0.5,
        180.0,
    ), cars[-1:]
    stopped = cars[-1][0]
    assert spin_until(
        executor, lambda: bool(truth) and _stamp(truth[-1]) >= stopped + PARKED_AGAIN, 30.0
    )
    end = _stamp(truth[-1])
    capsys.readouterr()
    assert hdrc3_main(["fcl", AGENT, "cancel"]) == 0
    node.destroy_node()
    assert launch.interrupt() == 0

    scored = [t for t in tracks if DEPART <= _stamp(t) <= end]
    found = [t for t in scored if t.status == ColorTrack.STATUS_TRACKING]
    width = float(info[-1].width)
    errors = [float(np.hypot(*(np.array([t.x, t.y]) - pixel_of_car(_stamp(t))))) for t in found]
    off_centre = [
        math.hypot(t.x - 0.5 * width, t.y - 0.5 * float(info[-1].height)) / width for t in found
    ]
    located = [t for t in found if t.located]
    ground = [math.dist((t.position.x, t.position.y), car_at(_stamp(t))[:2]) for t in located]
    ground_bounds = [ground_bound(_stamp(t)) for t in located]
    flown = [t for t in truth if DEPART <= _stamp(t) <= end]
    track_xy = np.array([t.position_enu[:2] for t in flown])
    travel = float(np.linalg.norm(np.diff(track_xy, axis=0), axis=1).sum())
    apart = [
        math.dist(t.position_enu[:2], car_at(_stamp(t))[:2])
        for t in flown
        if _stamp(t) >= DEPART + SETTLE
    ]
    lost = [(round(_stamp(t), 2), t.reason) for t in scored if t not in found]
    assert len(scored) >= 20 and len(found) >= 0.95 * len(scored), (len(scored), lost)
    print(
        f"seeded at {seeded:.2f} s; {len(found)}/{len(scored)} images tracked over "
        f"{end - DEPART:.1f} s of driving; pixel error median {np.median(errors):.1f} px, max "
        f"{max(errors):.1f}; off centre median {np.median(off_centre):.3f} of the width; ground "
        f"error median {np.median(ground):.2f} m, max {max(ground):.2f}; flew {travel:.0f} m "
        f"behind the car, {np.mean(apart):.1f} m apart on average ({min(apart):.1f}-"
        f"{max(apart):.1f})"
    )
    pairs = list(zip(errors, found, strict=True))
    assert all(e <= 0.5 * math.sqrt(t.area) + PIXEL_SLACK for e, t in pairs), [
        (round(e, 1), t.area) for e, t in pairs
    ]
    assert float(np.median(off_centre)) <= CENTRE_BOUND, off_centre
    assert travel >= MIN_TRAVEL, travel
    assert DISTANCE_BAND[0] <= min(apart) and max(apart) <= DISTANCE_BAND[1], apart
    assert abs(float(np.mean(apart)) - DISTANCE) <= 5.0, apart
    assert len(ground) >= 0.9 * len(found), (len(ground), len(found))
    assert all(e <= b for e, b in zip(ground, ground_bounds, strict=True)), (ground, ground_bounds)
