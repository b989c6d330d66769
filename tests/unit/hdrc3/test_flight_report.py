from pathlib import Path

import pymap3d
import pytest
from rclpy.serialization import serialize_message

from hdrc3.flight_report import build_report, plot_report
from hdrc3.mcap_recording import RecordingWriter, TopicInfo
from hdrc3_base.errors import DataError
from hdrc3_control.path_segment import PathSegment
from hdrc3_interfaces.msg import HelicopterState, PfcState, PlatformEvent

ORIGIN = (55.70, 13.47, 50.0)


def _record(path: Path, offset_north: float) -> None:
    writer = RecordingWriter(path)
    writer.add_topic(TopicInfo("/uav0/helicopter_state", "hdrc3_interfaces/msg/HelicopterState"))
    writer.add_topic(TopicInfo("/uav0/platform_events", "hdrc3_interfaces/msg/PlatformEvent"))
    writer.add_topic(TopicInfo("/uav0/pfc/state", "hdrc3_interfaces/msg/PfcState"))
    for i in range(11):  # 0..100 m east at 10 m/s, offset north
        lat, lon, alt = pymap3d.enu2geodetic(10.0 * i, offset_north, 30.0, *ORIGIN)
        msg = HelicopterState(latitude=lat, longitude=lon, altitude=alt, velocity_east=10.0)
        msg.header.stamp.sec = 100 + i
        writer.write("/uav0/helicopter_state", serialize_message(msg), i)
        pfc = PfcState(mode=PfcState.MODE_HOVER if i < 3 else PfcState.MODE_TRAJ3D)
        pfc.header.stamp.sec = 100 + i
        writer.write("/uav0/pfc/state", serialize_message(pfc), i)
    for sec, kind, reason in (
        (103, PlatformEvent.KIND_SEGMENT_REQUEST, ""),
        (110, PlatformEvent.KIND_FINISHED, ""),
    ):
        event = PlatformEvent(command="fcl_traj3d", kind=kind, reason=reason)
        event.header.stamp.sec = sec
        writer.write("/uav0/platform_events", serialize_message(event), sec)
    writer.close()


def test_report_measures_track_speed_and_cross_track(tmp_path: Path) -> None:
    rec = tmp_path / "flight.mcap"
    _record(rec, offset_north=2.0)
    plan = [PathSegment.straight((0.0, 0.0, 30.0), (100.0, 0.0, 30.0), 10.0)]
    report = build_report(rec, "uav0", ORIGIN)
    report.measure_cross_track(plan, window=(0.0, 10.0))
    assert len(report.track) == 11
    assert report.distance == pytest.approx(100.0, abs=0.05)
    assert report.max_speed == pytest.approx(10.0)
    assert report.duration == pytest.approx(10.0)
    assert report.cross_track_rms() == pytest.approx(2.0, abs=0.01)
    assert [(e.time, e.kind) for e in report.events] == [
        (3.0, "SEGMENT_REQUEST"),
        (10.0, "FINISHED"),
    ]
    text = "\n".join(report.summary())
    assert "distance flown         100.0 m" in text
    assert "fcl_traj3d             FINISHED" in text
    assert "modes               hover -> traj3d" in text
    png = plot_report(report, tmp_path / "flight.png", plan)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_recording_without_state_names_its_topics(tmp_path: Path) -> None:
    rec = tmp_path / "empty.mcap"
    writer = RecordingWriter(rec)
    writer.add_topic(TopicInfo("/other", "std_msgs/msg/String"))
    writer.close()
    with pytest.raises(DataError, match="has no /uav0/helicopter_state; topics: /other"):
        build_report(rec, "uav0", ORIGIN)
