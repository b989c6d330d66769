from __future__ import annotations

import pytest
from sensor_msgs.msg import Image
from std_msgs.msg import String

from hdrc3.live.converters import SkipReason
from hdrc3.live.view import LiveView
from hdrc3_interfaces.msg import Path, TruthState
from sim.world_loader import load_world

TRUTH = "hdrc3_interfaces/msg/TruthState"


@pytest.fixture(scope="module")
def world():
    return load_world("revinge")


@pytest.mark.parametrize(
    ("topic", "type_name", "route"),
    [
        ("/uav0/ground_truth/state", TRUTH, ("uav0", "ground_truth/state")),
        ("/uav1/path_planner/gis_state", "hdrc3_interfaces/msg/GisState",
         ("uav1", "path_planner/gis_state")),
        ("/uav0/ground_truth/state", "std_msgs/msg/String", None),  # wrong type
        ("/uav0/ground_truth/odometry", "nav_msgs/msg/Odometry", None),
        ("/clock", "rosgraph_msgs/msg/Clock", None),
        ("/UAV0/ground_truth/state", TRUTH, None),  # not an agent name
    ],
)  # fmt: skip
def test_route(world, topic, type_name, route):
    assert LiveView(world).route(topic, type_name) == route


def test_start_sends_the_world_and_latches_it(world):
    view = LiveView(world)
    assert [e.channel for e in view.start(0)] == ["/live/world"]
    assert len(view.latched("/live/world")) == 1
    assert view.latched("/live/tf") == []  # not latched


def test_one_truth_message_feeds_pose_model_and_track_channels(world):
    view = LiveView(world)
    msg = TruthState()
    first = view.on_message("uav0", "ground_truth/state", msg, 0)
    msg.position_enu = [5.0, 0.0, 0.0]
    second = view.on_message("uav0", "ground_truth/state", msg, 40_000_000)
    assert [e.channel for e in first] == ["/live/tf", "/live/aircraft"]
    assert [e.channel for e in second] == ["/live/tf", "/live/tracks"]


def test_latched_channels_keep_the_latest_message_per_agent(world):
    view = LiveView(world)
    for agent in ("uav0", "uav1", "uav0"):
        view.on_message(agent, "planned_path", Path(), 0)
    assert len(view.latched("/live/planned_paths")) == 2


def rgb_image(width: int = 4, height: int = 2) -> Image:
    data = bytes(width * height * 3)
    return Image(height=height, width=width, encoding="rgb8", step=width * 3, data=data)


def test_camera_images_go_to_the_agents_own_channel(world):
    view = LiveView(world)
    out = view.on_message("uav1", "camera/thermal/image_raw", rgb_image(), 0)
    assert [e.channel for e in out] == ["/live/camera/thermal/uav1"]
    assert [c.topic for c in view.channels_of("camera/thermal/image_raw")] == [
        "/live/camera/thermal"
    ]


def test_wants_is_false_while_the_image_rate_limit_would_drop(world):
    view = LiveView(world)
    assert view.wants("uav0", "camera/color/image_raw", 0)
    view.on_message("uav0", "camera/color/image_raw", rgb_image(), 0)
    assert not view.wants("uav0", "camera/color/image_raw", 40_000_000)
    assert view.wants("uav1", "camera/color/image_raw", 40_000_000)
    assert view.wants("uav0", "ground_truth/state", 40_000_000)


def test_skips_are_counted_per_channel(world):
    view = LiveView(world)
    assert view.skipped() == {}
    view.on_message("uav0", "saliency/map", String(data="nope"), 0)
    view.on_message("uav0", "camera/color/image_raw", Image(encoding="yuv422"), 0)
    assert view.skipped() == {
        "/live/saliency": {SkipReason.MALFORMED_MAP: 1},
        "/live/camera/color": {SkipReason.UNKNOWN_ENCODING: 1},
    }


@pytest.mark.parametrize(
    ("suffix", "newest_only"),
    [("camera/color/image_raw", True), ("camera/thermal/image_raw", True),
     ("ground_truth/state", False), ("saliency/map", False)],
)  # fmt: skip
def test_camera_images_are_taken_newest_only(world, suffix, newest_only):
    assert LiveView(world).newest_only(suffix) is newest_only
