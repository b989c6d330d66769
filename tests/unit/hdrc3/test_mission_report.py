"""A mission read from a recording: agents, one ENU frame, events, topics, damaged files."""

from __future__ import annotations

from pathlib import Path

import pymap3d
import pytest

from hdrc3.fake_recording import FAILURE, ORIGIN, write_fake_flights
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
