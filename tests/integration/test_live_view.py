"""The live view end to end: `hdrc3 launch --live` against a real one-agent system, a real
WebSocket client speaking the Foxglove protocol, and the live channels in the recording."""

from __future__ import annotations

import socket
import time
from collections import Counter
from pathlib import Path

import pytest
from foxglove.messages import FrameTransforms, SceneUpdate

from hdrc3.live.channels import CHANNEL_NAMES, CHANNELS
from hdrc3.live.probe import SUBPROTOCOL, FoxgloveProbe, Frame
from hdrc3.live.wire import WireSchema, decode
from hdrc3.mcap_recording import RecordingReader
from hdrc3_base.errors import DataError

pytestmark = [pytest.mark.ros, pytest.mark.slow]

SYSTEM = ("--agents", "uav0", "--nodes", "world_sim,control_kernel,platform_server")
TF_FRAMES = 10


def flushed(path: Path) -> set[str]:
    """Topics in the chunks a running recorder has flushed to ``path`` so far."""
    try:
        return {m.topic for m in RecordingReader.open(path).messages()}
    except DataError:  # not created yet, or a chunk read while it is being written
        return set()


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def test_launch_live_streams_the_system_and_records_the_same_channels(hdrc3_cli, tmp_path: Path):
    port = free_port()
    out = tmp_path / "run.mcap"
    launch = hdrc3_cli("launch", *SYSTEM, "--live-port", str(port), "--record", str(out))
    launch.wait_for_line("READY", timeout=120)

    with FoxgloveProbe(f"ws://127.0.0.1:{port}") as client:
        assert client.subprotocol == SUBPROTOCOL
        assert client.wait_for_channels(set(CHANNEL_NAMES), timeout_s=20), client.channels
        for channel in CHANNELS:
            advert = client.channels[channel.topic]
            assert (advert["schemaName"], advert["encoding"]) == (
                channel.schema.name,
                channel.schema.message_encoding,
            )
        client.subscribe(["/live/world", "/live/aircraft", "/live/tf"])
        frames: dict[str, list[Frame]] = {
            "/live/world": [],
            "/live/aircraft": [],
            "/live/tf": [],
        }

        def complete() -> bool:
            return len(frames["/live/tf"]) >= TF_FRAMES and all(frames.values())

        while not complete():
            frame = client.receive(timeout_s=30)
            assert frame is not None, {t: len(f) for t, f in frames.items()}
            frames[frame.topic].append(frame)

    scene = WireSchema.well_known(SceneUpdate)
    world = decode(scene, frames["/live/world"][0].data)
    assert "terrain" in [e.id for e in world.entities]
    (aircraft,) = decode(scene, frames["/live/aircraft"][0].data).entities
    assert (aircraft.id, aircraft.frame_id) == ("aircraft/uav0", "uav0")
    for frame in frames["/live/tf"]:
        (tf,) = decode(WireSchema.well_known(FrameTransforms), frame.data).transforms
        assert (tf.parent_frame_id, tf.child_frame_id) == ("world", "uav0")

    # the recorder starts last and flushes a chunk every second: wait until it wrote poses
    deadline = time.monotonic() + 60
    while "/live/tf" not in flushed(out) and time.monotonic() < deadline:
        launch.poll_output(0.5)
    assert launch.interrupt(timeout=60) == 0

    reader = RecordingReader.open(out)
    messages = list(reader.messages())
    recorded = {m.topic: m for m in messages if m.topic.startswith("/live/")}
    assert {"/live/world", "/live/tf", "/live/aircraft"} <= set(recorded), Counter(
        m.topic for m in messages
    )
    (tf,) = decode(WireSchema.well_known(FrameTransforms), recorded["/live/tf"].data).transforms
    assert tf.child_frame_id == "uav0"
    assert not any(t.startswith("/live/") for t in reader.topics())  # not replayed as ROS


@pytest.mark.parametrize(
    "command",
    [("live", "--port"), ("launch", "--nodes", "system_monitor", "--live-port")],
)
def test_a_port_in_use_is_a_clear_error_without_traceback(hdrc3_cli, command):
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        child = hdrc3_cli(*command, str(port))
        assert child.finish(timeout=60) == 2
    text = "\n".join(child.lines)
    assert f"{port}" in text and ("in use" in text or "not free" in text), text
    assert "Traceback" not in text
