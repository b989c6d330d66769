"""A mission read from a recording: agents, one ENU frame, events, topics, damaged files."""

from __future__ import annotations

from pathlib import Path

import pymap3d
import pytest
from rclpy.serialization import serialize_message
from std_msgs.msg import String

from hdrc3.fake_recording import DETECTIONS, FAILURE, ORIGIN, write_fake_flights
from hdrc3.mcap_recording import RecordingWriter, TopicInfo
from hdrc3.mission_report import read_mission
from hdrc3_base.errors import DataError


def test_every_agent_in_one_frame_with_events_and_topic_rates(tmp_path: Path) -> None:
    rec = tmp_path / "run.mcap"
    write_fake_flights(rec)
    seen: list[tuple[int, int | None]] = []
    data = read_mission(rec, lambda done, total: seen.append((done, total)))
    assert list(data.flights) == ["uav0", "uav1"]
    assert data.origin == pytest.approx(pymap3d.enu2geodetic(0.0, 0.0, 30.0, *ORIGIN))
    uav1 = data.flights["uav1"]
    assert (uav1.track[0].east, uav1.track[0].north) == pytest.approx((0.0, 40.0), abs=1e-3)
    assert uav1.distance == pytest.approx(100.0, abs=0.05)
    assert [m for _, m in uav1.modes] == ["hover", "flyto"]
    assert uav1.start == pytest.approx(100.0)
    assert [(e.kind, e.reason) for e in uav1.events] == [("FAILED", FAILURE)]
    assert data.topics["/uav0/helicopter_state"].count == 11
    assert data.topics["/uav0/helicopter_state"].rate == pytest.approx(1.0)
    assert data.messages == 2 * 22 + 3 and data.problems == []
    assert seen[-1] == (data.messages, data.messages)


def test_truncated_recording_gives_what_it_holds_and_says_so(tmp_path: Path) -> None:
    rec = tmp_path / "run.mcap"
    write_fake_flights(rec)
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(rec.read_bytes()[: rec.stat().st_size // 2])
    data = read_mission(cut)
    assert any("ends mid-record" in p for p in data.problems)
    assert data.messages <= 47  # complete chunks only


def test_recording_without_flights_is_reported_not_refused(tmp_path: Path) -> None:
    rec = tmp_path / "other.mcap"
    write_fake_flights(rec, agents={})
    data = read_mission(rec)
    assert data.flights == {}
    assert data.problems == [
        "no Data Interface topic (/<agent>/helicopter_state): no flights to show"
    ]


@pytest.mark.parametrize(
    ("content", "words"), [(None, "no such recording"), (b"x" * 64, "not an MCAP")]
)
def test_not_a_recording_is_a_data_error(tmp_path: Path, content: bytes | None, words: str) -> None:
    path = tmp_path / "bad.mcap"
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(DataError, match=words):
        read_mission(path)


def test_the_upper_layers_nodes_verdicts_recoveries_and_detections(tmp_path: Path) -> None:
    data = read_mission(write_fake_flights(tmp_path / "run.mcap", upper_layers=True))
    log = data.log
    spans = {
        a: [(n.node_id, n.action, n.start, n.end, n.state) for n in s] for a, s in log.nodes.items()
    }
    assert spans == {
        "uav0": [("fly", "fly-to", 101.0, 109.0, "succeeded")],  # the sequence is not an action
        "uav1": [("scan", "scan-area", 102.0, 108.0, "failed")],
    }
    assert log.nodes["uav1"][0].reason == FAILURE
    assert [v.monitor_id for v in log.monitor] == ["speed_limit", "held"]
    assert [v.monitor_id for v in log.unrecovered()] == ["speed_limit"]  # hovered, no new plan
    assert [r.node_id for r in log.recoveries] == ["scan"]
    assert data.origin is not None and data.problems == []
    places = [(d.agent, *d.enu(data.origin), d.confirmed) for d in data.detections]
    expected = [("uav0", e, n, c) for e, n, c in DETECTIONS]
    assert places == [pytest.approx(x) for x in expected]


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("{", "not readable: Expecting property name"),
        ('{"type": "Feature"}', "not readable: not a GeoJSON FeatureCollection"),
    ],
)
def test_a_malformed_saliency_map_is_a_problem_not_an_error(
    tmp_path: Path, text: str, words: str
) -> None:
    rec = tmp_path / "run.mcap"
    writer = RecordingWriter(rec)
    writer.add_topic(TopicInfo("/uav0/saliency/map", "std_msgs/msg/String"))
    writer.write("/uav0/saliency/map", serialize_message(String(data=text)), 10**9)
    writer.close()
    data = read_mission(rec)
    assert data.detections == []
    assert any(f"uav0's saliency map is {words}" in p for p in data.problems), data.problems
