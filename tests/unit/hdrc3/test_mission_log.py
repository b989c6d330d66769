"""The upper layers in a recording: TST node spans, monitor verdicts, recoveries, detections."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from rclpy.serialization import serialize_message
from std_msgs.msg import String

from hdrc3.fake_recording import DETECTIONS, FAILURE, write_fake_flights
from hdrc3.mcap_recording import RecordingWriter, TopicInfo
from hdrc3.mission_report import read_mission


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
    (look,) = log.unfinished()
    assert (look.agent, look.node_id, look.action, look.start) == ("uav0", "look", "look-at", 109.5)
    assert look.state == "running" and math.isnan(look.end)
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
