"""The live view end to end: `hdrc3 launch --live` against a real one-agent system, a real
WebSocket client speaking the Foxglove protocol, and the live channels in the recording."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest
from foxglove.messages import FrameTransforms, SceneUpdate

from hdrc3.live.channels import CHANNEL_NAMES, CHANNELS
from hdrc3.live.probe import SUBPROTOCOL, FoxgloveProbe, Frame
from hdrc3.live.wire import WireSchema, decode
from hdrc3.mcap_recording import RecordingReader

pytestmark = [pytest.mark.ros, pytest.mark.slow]

SYSTEM = ("--agents", "uav0", "--nodes", "world_sim,control_kernel,platform_server")
TF_FRAMES = 10


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
        client.subscribe(["/hdrc3/world", "/hdrc3/aircraft", "/hdrc3/tf"])
        frames: dict[str, list[Frame]] = {
            "/hdrc3/world": [],
            "/hdrc3/aircraft": [],
            "/hdrc3/tf": [],
        }

        def complete() -> bool:
            return len(frames["/hdrc3/tf"]) >= TF_FRAMES and all(frames.values())

        while not complete():
            frame = client.receive(timeout_s=30)
            assert frame is not None, {t: len(f) for t, f in frames.items()}
            frames[frame.topic].append(frame)

    scene = WireSchema.well_known(SceneUpdate)
    world = decode(scene, frames["/hdrc3/world"][0].data)
    assert "terrain" in [e.id for e in world.entities]
    (aircraft,) = decode(scene, frames["/hdrc3/aircraft"][0].data).entities
    assert (aircraft.id, aircraft.frame_id) == ("aircraft/uav0", "uav0")
    for frame in frames["/hdrc3/tf"]:
        (tf,) = decode(WireSchema.well_known(FrameTransforms), frame.data).transforms
        assert (tf.parent_frame_id, tf.child_frame_id) == ("world", "uav0")
    assert launch.interrupt(timeout=60) == 0

    reader = RecordingReader.open(out)
    recorded = {m.topic: m for m in reader.messages() if m.topic.startswith("/hdrc3/")}
    assert {"/hdrc3/world", "/hdrc3/tf", "/hdrc3/aircraft"} <= set(recorded)
    (tf,) = decode(WireSchema.well_known(FrameTransforms), recorded["/hdrc3/tf"].data).transforms
    assert tf.child_frame_id == "uav0"
    assert not any(t.startswith("/hdrc3/") for t in reader.topics())  # not replayed as ROS


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
