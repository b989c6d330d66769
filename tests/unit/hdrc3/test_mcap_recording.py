from pathlib import Path

import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rclpy.serialization import deserialize_message, serialize_message

from hdrc3.mcap_recording import RecordingReader, RecordingWriter, TopicInfo
from hdrc3_base.errors import DataError, Hdrc3Error
from hdrc3_interfaces.msg import HelicopterState

TOPIC = "/uav0/helicopter_state"
TYPE = "hdrc3_interfaces/msg/HelicopterState"


def _state(i: int) -> bytes:
    return serialize_message(HelicopterState(altitude=float(i), rpm=850.0, auto_flag=i % 2 == 0))


def _altitude(data: bytes) -> float:
    return float(deserialize_message(data, HelicopterState).altitude)


def _write(path: Path, count: int, flush_every: int = 0) -> RecordingWriter:
    writer = RecordingWriter(path, flush_period_ns=10**18)
    writer.add_topic(TopicInfo(TOPIC, TYPE, "- history: 1"))
    for i in range(count):
        writer.write(TOPIC, _state(i), log_time_ns=1_000 + i)
        if flush_every and (i + 1) % flush_every == 0:
            writer.flush()
    return writer


def test_round_trip_through_independent_decoder(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    _write(path, 50).close()
    with path.open("rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        assert summary is not None
        assert [s.encoding for s in summary.schemas.values()] == ["ros2msg"]
        assert [c.message_encoding for c in summary.channels.values()] == ["cdr"]
        decoded = [m.altitude for _, _, _, m in reader.iter_decoded_messages()]
    assert decoded == [float(i) for i in range(50)]


def test_reader_returns_messages_and_topics(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    _write(path, 5).close()
    reader = RecordingReader.open(path)
    assert reader.topics() == {TOPIC: TYPE}
    messages = list(reader.messages())
    assert [deserialize_message(m.data, HelicopterState).altitude for m in messages] == [
        0.0,
        1.0,
        2.0,
        3.0,
        4.0,
    ]
    assert [m.log_time_ns for m in messages] == [1000, 1001, 1002, 1003, 1004]
    assert not reader.truncated


@pytest.mark.parametrize(
    ("topics", "count"), [(None, 7), ([TOPIC], 5), (["/uav0/other"], 2), (["/none"], 0)]
)
def test_message_count_comes_from_the_summary(
    tmp_path: Path, topics: list[str] | None, count: int
) -> None:
    path = tmp_path / "run.mcap"
    writer = _write(path, 5)
    writer.add_topic(TopicInfo("/uav0/other", TYPE))
    for i in range(2):
        writer.write("/uav0/other", _state(i), log_time_ns=2_000 + i)
    writer.close()
    assert RecordingReader.open(path).message_count(topics) == count


def test_a_file_without_summary_has_no_message_count(tmp_path: Path) -> None:
    path = tmp_path / "killed.mcap"
    _write(path, 20, flush_every=10)  # no close(): no footer, no summary
    assert RecordingReader.open(path).message_count() is None


def test_killed_writer_leaves_file_readable_up_to_last_chunk(tmp_path: Path) -> None:
    path = tmp_path / "killed.mcap"
    writer = _write(path, 30, flush_every=10)  # three complete chunks on disk
    writer.write(TOPIC, _state(99), log_time_ns=5_000)  # in the open chunk: lost
    # No close(): the process "dies" here. Cut the file mid-record as well.
    data = path.read_bytes()
    for cut in (len(data), len(data) - 7):
        partial = tmp_path / f"cut{cut}.mcap"
        partial.write_bytes(data[:cut])
        reader = RecordingReader.open(partial)
        altitudes = [
            deserialize_message(m.data, HelicopterState).altitude for m in reader.messages()
        ]
        assert reader.truncated
        assert altitudes[:20] == [float(i) for i in range(20)]
        assert len(altitudes) in (20, 30)
    assert len(list(RecordingReader.open(tmp_path / f"cut{len(data)}.mcap").messages())) == 30


def test_time_based_flush_closes_chunks(tmp_path: Path) -> None:
    path = tmp_path / "periodic.mcap"
    writer = RecordingWriter(path, flush_period_ns=100)
    writer.add_topic(TopicInfo(TOPIC, TYPE))
    for i in range(10):
        writer.write(TOPIC, _state(i), log_time_ns=i * 60)
    # Without close, every message older than the last flush is already on disk.
    on_disk = list(RecordingReader.open(path).messages())
    assert len(on_disk) >= 8


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (None, "no such recording"),
        (b"hello world, not mcap", "not an MCAP file"),
    ],
)
def test_bad_files_are_rejected(tmp_path: Path, content: bytes | None, message: str) -> None:
    path = tmp_path / "bad.mcap"
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(DataError, match=message):
        RecordingReader.open(path)


def test_corrupt_chunk_is_reported(tmp_path: Path) -> None:
    path = tmp_path / "corrupt.mcap"
    _write(path, 20).close()
    with path.open("rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None
    chunk = summary.chunk_indexes[0]
    data = bytearray(path.read_bytes())
    data[chunk.chunk_start_offset + chunk.chunk_length - 10] ^= 0xFF  # inside the payload
    path.write_bytes(bytes(data))
    with pytest.raises(DataError, match="corrupt"):
        list(RecordingReader.open(path).messages())


def test_writing_an_unregistered_topic_is_misuse(tmp_path: Path) -> None:
    writer = RecordingWriter(tmp_path / "x.mcap")
    with pytest.raises(Hdrc3Error, match="no channel"):
        writer.write("/nope", b"", 0)
    writer.close()


def test_unwritable_output_is_a_data_error(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="cannot create"):
        RecordingWriter(tmp_path / "missing-dir" / "x.mcap")


def test_other_channels_sit_beside_the_ros_topics_but_are_not_topics(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    writer = _write(path, 2)
    writer.add_channel("/live/tst", ("hdrc3.TstTable", "jsonschema", b"{}"), "json")
    writer.write("/live/tst", b'{"nodes":[]}', log_time_ns=2_000)
    writer.close()
    reader = RecordingReader.open(path)
    assert reader.topics() == {TOPIC: TYPE}  # what replay republishes
    last = list(reader.messages())[-1]
    assert (last.topic, last.type_name, last.data) == (
        "/live/tst",
        "hdrc3.TstTable",
        b'{"nodes":[]}',
    )
    with path.open("rb") as stream:
        channels = make_reader(stream).get_summary().channels.values()
    assert sorted(c.message_encoding for c in channels) == ["cdr", "json"]
