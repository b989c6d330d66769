"""The mission report as files: one self-contained HTML page beside its PNG figures.

``index.html`` shows the summary per agent, a map of every track (with the saliency maps'
points) and altitude over time, one figure per agent (track, speed and altitude with the command
outcomes, PFC flight modes), a timeline of the TST nodes and flight modes over sim time, the
platform events, the TST nodes, the execution monitor's verdicts, the recoveries, the saliency
map points, the problems met while reading, and the recorded topics with their rates. The
page needs no server and no network: figures are files next to it, text is escaped. A short
script states how many figures the browser loaded (a broken image shows at once).
"""

from __future__ import annotations

import html
import math
from collections.abc import Iterable
from pathlib import Path

from hdrc3.flight_report import plot_report
from hdrc3.mission_log import MONITOR_KINDS, RECOVERY_STEPS, NodeSpan, plot_timeline
from hdrc3.mission_report import MissionData
from hdrc3_base.stamps import stamp_s

_QUIET_KINDS = ("SEGMENT_REQUEST",)
"""Event kinds counted but not listed one by one (a path asks for every segment)."""


def write_report(data: MissionData, out: Path) -> Path:
    """Write ``out/index.html`` and its figures; returns the page's path."""
    out.mkdir(parents=True, exist_ok=True)
    figures: list[tuple[str, str]] = []
    if data.flights:
        caption = "All agents: tracks and altitude"
        if data.detections:
            caption += "; saliency map points (x confirmed, dot not)"
        figures.append(("overview.png", caption))
        _plot_overview(data, out / "overview.png")
        for agent, flight in data.flights.items():
            if flight.track:
                name = f"flight_{agent}.png"
                plot_report(flight, out / name)
                figures.append((name, f"{agent}: track, speed and altitude, flight modes"))
    modes = {
        agent: [(f.start + t, mode) for t, mode in f.modes]
        for agent, f in data.flights.items()
        if f.modes and math.isfinite(f.start)
    }
    nodes = _spans_by_agent(data)
    if nodes or modes:
        ends = {a: f.start + f.duration for a, f in data.flights.items() if f.track}
        figures.append(("timeline.png", "TST nodes and flight modes over sim time"))
        plot_timeline(out / "timeline.png", nodes, modes, ends)
    page = out / "index.html"
    page.write_text(_page(data, figures), encoding="utf-8")
    return page


def _plot_overview(data: MissionData, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_map, ax_alt) = plt.subplots(1, 2, figsize=(14, 6), width_ratios=(1, 1.3))
    for flight in data.flights.values():
        if not flight.track:
            continue
        east = [p.east for p in flight.track]
        north = [p.north for p in flight.track]
        (line,) = ax_map.plot(east, north, label=flight.agent)
        ax_map.plot(east[0], north[0], "o", color=line.get_color())
        ax_map.plot(east[-1], north[-1], "s", color=line.get_color())
        ax_alt.plot(
            [p.time for p in flight.track], [p.up for p in flight.track], label=flight.agent
        )
    if data.origin is not None:
        for confirmed, style in ((True, "x"), (False, ".")):
            points = [d.enu(data.origin) for d in data.detections if d.confirmed is confirmed]
            if points:
                xs, ys = zip(*points, strict=True)
                label = "confirmed map points" if confirmed else "unconfirmed map points"
                colour = "tab:red" if confirmed else "grey"
                ax_map.plot(xs, ys, style, color=colour, ms=8, label=label)
    ax_map.set_xlabel("east [m]")
    ax_map.set_ylabel("north [m]")
    ax_map.set_aspect("equal", adjustable="datalim")
    ax_map.set_title("tracks (o start, square end)")
    ax_alt.set_xlabel("time since the agent's first sample [s]")
    ax_alt.set_ylabel("altitude, ENU up [m]")
    ax_alt.set_title("altitude")
    for ax in (ax_map, ax_alt):
        ax.grid(True)
        ax.legend(loc="best")
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)


