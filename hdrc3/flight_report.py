"""Flight report from a recording: track, speed profile, events, tracking error, and a PNG.

Reads the Data Interface (`<agent>/helicopter_state`) and the platform events
(`<agent>/platform_events`) out of an MCAP recording, compares the flown track with the planned
path, and draws track, speed and event timeline with matplotlib.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pymap3d
from numpy.typing import NDArray
from rclpy.serialization import deserialize_message

from hdrc3.mcap_recording import RecordedMessage, RecordingReader
from hdrc3.message_types import constant_names, message_class
from hdrc3_base.errors import DataError
from hdrc3_base.stamps import stamp_s
from hdrc3_control.path_segment import PathSegment
from hdrc3_platform_server.codes import EventKind


@dataclass(frozen=True, slots=True)
class TrackPoint:
    """One Data Interface sample in the local ENU frame."""

    time: float
    """Seconds since the first sample."""
    east: float
    north: float
    up: float
    speed: float
    """Horizontal speed, m/s."""
    on_ground: bool
    auto: bool


@dataclass(frozen=True, slots=True)
class EventMark:
    """One platform event on the timeline."""

    time: float
    command: str
    kind: str
    reason: str


@dataclass
class FlightReport:
    """What happened in one agent's flight."""

    agent: str
    track: list[TrackPoint] = field(default_factory=list)
    events: list[EventMark] = field(default_factory=list)
    cross_track: list[float] = field(default_factory=list)
    """Distance of each in-path sample to the planned path, m."""
    modes: list[tuple[float, str]] = field(default_factory=list)
    """(time, PFC flight mode) at every mode change, from `<agent>/pfc/state`."""
    start: float = math.nan
    """Sim time of the first sample, s (the zero of the other times)."""

    @property
    def distance(self) -> float:
        """Distance flown along the track, m (3D)."""
        return float(
            sum(
                math.dist((a.east, a.north, a.up), (b.east, b.north, b.up))
                for a, b in zip(self.track, self.track[1:], strict=False)
            )
        )

    @property
    def max_speed(self) -> float:
        """Largest horizontal speed, m/s."""
        return max((p.speed for p in self.track), default=0.0)

    @property
    def duration(self) -> float:
        """Time from the first to the last sample, s."""
        return self.track[-1].time - self.track[0].time if self.track else 0.0

    def cross_track_rms(self) -> float:
        """RMS distance to the planned path while flying it, m (nan without a plan)."""
        if not self.cross_track:
            return math.nan
        return float(math.sqrt(sum(e * e for e in self.cross_track) / len(self.cross_track)))

    def measure_cross_track(self, plan: Sequence[PathSegment], window: tuple[float, float]) -> None:
        """Measure each sample's distance to the planned path while it was flown.

        Args:
            plan: Planned path.
            window: Times (s since the first sample) between which the plan was flown.
        """
        samples = _sample_plan(plan)
        self.cross_track = [
            float(np.min(np.linalg.norm(samples - np.array([p.east, p.north, p.up]), axis=1)))
            for p in self.track
            if window[0] <= p.time <= window[1]
        ]

    def summary(self) -> list[str]:
        """One screen of text."""
        lines = [
            f"agent {self.agent}: {len(self.track)} state samples over {self.duration:.1f} s",
            f"  distance flown      {self.distance:8.1f} m",
            f"  max speed           {self.max_speed:8.1f} m/s",
        ]
        if self.cross_track:
            lines.append(
                f"  tracking error      {self.cross_track_rms():8.2f} m RMS, "
                f"{max(self.cross_track):.2f} m max (on the survey path)"
            )
        if self.modes:
            lines.append(f"  modes               {' -> '.join(m for _, m in self.modes)}")
        lines.append(f"  events              {len(self.events)}")
        for event in self.events:
            if event.kind in ("SEGMENT_REQUEST", "INFO"):
                continue
            reason = f" ({event.reason})" if event.reason else ""
            lines.append(f"    {event.time:7.1f} s  {event.command:<22} {event.kind}{reason}")
        requests = sum(1 for e in self.events if e.kind == "SEGMENT_REQUEST")
        infos = sum(1 for e in self.events if e.kind == "INFO")
        lines.append(f"    + {requests} segment requests, {infos} progress reports")
        return lines


def _to_enu(
    origin: tuple[float, float, float], lat: float, lon: float, alt: float
) -> NDArray[np.float64]:
    e, n, u = pymap3d.geodetic2enu(lat, lon, alt, *origin)
    return np.array([e, n, u])


def _sample_plan(plan: Sequence[PathSegment], step: float = 0.5) -> NDArray[np.float64]:
    points = []
    for segment in plan:
        count = max(2, int(segment.arc_length() / step))
        points += [segment.position(s) for s in np.linspace(0.0, 1.0, count)]
    return np.array(points)


