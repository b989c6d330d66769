"""The emergency-services mission's report: what was found, delivered, violated and recovered.

Reads the flagship's products (``hdrc3 demo --out DIR``): the recording ``run.mcap``, the merged
saliency map and the leg II TST's drop points. It measures against the world file's ground
truth, which here only scores the run (the mission itself never reads it): the people in the
region found by a confirmed map point within :data:`FOUND_WITHIN_M`, the confirmed points with no
person near (false positives), where every box finally lies against its drop point, the
execution monitor's violations and whether a recovery replanned after each, and the closest
approach of two aircraft. Figures: ``map.png`` (region, tracks, people, map points, drop points,
boxes) and ``timeline.png`` (per agent the TST nodes over sim time, and the PFC's flight modes);
``index.html`` shows them with the tables and the general recording report's figures.
"""

from __future__ import annotations

import html
import math
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rclpy.serialization import deserialize_message
from shapely.geometry import Point, Polygon

from hdrc3.emergency_mission import Body
from hdrc3.mcap_recording import RecordingReader
from hdrc3.message_types import constant_names, message_class
from hdrc3.mission_log import MissionLog, NodeSpan, plot_timeline
from hdrc3.mission_report import read_mission
from hdrc3.recovery_record import stamp_ms
from hdrc3.report_page import write_report
from hdrc3_interfaces.msg import PfcState
from hdrc3_platform_server.geo_frame import frame_from_world
from sim.world import ObjectKind
from sim.world_loader import load_world

FOUND_WITHIN_M = 3.0
"""m: a person counts as found with a confirmed map point this close (chapter: ~2 m bias)."""
DELIVERED_WITHIN_M = 5.0
"""m of its drop point where a box must lie, no longer held, to count as delivered."""


@dataclass(frozen=True)
class Delivery:
    """One box's delivery as recorded."""

    box: str
    body: str
    target: tuple[float, float]
    final: tuple[float, float] | None
    held_by: str

    @property
    def error(self) -> float:
        """M from the drop point (inf when the box was never seen)."""
        if self.final is None:
            return math.inf
        return math.hypot(self.final[0] - self.target[0], self.final[1] - self.target[1])

    @property
    def delivered(self) -> bool:
        """On the ground within :data:`DELIVERED_WITHIN_M` of the drop point."""
        return not self.held_by and self.error <= DELIVERED_WITHIN_M


@dataclass
class Evaluation:
    """The mission scored against the world file."""

    people: list[tuple[str, float, float]] = field(default_factory=list)
    """(id, east, north) of every person in the region."""
    found: dict[str, tuple[Body, float]] = field(default_factory=dict)
    """Person id -> the confirmed point that found it and its error, m."""
    false_positives: list[Body] = field(default_factory=list)
    deliveries: list[Delivery] = field(default_factory=list)
    violations: list[Any] = field(default_factory=list)
    """The execution monitors' ``MonitorViolation`` messages of kind violation."""
    unrecovered: list[Any] = field(default_factory=list)
    recoveries: list[Any] = field(default_factory=list)
    tracks: dict[str, list[tuple[float, float, float, float]]] = field(default_factory=dict)
    """Per agent (sim s, east, north, up) in the world's frame."""
    nodes: dict[str, list[NodeSpan]] = field(default_factory=dict)
    """Per agent its elementary action nodes (a goal node's are its plan's steps)."""
    modes: dict[str, list[tuple[float, str]]] = field(default_factory=dict)
    min_separation: float = math.inf
    """m: the closest two aircraft came to each other in the air."""

    @property
    def sim_seconds(self) -> float:
        """Sim time the recording's Data Interface samples span, s."""
        times = [p[0] for track in self.tracks.values() for p in track]
        return max(times) - min(times) if times else 0.0

    def targets(self, wall_seconds: float) -> list[tuple[str, bool]]:
        """Issue 18's targets for the flagship, each with whether this run met it."""
        speed = self.sim_seconds / wall_seconds if wall_seconds > 0 else 0.0
        return [
            (
                f"all people in the region found ({len(self.found)}/{len(self.people)}), "
                f"<= 1 false positive ({len(self.false_positives)})",
                len(self.found) == len(self.people) and len(self.false_positives) <= 1,
            ),
            (
                f"every box delivered ({sum(d.delivered for d in self.deliveries)}"
                f"/{len(self.deliveries)})",
                bool(self.deliveries) and all(d.delivered for d in self.deliveries),
            ),
            (f"0 unrecovered violations ({len(self.unrecovered)})", not self.unrecovered),
            (f"wall time <= 15 min ({wall_seconds / 60:.1f} min)", wall_seconds <= 900.0),
            (
                f"faster than real time ({self.sim_seconds:.0f} s of sim in {wall_seconds:.0f} s "
                f"wall: {speed:.2f}x)",
                speed >= 1.0,
            ),
        ]

    def summary(self) -> list[str]:
        """Lines for the demo's one-screen summary."""
        delivered = sum(d.delivered for d in self.deliveries)
        errors = [e for _, e in self.found.values()]
        mean = f", mean error {sum(errors) / len(errors):.1f} m" if errors else ""
        lines = [
            f"  bodies found: {len(self.found)} of {len(self.people)} people in the region{mean}; "
            f"{len(self.false_positives)} false positive(s)",
            f"  boxes delivered: {delivered} of {len(self.deliveries)} "
            f"(on the ground within {DELIVERED_WITHIN_M:g} m of the drop point)",
            f"  monitor violations: {len(self.violations)}, recovered by replanning: "
            f"{len(self.violations) - len(self.unrecovered)}, unrecovered: {len(self.unrecovered)}",
        ]
        if math.isfinite(self.min_separation):
            lines.append(
                f"  closest approach of two aircraft in the air: {self.min_separation:.1f} m"
            )
        return lines


