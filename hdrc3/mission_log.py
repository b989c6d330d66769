"""What a recording says about a mission above the platform: TST nodes, monitors, detections.

Reads the topics of the chapter's upper layers from a recording, for any report: every
elementary TST node that ran (``/<agent>/tst_status``, section 6.3) with its start and end in
sim time, the execution monitor's violations and other verdicts (``/<agent>/monitor_violations``,
section 9.3), the recovery steps (``/<agent>/recovery_events``) and each agent's last saliency
map (``/<agent>/saliency/map``, section 11.1.1). :func:`plot_timeline` draws the nodes and the
flight modes per agent over sim time.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import pymap3d
from rclpy.serialization import deserialize_message

from hdrc3.mcap_recording import RecordedMessage
from hdrc3.message_types import constant_names, message_class
from hdrc3_base.stamps import stamp_s
from hdrc3_interfaces.msg import MonitorViolation, RecoveryEvent
from hdrc3_perception.saliency_map import MapError, locations_from_geojson
from hdrc3_tst.model import NodeKind, NodeState

SUFFIXES = ("/tst_status", "/monitor_violations", "/recovery_events", "/saliency/map")
"""The topics read, after ``/<agent>``."""
_COMPOSITES = frozenset(k.value for k in NodeKind if k is not NodeKind.ACTION)
"""``TstNodeStatus.kind`` of nodes that are not elementary actions (an action's is its name)."""
MONITOR_KINDS = constant_names(MonitorViolation, "KIND_")
"""``MonitorViolation.kind`` -> readable name (violation, stale data, refused)."""
RECOVERY_STEPS = constant_names(RecoveryEvent, "STEP_")
"""``RecoveryEvent.step`` -> readable name (suspended, braked, ..., replanned, gave up)."""


@dataclass(frozen=True, slots=True)
class NodeSpan:
    """An elementary TST node from the time it ran to the time it ended (sim time, s)."""

    mission: str
    agent: str
    node_id: str
    action: str
    start: float
    end: float
    state: str
    reason: str

    @property
    def label(self) -> str:
        """``mission/node action``."""
        return f"{self.mission}/{self.node_id} {self.action}"


@dataclass(frozen=True, slots=True)
class Detection:
    """A point of an agent's last saliency map."""

    agent: str
    latitude: float
    longitude: float
    altitude: float
    certainty: float
    """T_body / T_frame."""
    frames: int
    confirmed: bool
    first_seen: float
    """Sim time of its first positive classification, s."""

    def enu(self, origin: tuple[float, float, float]) -> tuple[float, float]:
        """(east, north) in the local frame of ``origin`` (latitude, longitude, altitude)."""
        e, n, _ = pymap3d.geodetic2enu(self.latitude, self.longitude, self.altitude, *origin)
        return float(e), float(n)


@dataclass
class MissionLog:
    """Collects the upper layers' messages of a recording, in file order."""

    nodes: dict[str, list[NodeSpan]] = field(default_factory=dict)
    """Agent -> its elementary nodes that ended, in the order they ended."""
    monitor: list[Any] = field(default_factory=list)
    """``MonitorViolation`` messages of every kind."""
    recoveries: list[Any] = field(default_factory=list)
    """``RecoveryEvent`` messages."""
    maps: dict[str, str] = field(default_factory=dict)
    """Agent -> the text of its last saliency map."""
    problems: list[str] = field(default_factory=list)
    _running: dict[tuple[str, str, str], tuple[float, str]] = field(default_factory=dict)
    """(agent, mission, node) -> (start, action) of nodes running but not ended yet."""
    _classes: dict[str, Any] = field(default_factory=dict)

    @staticmethod
    def reads(topic: str) -> bool:
        """Whether ``topic`` is one of an agent's topics this log takes."""
        return topic.count("/") >= 2 and topic.endswith(SUFFIXES)

    def add(self, message: RecordedMessage) -> None:
        """Take one recorded message of a topic :meth:`reads`."""
        cls = self._classes.get(message.type_name)
        if cls is None:
            cls = self._classes[message.type_name] = message_class(message.type_name)
        msg = deserialize_message(message.data, cls)
        agent = message.topic.split("/")[1]
        if message.topic.endswith("/tst_status"):
            self._node_status(msg)
        elif message.topic.endswith("/monitor_violations"):
            self.monitor.append(msg)
        elif message.topic.endswith("/recovery_events"):
            self.recoveries.append(msg)
        else:
            self.maps[agent] = str(msg.data)

    def _node_status(self, msg: Any) -> None:
        if msg.kind in _COMPOSITES:
            return
        key = (msg.agent, msg.mission, msg.node_id)
        t = stamp_s(msg.header.stamp)
        if msg.state == NodeState.RUNNING.value and math.isfinite(msg.start):
            self._running.setdefault(key, (t, msg.kind))  # not while it waits to begin
        elif msg.state in {s.value for s in NodeState if s.finished} and key in self._running:
            start, action = self._running.pop(key)
            span = NodeSpan(
                msg.mission, msg.agent, msg.node_id, action, start, t, msg.state, msg.reason
            )
            self.nodes.setdefault(msg.agent, []).append(span)

    def unfinished(self) -> list[NodeSpan]:
        """Nodes still running when the recording ends (end: nan, state: running)."""
        running = NodeState.RUNNING.value
        return [
            NodeSpan(mission, agent, node, action, start, math.nan, running, "")
            for (agent, mission, node), (start, action) in self._running.items()
        ]

    @property
    def violations(self) -> list[Any]:
        """The monitor's violations (not its stale-data or refused notes)."""
        return [m for m in self.monitor if m.kind == MonitorViolation.KIND_VIOLATION]

    def unrecovered(self) -> list[Any]:
        """Violations after which no recovery of the same agent and formula replanned."""
        replanned = [
            (r.agent, r.monitor_id, stamp_s(r.header.stamp))
            for r in self.recoveries
            if r.step == RecoveryEvent.STEP_REPLANNED
        ]
        return [
            v
            for v in self.violations
            if not any(
                a == v.agent and m == v.monitor_id and t >= stamp_s(v.header.stamp)
                for a, m, t in replanned
            )
        ]

    def detections(self) -> list[Detection]:
        """The points of every agent's last map; a malformed map is a problem, not an error."""
        out: list[Detection] = []
        for agent, text in sorted(self.maps.items()):
            try:
                features = _features(text)
            except (ValueError, MapError) as exc:
                self.problems.append(f"{agent}'s saliency map is not readable: {exc}")
                continue
            out += [Detection(agent, *f) for f in features]
        return out


def _features(text: str) -> list[tuple[float, float, float, float, int, bool, float]]:
    """(lat, lon, alt, certainty, frames, confirmed, first seen) of a map's points."""
    data = json.loads(text)
    locations = locations_from_geojson(data)  # raises on a map not written by the saliency node
    out = []
    for feature, location in zip(data["features"], locations, strict=True):
        props = feature["properties"]
        place = [props.get(k) for k in ("lat", "lon", "alt")]
        if not all(isinstance(v, int | float) and math.isfinite(v) for v in place):
            raise MapError(f"feature {location.ident}: needs finite lat, lon and alt")
        lat, lon, alt = (float(v) for v in place)
        confirmed = bool(props.get("confirmed", False))
        out.append(
            (lat, lon, alt, location.p_body, location.t_frame, confirmed, location.first_seen)
        )
    return out


def plot_timeline(
    path: Any,
    nodes: Mapping[str, Sequence[NodeSpan]],
    modes: Mapping[str, Sequence[tuple[float, str]]],
    ends: Mapping[str, float],
) -> None:
    """Per agent its elementary nodes (upper bar) and flight modes (lower bar) over sim time.

    Args:
        path: The PNG to write.
        nodes: Agent -> its node spans; a span without an end (still running) is hatched.
        modes: Agent -> (sim time, flight mode) at every mode change.
        ends: Agent -> its last sim time in the recording, where its last mode and its
            unfinished nodes end.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    agents = sorted(set(nodes) | set(modes))
    names = sorted({name for changes in modes.values() for _, name in changes})
    palette = plt.get_cmap("tab10")
    colours = {
        NodeState.SUCCEEDED.value: "#b5e3b5",
        NodeState.FAILED.value: "tab:red",
        NodeState.ABORTED.value: "tab:orange",
    }
    fig, ax = plt.subplots(figsize=(14, 1.6 + 1.4 * max(1, len(agents))))
    for row, agent in enumerate(agents):
        y = 2 * row
        last = ends.get(agent, math.nan)
        for span in nodes.get(agent, ()):
            open_ended = math.isnan(span.end)
            end = last if open_ended else span.end
            ax.barh(y + 0.5, end - span.start, left=span.start, height=0.8,
                    color=colours.get(span.state, "#cfe2f3"), edgecolor="white",
                    hatch="//" if open_ended else None)  # fmt: skip
            ax.text(span.start + 0.5, y + 0.5, span.action, fontsize=7, va="center", rotation=30)
        changes = modes.get(agent, ())
        for i, (t, name) in enumerate(changes):
            end = changes[i + 1][0] if i + 1 < len(changes) else max(t, last)
            colour = palette(names.index(name) % 10)
            ax.barh(y - 0.4, max(end - t, 0.1), left=t, height=0.6, color=colour)
    for name in names:
        ax.barh(0, 0, color=palette(names.index(name) % 10), label=name)
    if names:
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8, title="flight mode")
    ax.set_yticks([2 * r for r in range(len(agents))], agents)
    ax.set_xlabel(
        "sim time [s] (upper bar: TST nodes, hatched: still running; lower: flight modes)"
    )
    ax.grid(True, axis="x")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
