"""States from MCAP recordings: field paths, message-time and periodic states, bad input."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_base.errors import ConfigError, DataError
from hdrc3_dyknow.fake_recording import FakeSample, write_fake_recording
from hdrc3_dyknow.trace_mcap import FluentSource, parse_fluent_source, read_trace_mcap

ALT = "altitude(uav0)=/uav0/helicopter_state.altitude"
CARRY = "carrying(uav1, box)=/uav1/helicopter_state.carrying"


@pytest.fixture
def recording(tmp_path: Path) -> Path:
    path = tmp_path / "flight.mcap"
    samples = [FakeSample("uav0", t, t / 100) for t in range(0, 500, 100)]
    samples += [FakeSample("uav1", t, 5.0, carrying=t > 100) for t in (50, 150, 350)]
    write_fake_recording(path, samples)
    return path


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (ALT, FluentSource("altitude(uav0)", "/uav0/helicopter_state", ("altitude",))),
        ("z=/a/b.pose.position.z", FluentSource("z", "/a/b", ("pose", "position", "z"))),
        ("v=/a/b.values.2", FluentSource("v", "/a/b", ("values", "2"))),
        (CARRY, FluentSource("carrying(uav1,box)", "/uav1/helicopter_state", ("carrying",))),
    ],
)
def test_parse_fluent_source(text: str, expected: FluentSource) -> None:
    assert parse_fluent_source(text) == expected


@pytest.mark.parametrize("text", ["alt", "alt=/topic", "alt=topic.x", "alt=/t.x..y", "(=/t.x"])
def test_bad_fluent_sources(text: str) -> None:
    with pytest.raises(ConfigError):
        parse_fluent_source(text)


def test_states_at_message_times_once_all_topics_arrived(recording: Path) -> None:
    sources = [parse_fluent_source(ALT), parse_fluent_source(CARRY)]
    states = list(read_trace_mcap(recording, sources))
    assert [s.time_ms for s in states] == [50, 100, 150, 200, 300, 350, 400]
    assert states[0].values == {"altitude(uav0)": 0.0, "carrying(uav1,box)": False}
    assert states[2].values == {"altitude(uav0)": 1.0, "carrying(uav1,box)": True}


def test_states_on_a_period_grid(recording: Path) -> None:
    sources = [parse_fluent_source(ALT), parse_fluent_source(CARRY)]
    states = list(read_trace_mcap(recording, sources, period_ms=120))
    assert [s.time_ms for s in states] == [50, 170, 290]  # 410 lies after the last message
    assert [s.values["altitude(uav0)"] for s in states] == [0.0, 1.0, 2.0]


@pytest.mark.parametrize(
    ("mapping", "period", "error", "message"),
    [
        ("a=/uav9/helicopter_state.altitude", None, ConfigError, "no topic /uav9"),
        ("a=/uav0/helicopter_state.heading", None, DataError, "no field 'heading'"),
        ("a=/uav0/helicopter_state.position", None, DataError, "not a number"),
        (ALT, 0.0, ConfigError, "positive"),
    ],
)
def test_bad_requests(
    recording: Path, mapping: str, period: float | None, error: type[Exception], message: str
) -> None:
    with pytest.raises(error, match=message):
        list(read_trace_mcap(recording, [parse_fluent_source(mapping)], period))


def test_unreadable_recording(tmp_path: Path) -> None:
    path = tmp_path / "broken.mcap"
    path.write_bytes(b"not an mcap file at all")
    with pytest.raises(DataError):
        list(read_trace_mcap(path, [parse_fluent_source(ALT)]))