def evaluate(
    recording: Path,
    world_name: str,
    region: Sequence[tuple[float, float]],
    bodies: Sequence[Body],
    drops: dict[str, tuple[str, tuple[float, float]]],
) -> Evaluation:
    """Score a flagship run.

    Args:
        recording: The run's MCAP.
        world_name: Its world (the ground truth it is scored against).
        region: The searched region's corners.
        bodies: The confirmed map points.
        drops: Box tag -> (body name, drop point) of leg II.
    """
    world = load_world(world_name)
    frame = frame_from_world(world_name)
    area = Polygon(region)
    ev = Evaluation()
    ev.people = [
        (o.id, o.east, o.north)
        for o in world.objects_of(ObjectKind.PERSON)
        if area.contains(Point(o.east, o.north))
    ]
    claimed: set[str] = set()
    for pid, e, n in ev.people:
        near = sorted((math.hypot(b.east - e, b.north - n), b.name, b) for b in bodies)
        if near and near[0][0] <= FOUND_WITHIN_M:
            ev.found[pid] = (near[0][2], near[0][0])
            claimed.add(near[0][1])
    ev.false_positives = [b for b in bodies if b.name not in claimed]
    _read(recording, frame, ev, drops)
    return ev


def _read(
    recording: Path,
    frame: Any,
    ev: Evaluation,
    drops: dict[str, tuple[str, tuple[float, float]]],
) -> None:
    reader = RecordingReader.open(recording)
    wanted = ("/helicopter_state", "/pfc/state", "/world_sim/objects")
    topics = {t: s for t, s in reader.topics().items() if t.endswith(wanted) or MissionLog.reads(t)}
    last_objects: Any = None
    log = MissionLog()
    mode_names = constant_names(PfcState, "MODE_")
    for m in reader.messages(list(topics)):
        if MissionLog.reads(m.topic):
            log.add(m)
            continue
        msg = deserialize_message(m.data, message_class(topics[m.topic]))
        agent = m.topic.split("/")[1]
        if m.topic == "/world_sim/objects":
            last_objects = msg
        elif m.topic.endswith("/helicopter_state"):
            position = frame.state_enu(msg)
            if position is not None:
                t = stamp_ms(msg.header.stamp) / 1e3
                ev.tracks.setdefault(agent, []).append((t, *position))
        else:
            name = mode_names.get(int(msg.mode), str(msg.mode))
            modes = ev.modes.setdefault(agent, [])
            if not modes or modes[-1][1] != name:
                modes.append((stamp_ms(msg.header.stamp) / 1e3, name))
    ev.nodes = log.nodes
    ev.violations = log.violations
    ev.recoveries = log.recoveries
    ev.unrecovered = log.unrecovered()
    objects = {o.id: o for o in last_objects.objects} if last_objects is not None else {}
    for box, (body, target) in sorted(drops.items()):
        o = objects.get(box)
        final = (o.east, o.north) if o is not None else None
        ev.deliveries.append(Delivery(box, body, target, final, o.held_by if o else ""))
    ev.min_separation = min_separation(ev.tracks)


