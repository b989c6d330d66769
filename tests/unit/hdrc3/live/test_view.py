from __future__ import annotations

import pytest

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