class FlightReportBuilder:
    """Builds one agent's :class:`FlightReport` from its recorded messages, in file order.

    ``origin`` (latitude, longitude, altitude) fixes the ENU frame; None takes the agent's first
    Data Interface sample as the origin.
    """

    def __init__(self, agent: str, origin: tuple[float, float, float] | None) -> None:
        self.report = FlightReport(agent)
        self.origin = origin
        self.state_topic = f"/{agent}/helicopter_state"
        self.events_topic = f"/{agent}/platform_events"
        self.pfc_topic = f"/{agent}/pfc/state"
        self._classes: dict[str, Any] = {}
        self._mode_names: dict[int, str] = {}
        self._t0: float | None = None

    @property
    def topics(self) -> tuple[str, str, str]:
        """The topics this builder reads."""
        return (self.state_topic, self.events_topic, self.pfc_topic)

    def _decode(self, message: RecordedMessage) -> Any:
        cls = self._classes.get(message.topic)
        if cls is None:
            cls = self._classes[message.topic] = message_class(message.type_name)
            if message.topic == self.pfc_topic:
                self._mode_names = constant_names(cls, "MODE_")
        return deserialize_message(message.data, cls)

    def add(self, message: RecordedMessage) -> None:
        """Take one message of one of :attr:`topics`."""
        msg = self._decode(message)
        stamp = stamp_s(msg.header.stamp)
        report = self.report
        if message.topic == self.pfc_topic:
            if self._t0 is None:
                return
            mode = self._mode_names.get(msg.mode, str(msg.mode))
            if not report.modes or report.modes[-1][1] != mode:
                report.modes.append((stamp - self._t0, mode))
        elif message.topic == self.state_topic:
            if self._t0 is None:
                self._t0 = report.start = stamp
            if self.origin is None:
                self.origin = (msg.latitude, msg.longitude, msg.altitude)
            e, n, u = _to_enu(self.origin, msg.latitude, msg.longitude, msg.altitude)
            report.track.append(
                TrackPoint(
                    stamp - self._t0,
                    float(e),
                    float(n),
                    float(u),
                    math.hypot(msg.velocity_north, msg.velocity_east),
                    bool(msg.on_ground_flag),
                    bool(msg.auto_flag),
                )
            )
        else:
            report.events.append(
                EventMark(
                    stamp - (self._t0 if self._t0 is not None else stamp),
                    msg.command,
                    _event_kind(msg.kind),
                    msg.reason,
                )
            )


def _event_kind(kind: int) -> str:
    """A PlatformEvent kind's name (``FINISHED``), or its number if this build does not know it."""
    try:
        return EventKind(kind).name
    except ValueError:
        return str(kind)


def build_report(recording: Path, agent: str, origin: tuple[float, float, float]) -> FlightReport:
    """Read one agent's flight out of a recording.

    Args:
        recording: MCAP file written by `hdrc3 record` / `hdrc3 launch --record`.
        agent: Agent namespace without slashes, e.g. ``uav0``.
        origin: World origin (latitude, longitude, altitude) for the ENU frame.
    """
    reader = RecordingReader.open(recording)
    topics = reader.topics()
    builder = FlightReportBuilder(agent, origin)
    if builder.state_topic not in topics:
        raise DataError(
            f"{recording} has no {builder.state_topic}; topics: {', '.join(sorted(topics))}"
        )
    for message in reader.messages(builder.topics):
        builder.add(message)
    return builder.report


def plot_report(report: FlightReport, out: Path, plan: Sequence[PathSegment] = ()) -> Path:
    """Draw track (with the plan), speed profile and event timeline into one PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(15, 7))
    grid = fig.add_gridspec(3, 2, width_ratios=(1, 1.3))
    ax_track = fig.add_subplot(grid[:, 0])
    ax_speed = fig.add_subplot(grid[0:2, 1])
    ax_mode = fig.add_subplot(grid[2, 1], sharex=ax_speed)
    east = [p.east for p in report.track]
    north = [p.north for p in report.track]
    if plan:
        samples = _sample_plan(plan)
        ax_track.plot(samples[:, 0], samples[:, 1], "--", color="grey", label="planned path")
    ax_track.plot(east, north, color="tab:blue", label="flown track")
    if report.track:
        ax_track.plot(east[0], north[0], "go", label="start")
        ax_track.plot(east[-1], north[-1], "rs", label="end")
    ax_track.set_xlabel("east [m]")
    ax_track.set_ylabel("north [m]")
    ax_track.set_aspect("equal", adjustable="datalim")
    ax_track.set_title(f"{report.agent}: track")
    ax_track.legend(loc="best")
    ax_track.grid(True)
    times = [p.time for p in report.track]
    ax_speed.plot(times, [p.speed for p in report.track], label="horizontal speed [m/s]")
    ax_speed.plot(times, [p.up for p in report.track], label="altitude (ENU up) [m]")
    terminal = [e for e in report.events if e.kind in ("FINISHED", "FAILED", "CANCELLED")]
    for index, event in enumerate(terminal):
        ax_speed.axvline(event.time, color="tab:red", linestyle=":", linewidth=0.8)
        ax_speed.annotate(
            f"{event.command.removeprefix('fcl_')} {event.kind.lower()}",
            (event.time, 0.97 - 0.12 * (index % 3)),
            xycoords=("data", "axes fraction"),
            rotation=0,
            fontsize=7,
            va="top",
        )
    ax_speed.set_title("speed and altitude; command outcomes")
    ax_speed.legend(loc="center right")
    ax_speed.grid(True)
    names = list(dict.fromkeys(mode for _, mode in report.modes))  # order of first use
    if report.modes and times:
        mode_times = [t for t, _ in report.modes] + [times[-1]]
        levels = [names.index(mode) for _, mode in report.modes]
        ax_mode.step(mode_times, [*levels, levels[-1]], where="post", color="tab:purple")
        ax_mode.set_yticks(range(len(names)), names, fontsize=7)
    ax_mode.set_xlabel("sim time [s]")
    ax_mode.set_title("PFC flight mode", fontsize=9)
    ax_mode.grid(True)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out