def min_separation(tracks: dict[str, list[tuple[float, float, float, float]]]) -> float:
    """Closest approach of two airborne aircraft (> 2 m up), on 1 s bins of their tracks."""
    binned: dict[int, dict[str, tuple[float, float, float]]] = defaultdict(dict)
    for agent, track in tracks.items():
        for t, e, n, u in track:
            binned[int(t)][agent] = (e, n, u)
    best = math.inf
    for where in binned.values():
        points = list(where.values())
        for i, a in enumerate(points):
            for b in points[i + 1 :]:
                if min(a[2], b[2]) > 2.0:
                    best = min(best, math.dist(a, b))
    return best


def write_page(
    out: Path,
    recording: Path,
    ev: Evaluation,
    region: Sequence[tuple[float, float]],
    bodies: Sequence[Body],
    summary: Sequence[str],
) -> Path:
    """``out/index.html`` with ``map.png``, ``timeline.png`` and the recording's own figures."""
    out.mkdir(parents=True, exist_ok=True)
    _plot_map(out / "map.png", ev, region, bodies)
    ends = {agent: track[-1][0] for agent, track in ev.tracks.items() if track}
    plot_timeline(out / "timeline.png", ev.nodes, ev.modes, ends)
    general = write_report(read_mission(recording), out / "recording")
    esc = html.escape
    rows = "".join(
        f"<tr><td>{esc(d.box)}</td><td>{esc(d.body)}</td><td>{d.target[0]:.1f}, {d.target[1]:.1f}"
        f"</td><td>{'-' if d.final is None else f'{d.final[0]:.1f}, {d.final[1]:.1f}'}</td>"
        f"<td>{d.error:.1f}</td><td>{'yes' if d.delivered else 'NO'}</td></tr>"
        for d in ev.deliveries
    )
    violations = "".join(
        f"<li>{esc(v.agent)} {esc(v.monitor_id)} at {stamp_ms(v.header.stamp) / 1e3:.1f} s "
        f"(node {esc(v.node_id) or '-'}): {esc(v.formula)}</li>"
        for v in ev.violations
    )
    recoveries = "".join(
        f"<li>{esc(r.agent)} {esc(r.node_id)} step {r.step} at {stamp_ms(r.header.stamp) / 1e3:.1f}"
        f" s: {esc(r.reason)}</li>"
        for r in ev.recoveries
    )
    page = out / "index.html"
    page.write_text(
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
        "<title>hdrc3: emergency-services mission</title><style>body{font-family:sans-serif;"
        "margin:2em;max-width:1400px}img{max-width:100%}table{border-collapse:collapse}"
        "td,th{border:1px solid #ccc;padding:2px 8px}</style></head><body>"
        "<h1>Emergency-services mission (chapter 11.1)</h1><pre>"
        + esc("\n".join(summary))
        + "</pre><h2>Map</h2><img src='map.png' alt='map'>"
        "<h2>Timeline</h2><img src='timeline.png' alt='timeline'>"
        "<h2>Deliveries</h2><table><tr><th>box</th><th>body</th><th>drop point</th>"
        f"<th>final</th><th>error [m]</th><th>delivered</th></tr>{rows}</table>"
        f"<h2>Violations</h2><ul>{violations or '<li>none</li>'}</ul>"
        f"<h2>Recoveries</h2><ul>{recoveries or '<li>none</li>'}</ul>"
        f"<p>The recording's own report: <a href='{general.relative_to(out)}'>recording</a></p>"
        "</body></html>",
        encoding="utf-8",
    )
    return page


def _plot_map(
    path: Path, ev: Evaluation, region: Sequence[tuple[float, float]], bodies: Sequence[Body]
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(10, 10))
    xs, ys = zip(*(*region, region[0]), strict=True)
    ax.plot(xs, ys, "k--", label="region")
    for agent, track in ev.tracks.items():
        ax.plot([p[1] for p in track], [p[2] for p in track], lw=1, label=f"{agent} track")
    if ev.people:
        ax.plot([p[1] for p in ev.people], [p[2] for p in ev.people], "o", mfc="none", ms=12,
                color="tab:red", label="people (truth)")  # fmt: skip
    if bodies:
        ax.plot([b.east for b in bodies], [b.north for b in bodies], "x", ms=10, mew=2,
                color="tab:green", label="confirmed map points")  # fmt: skip
    for d in ev.deliveries:
        ax.plot(*d.target, "^", color="tab:purple", ms=9)
        if d.final is not None:
            ax.plot(*d.final, "s", color="tab:brown", ms=6)
            ax.annotate(d.box, d.final, fontsize=8)
    ax.plot([], [], "^", color="tab:purple", label="drop points")
    ax.plot([], [], "s", color="tab:brown", label="boxes at the end")
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True)
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
