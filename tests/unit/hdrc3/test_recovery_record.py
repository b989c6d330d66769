"""Reading a lost load's detection and recovery from a recording (real MCAP, made-up run)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from rclpy.serialization import serialize_message

from hdrc3.mcap_recording import RecordingWriter, TopicInfo
from hdrc3.recovery_record import read_failed_lift, read_lost_load
from hdrc3_interfaces.msg import (
    HookState,
    MonitorViolation,
    PfcState,
    RecoveryEvent,
    WorldObject,
    WorldObjects,
)

TOPICS = {
    "/world_sim/objects": "WorldObjects",
    "/uav0/sensors/carrying": "HookState",
    "/uav0/monitor_violations": "MonitorViolation",
    "/uav0/recovery_events": "RecoveryEvent",
    "/uav0/pfc/state": "PfcState",
}


def _stamp(msg: Any, ms: int) -> Any:
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(ms * 1_000_000, 10**9)
    return msg


def _write(path: Path, out: list[tuple[int, str, Any]]) -> Path:
    """A recording of ``out`` ((sim ms, topic, message)), in time order."""
    writer = RecordingWriter(path)
    for topic, kind in TOPICS.items():
        writer.add_topic(TopicInfo(topic, f"hdrc3_interfaces/msg/{kind}"))
    for ms, topic, msg in sorted(out, key=lambda x: x[0]):
        writer.write(topic, serialize_message(_stamp(msg, ms)), ms * 1_000_000)
    writer.close()
    return path


def write_run(path: Path, *, violated: bool = True) -> Path:
    """box1 held from 1.0 s, off the hook at 3.0 s (truth) and 3.1 s (sensor)."""
    out: list[tuple[int, str, Any]] = []
    for ms in range(0, 6001, 100):
        held = "uav0" if 1000 <= ms < 3000 else ""
        box = WorldObject(id="box1", kind="box", east=float(ms), held_by=held)
        out.append((ms, "/world_sim/objects", WorldObjects(objects=[box])))
        tag = "box1" if 1000 <= ms < 3100 else ""
        out.append((ms, "/uav0/sensors/carrying", HookState(carrying=bool(tag), object_id=tag)))
        mode = PfcState.MODE_TRAJ3D if ms < 3200 else PfcState.MODE_BRAKING
        out.append(
            (ms, "/uav0/pfc/state", PfcState(mode=mode if ms < 4000 else PfcState.MODE_HOVER))
        )
    if violated:
        v = MonitorViolation(
            kind=MonitorViolation.KIND_VIOLATION,
            monitor_id="box_held@d/2",
            argument_names=["box"],
            argument_values=["box1"],
        )
        out.append((3100, "/uav0/monitor_violations", v))
        for ms, step in ((3160, 1), (3160, 2), (4100, 5)):
            event = RecoveryEvent(monitor_id="box_held@d/2", step=step)
            out.append((ms, "/uav0/recovery_events", event))
    other = RecoveryEvent(monitor_id="speed_limit", step=RecoveryEvent.STEP_IGNORED)
    out.append((3500, "/uav0/recovery_events", other))
    return _write(path, out)


def test_detection_recovery_and_modes_are_read_from_the_recording(tmp_path: Path) -> None:
    record = read_lost_load(write_run(tmp_path / "run.mcap"), "uav0", "box1")
    assert (record.released_ms, record.sensor_ms) == (3000, 3100)
    assert (record.detection_ms, record.reaction_ms) == (100, 160)
    assert record.violation is not None and record.violation.monitor_id == "box_held@d/2"
    assert [e.step for e in record.recovery] == [1, 2, 5]  # not the other formula's event
    assert record.modes[0] == PfcState.MODE_TRAJ3D and record.modes[-1] == PfcState.MODE_HOVER
    assert PfcState.MODE_BRAKING in record.modes
    assert record.final is not None and record.final.east == 6000.0


def test_a_run_without_a_violation_has_no_detection(tmp_path: Path) -> None:
    record = read_lost_load(write_run(tmp_path / "run.mcap", violated=False), "uav0", "box1")
    assert record.violation is None and record.recovery == () and record.modes == ()
    assert (record.detection_ms, record.reaction_ms) == (None, None)
    assert record.released_ms == 3000


def write_stalled_run(path: Path) -> Path:
    """carrier3 gripped from 1.0 s, the winch stalled from 2.1 s, violated at 3.1 s."""
    out: list[tuple[int, str, Any]] = []
    for ms in range(0, 5001, 100):
        tag = "carrier3" if 1000 <= ms < 3500 else ""
        stalled = 1800 <= ms < 2000 or 2100 <= ms < 3500  # a moment's stall at 1.8 s
        winch = HookState.WINCH_STALLED if stalled else HookState.WINCH_RAISING
        reading = HookState(carrying=bool(tag), object_id=tag, winch=winch)
        out.append((ms, "/uav0/sensors/carrying", reading))
        objects = [WorldObject(id=i, kind="box", east=float(ms)) for i in ("carrier3", "box7")]
        out.append((ms, "/world_sim/objects", WorldObjects(objects=objects)))
    v = MonitorViolation(
        kind=MonitorViolation.KIND_VIOLATION,
        monitor_id="carrier_lifted@d/2",
        argument_names=["carrier"],
        argument_values=["carrier3"],
    )
    out.append((3100, "/uav0/monitor_violations", v))
    for ms, step in ((3150, 1), (3150, 3)):
        out.append((ms, "/uav0/recovery_events", RecoveryEvent(monitor_id=v.monitor_id, step=step)))
    return _write(path, out)


def test_a_failed_lift_is_read_from_the_recording(tmp_path: Path) -> None:
    record = read_failed_lift(write_stalled_run(tmp_path / "run.mcap"), "uav0", "carrier3")
    assert (record.stalled_ms, record.detection_ms) == (2100, 1000)
    assert record.violation is not None and record.violation.monitor_id == "carrier_lifted@d/2"
    assert [e.step for e in record.recovery] == [1, 3]
    assert sorted(record.final) == ["box7", "carrier3"]
    assert record.final["box7"].east == 5000.0
