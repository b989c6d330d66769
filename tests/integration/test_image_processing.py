"""PPCL image processing end to end: `hdrc3 ppcl uav0 ip_saliency` engages the saliency pipeline.

The real chain: the Platform Server forwards the command to the perception kernel (PPC), whose
Ip automaton engages the pipeline and publishes its mode; the saliency node then subscribes the
images world_render draws and processes colour + thermal pairs; `ip_abort` stops it again.
"""

from __future__ import annotations

import json
from typing import Any

import pytest
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Bool, String, UInt8

from hdrc3.cli.main import main as hdrc3_main
from hdrc3_control.perception_kernel_node import IMAGE_PROCESSING_TOPIC
from hdrc3_control.ppc_modes import ImageProcessing
from hdrc3_perception.node import LATCHED, RESULT_QOS
from tests.integration.ros_wait import spin_until

pytestmark = pytest.mark.ros

CLOCK_LAG = 1.0  # how far the sim clock may be ahead of a fresh /clock the test handled (s)
CLOCK_QOS = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)


def test_ip_saliency_runs_the_pipeline_until_ip_abort(
    hdrc3_cli: Any, ros_context: Any, capsys: pytest.CaptureFixture[str]
) -> None:
    launch = hdrc3_cli(
        "launch", "--agents", "uav0", "--speed", "1", "--cameras",
        "--nodes", "world_sim,control_kernel,platform_server,perception_kernel",
    )  # fmt: skip
    launch.wait_for_line("READY", timeout=120)
    node = Node("image_processing_test", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    results: list[dict[str, Any]] = []
    modes: list[int] = []
    engaged: list[bool] = []
    clock = [0.0]
    node.create_subscription(
        String, "/uav0/saliency/pair_result", lambda m: results.append(json.loads(m.data)),
        RESULT_QOS,
    )  # fmt: skip
    node.create_subscription(
        UInt8, f"/uav0/{IMAGE_PROCESSING_TOPIC}", lambda m: modes.append(m.data), LATCHED
    )
    node.create_subscription(
        Bool, "/uav0/saliency/engaged", lambda m: engaged.append(m.data), LATCHED
    )
    node.create_subscription(
        Clock, "/clock", lambda m: clock.append(m.clock.sec + 1e-9 * m.clock.nanosec), CLOCK_QOS
    )
    assert spin_until(executor, lambda: modes == [ImageProcessing.IDLE], 60.0), modes
    assert hdrc3_main(["state", "uav0", "--once", "--timeout", "60"]) == 0

    assert hdrc3_main(["ppcl", "uav0", "ip_saliency"]) == 1  # control first
    assert "request control of the image_processing" in capsys.readouterr().out
    assert hdrc3_main(["ppcl", "uav0", "request", "ip", "--owner", "test"]) == 0
    assert hdrc3_main(["ppcl", "uav0", "ip_saliency", "--timeout", "60"]) == 0
    assert "ppcl_ip_saliency: FINISHED" in capsys.readouterr().out
    assert spin_until(executor, lambda: modes[-1] == ImageProcessing.SALIENCY, 30.0), modes
    # the pipeline gets pairs of the rendered images and processes them (the pad from 0 m)
    assert spin_until(executor, lambda: len(results) >= 3, 120.0), (results, clock[-1])
    assert {r["status"] for r in results} <= {"processed", "no_state"}
    assert any(r["status"] == "processed" for r in results), results

    assert hdrc3_main(["ppcl", "uav0", "ip_abort", "--timeout", "60"]) == 0
    assert spin_until(executor, lambda: modes[-1] == ImageProcessing.IDLE, 30.0), modes
    # the node stops when it reads the mode, and may be seconds behind under load (it finishes
    # the pairs its subscriptions had queued); once it says so, no newer pair is processed
    assert spin_until(executor, lambda: engaged[-2:] == [True, False], 60.0), engaged
    seen = len(clock)  # the clock the test last handled may be stale: take two fresh ones
    assert spin_until(executor, lambda: len(clock) >= seen + 2, 60.0)
    stopped_at = clock[-1] + CLOCK_LAG
    assert spin_until(executor, lambda: clock[-1] > stopped_at + 3.0, 60.0)
    assert all(r["time"] <= stopped_at for r in results), [r["time"] for r in results]
    node.destroy_node()
    assert launch.interrupt() == 0
