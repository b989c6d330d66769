"""What a recording says about a mission: every agent's flight, its events and modes, the topics.

Above the platform (:mod:`hdrc3.mission_log`): the TST nodes that ran, the execution monitors'
verdicts, the recoveries and the saliency maps' detections.

Reads any MCAP recording written by ``hdrc3 record`` / ``hdrc3 launch --record`` in one pass. The
agents are found from their Data Interface topics (``/<agent>/helicopter_state``); all tracks share
one local ENU frame whose origin is the first Data Interface sample in the file. A recording that
ends mid-record (a killed recorder) or holds corrupt data still gives a report of what could be
read, with the problem named in :attr:`MissionData.problems`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from hdrc3.flight_report import FlightReport, FlightReportBuilder
from hdrc3.mcap_recording import RecordingReader
from hdrc3.mission_log import Detection, MissionLog
from hdrc3_base.errors import DataError

STATE_SUFFIX = "/helicopter_state"
"""The Data Interface topic of an agent: ``/<agent>/helicopter_state`` (chapter 6.2.4)."""

Progress = Callable[[int, int | None], None]
"""Called with (messages read so far, total or None when the file has no summary)."""


@dataclass
class TopicStats:
    """How much one topic holds."""

    type_name: str
    count: int = 0
    first_ns: int = 0
    last_ns: int = 0

    @property
    def rate(self) -> float:
        """Mean message rate over the topic's own time span, Hz (0 for fewer than 2)."""
        span = (self.last_ns - self.first_ns) * 1e-9
        return (self.count - 1) / span if self.count > 1 and span > 0 else 0.0


@dataclass
class MissionData:
    """Everything the report shows, read from one recording."""

    recording: Path
    topics: dict[str, TopicStats] = field(default_factory=dict)
    flights: dict[str, FlightReport] = field(default_factory=dict)
    origin: tuple[float, float, float] | None = None
    """(latitude, longitude, altitude) of the common ENU frame."""
    log: MissionLog = field(default_factory=MissionLog)
    """TST nodes, monitor verdicts, recoveries and saliency maps."""
    detections: list[Detection] = field(default_factory=list)
    """The points of every agent's last saliency map."""
    problems: list[str] = field(default_factory=list)

    @property
    def messages(self) -> int:
        """Messages read."""
        return sum(t.count for t in self.topics.values())

    @property
    def duration(self) -> float:
        """Log time from the first to the last message read, s."""
        if not self.topics:
            return 0.0
        first = min(t.first_ns for t in self.topics.values())
        last = max(t.last_ns for t in self.topics.values())
        return (last - first) * 1e-9


def read_mission(path: Path, progress: Progress | None = None) -> MissionData:
    """Read ``path`` once; raises DataError only when it is not a readable MCAP file at all."""
    reader = RecordingReader.open(path)
    total = reader.message_count()
    data = MissionData(path)
    builders: dict[str, FlightReportBuilder] = {}
    try:
        for message in reader.messages():
            stats = data.topics.get(message.topic)
            if stats is None:
                stats = data.topics[message.topic] = TopicStats(
                    message.type_name, first_ns=message.log_time_ns
                )
            stats.count += 1
            stats.last_ns = message.log_time_ns
            if MissionLog.reads(message.topic):
                data.log.add(message)
            builder = _builder_of(message.topic, builders, data)
            if builder is not None:
                if builder.origin is None and data.origin is not None:
                    builder.origin = data.origin
                builder.add(message)
                data.origin = data.origin or builder.origin
            if progress is not None and data.messages % 5000 == 0:
                progress(data.messages, total)
    except DataError as exc:
        data.problems.append(
            f"reading stopped at corrupt data after {data.messages} messages: {exc}"
        )
    if reader.truncated:
        data.problems.append(
            f"the recording ends mid-record (a recorder killed while writing): "
            f"{data.messages} complete messages read"
        )
    if not builders:
        data.problems.append(
            "no Data Interface topic (/<agent>/helicopter_state): no flights to show"
        )
    data.flights = {agent: b.report for agent, b in sorted(builders.items())}
    data.detections = data.log.detections()
    data.problems += data.log.problems
    if progress is not None:
        progress(data.messages, total)
    return data


def _builder_of(
    topic: str, builders: dict[str, FlightReportBuilder], data: MissionData
) -> FlightReportBuilder | None:
    """The flight builder that reads ``topic``, created with its agent's Data Interface topic."""
    parts = topic.split("/")
    if len(parts) < 3 or not parts[1]:
        return None
    agent = parts[1]
    if topic == f"/{agent}{STATE_SUFFIX}" and agent not in builders:
        builders[agent] = FlightReportBuilder(agent, data.origin)
    builder = builders.get(agent)
    return builder if builder is not None and topic in builder.topics else None