def _table(header: tuple[str, ...], rows: Iterable[tuple[object, ...]]) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>" for row in rows
    )
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _page(data: MissionData, figures: list[tuple[str, str]]) -> str:
    esc = html.escape
    parts = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        f"<title>hdrc3 report: {esc(data.recording.name)}</title>",
        "<style>body{font-family:sans-serif;margin:2em;max-width:1400px}"
        "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:2px 8px;"
        "text-align:left;font-size:90%}img{max-width:100%;border:1px solid #eee}"
        ".problem{color:#a00}</style></head><body>",
        f"<h1>Mission report: {esc(data.recording.name)}</h1>",
        f"<p>{data.messages} messages on {len(data.topics)} topics over {data.duration:.1f} s "
        f"of log time; {len(data.flights)} agent(s).",
    ]
    if data.origin is not None:
        lat, lon, alt = data.origin
        parts.append(f" Local frame origin: {lat:.6f}, {lon:.6f}, {alt:.1f} m.")
    parts.append("</p><p id='figures'>figures: not checked (scripts off)</p>")
    if data.problems:
        parts.append("<h2>Problems</h2><ul>")
        parts += [f"<li class='problem'>{esc(p)}</li>" for p in data.problems]
        parts.append("</ul>")
    if data.flights:
        parts.append("<h2>Flights</h2>")
        parts.append(
            _table(
                ("agent", "samples", "duration [s]", "distance [m]", "max speed [m/s]", "modes"),
                (
                    (
                        f.agent,
                        len(f.track),
                        f"{f.duration:.1f}",
                        f"{f.distance:.1f}",
                        f"{f.max_speed:.1f}",
                        " -> ".join(m for _, m in f.modes),
                    )
                    for f in data.flights.values()
                ),
            )
        )
    for name, caption in figures:
        parts.append(f"<figure><img src='{esc(name)}' alt='{esc(caption)}'>")
        parts.append(f"<figcaption>{esc(caption)}</figcaption></figure>")
    events = [
        (f"{e.time:.1f}", f.agent, e.command, e.kind, e.reason)
        for f in data.flights.values()
        for e in f.events
        if e.kind not in _QUIET_KINDS
    ]
    if events:
        quiet = sum(1 for f in data.flights.values() for e in f.events if e.kind in _QUIET_KINDS)
        parts.append("<h2>Platform events</h2>")
        parts.append(f"<p>plus {quiet} segment requests (not listed)</p>")
        parts.append(_table(("time [s]", "agent", "command", "kind", "reason"), events))
    parts += _upper_layers(data)
    parts.append("<h2>Topics</h2>")
    parts.append(
        _table(
            ("topic", "type", "messages", "rate [Hz]"),
            (
                (topic, s.type_name, s.count, f"{s.rate:.1f}")
                for topic, s in sorted(data.topics.items())
            ),
        )
    )
    parts.append(
        "<script>window.addEventListener('load',function(){var i=document.images,n=0;"
        "for(var k=0;k<i.length;k++){if(i[k].complete&&i[k].naturalWidth>0){n++;}}"
        "document.getElementById('figures').textContent="
        "'figures: '+n+' of '+i.length+' loaded';});</script>"
    )
    parts.append("</body></html>\n")
    return "".join(parts)


def _spans_by_agent(data: MissionData) -> dict[str, list[NodeSpan]]:
    """Every agent's ended and still running nodes."""
    out = {agent: list(spans) for agent, spans in data.log.nodes.items()}
    for span in data.log.unfinished():
        out.setdefault(span.agent, []).append(span)
    return out


def _upper_layers(data: MissionData) -> list[str]:
    """Tables of the TST nodes, monitor verdicts, recoveries and saliency map points."""
    log, parts = data.log, []
    spans = sorted(
        (n for nodes in _spans_by_agent(data).values() for n in nodes), key=lambda n: n.start
    )
    if spans:
        parts.append("<h2>TST nodes</h2>")
        parts.append(
            _table(
                ("agent", "mission", "node", "action", "start [s]", "end [s]", "state", "reason"),
                (
                    (
                        n.agent,
                        n.mission,
                        n.node_id,
                        n.action,
                        f"{n.start:.1f}",
                        "-" if math.isnan(n.end) else f"{n.end:.1f}",
                        n.state,
                        n.reason,
                    )
                    for n in spans
                ),
            )
        )
    if log.monitor:
        parts.append("<h2>Execution monitor</h2>")
        parts.append(
            _table(
                ("time [s]", "agent", "verdict", "formula", "node", "recovery", "reason"),
                (
                    (
                        f"{stamp_s(v.header.stamp):.1f}",
                        v.agent,
                        MONITOR_KINDS.get(v.kind, v.kind),
                        v.monitor_id,
                        v.node_id or "-",
                        v.recovery or "-",
                        v.reason or v.formula,
                    )
                    for v in log.monitor
                ),
            )
        )
        unrecovered = log.unrecovered()
        parts.append(f"<p>{len(unrecovered)} violation(s) not followed by a new plan.</p>")
    if log.recoveries:
        parts.append("<h2>Recoveries</h2>")
        parts.append(
            _table(
                ("time [s]", "agent", "node", "formula", "step", "attempt", "reason", "plan"),
                (
                    (
                        f"{stamp_s(r.header.stamp):.1f}",
                        r.agent,
                        r.node_id,
                        r.monitor_id,
                        RECOVERY_STEPS.get(r.step, r.step),
                        r.attempt,
                        r.reason,
                        "; ".join(r.plan),
                    )
                    for r in log.recoveries
                ),
            )
        )
    if data.detections and data.origin is not None:
        origin = data.origin
        parts.append("<h2>Saliency map points</h2>")
        parts.append(
            _table(
                (
                    "agent",
                    "east [m]",
                    "north [m]",
                    "certainty",
                    "frames",
                    "confirmed",
                    "first seen [s]",
                ),
                (
                    (
                        d.agent,
                        *(f"{v:.1f}" for v in d.enu(origin)),
                        f"{d.certainty:.2f}",
                        d.frames,
                        "yes" if d.confirmed else "no",
                        f"{d.first_seen:.1f}",
                    )
                    for d in data.detections
                ),
            )
        )
    return parts
