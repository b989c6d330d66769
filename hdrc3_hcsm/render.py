"""Drawing: a model as graphviz dot text (SVG through the ``dot`` program when installed).

The drawing follows the instance tree from ``root``: each automaton is a cluster labelled with its
letter, each superstate a bold cluster whose ordered regions are dashed clusters, transitions carry
their numbers (``A.1 Ev-EV [guard] / actions``). Given an active configuration (from a trace),
active states are filled. A model without root (a library) draws every automaton at top level.
"""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Iterable
from pathlib import Path

from hdrc3_base.errors import ConfigError
from hdrc3_hcsm.model import Automaton, Model, StateKind

ACTIVE_FILL = "gold"


def _q(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


class _Writer:
    def __init__(self, model: Model, active: frozenset[str]) -> None:
        self.model = model
        self.active = active
        self.lines: list[str] = []
        self.clusters = 0

    def emit(self, depth: int, text: str) -> None:
        self.lines.append("  " * depth + text)

    def cluster(self) -> str:
        self.clusters += 1
        return f"cluster_{self.clusters}"

    def container(self, names: tuple[str, ...], prefix: str, depth: int) -> None:
        regions = self.model.regions_of(names)
        for i, name in enumerate(regions):
            suffix = f"[{i + 1}]" if regions.count(name) > 1 else ""
            automaton = self.model.automaton(name)
            if automaton is None:
                continue
            path = f"{prefix}{name}{suffix}"
            self.emit(depth, f"subgraph {self.cluster()} {{")
            style = "dashed" if len(regions) > 1 else "solid"
            title = f"{automaton.label}: {name}" + (
                f"  (region {i + 1})" if len(regions) > 1 else ""
            )
            self.emit(depth + 1, f"label={_q(title)}; style={style};")
            self.automaton(automaton, path, depth + 1)
            self.emit(depth, "}")

    def node_id(self, path: str, state: str) -> str:
        return _q(f"{path}:{state}")

    def automaton(self, a: Automaton, path: str, depth: int) -> None:
        anchors: dict[str, tuple[str, str | None]] = {}
        for s in a.states:
            nid = self.node_id(path, s.name)
            on = f"{path}:{s.name}" in self.active
            fill = f', style="rounded,filled", fillcolor={ACTIVE_FILL}' if on else ""
            if s.kind is StateKind.SUPER:
                cid = self.cluster()
                anchors[s.name] = (nid, cid)
                self.emit(depth, f"subgraph {cid} {{")
                bg = f" bgcolor={_q('lightyellow')};" if on else ""
                self.emit(depth + 1, f"label={_q(s.name)}; style=bold;{bg}")
                self.emit(depth + 1, f"{nid} [shape=point, width=0.05{fill}];")
                self.container(s.regions, f"{path}/{s.name}/", depth + 1)
                self.emit(depth, "}")
                continue
            anchors[s.name] = (nid, None)
            shape = "doublecircle" if s.kind is StateKind.EXIT else "box"
            style = "" if on else ', style="rounded"'
            self.emit(depth, f"{nid} [label={_q(s.name)}, shape={shape}{style}{fill}];")
            if s.kind is StateKind.INIT:
                start = _q(f"{path}:__init__")
                self.emit(depth, f"{start} [shape=point, width=0.12];")
                self.emit(depth, f"{start} -> {nid};")
        for t in a.transitions:
            if t.source not in anchors or t.target not in anchors:
                continue
            src, src_cluster = anchors[t.source]
            dst, dst_cluster = anchors[t.target]
            attrs = [f"label={_q(t.label())}", "fontsize=9"]
            if src_cluster is not None:
                attrs.append(f"ltail={src_cluster}")
            if dst_cluster is not None and dst_cluster != src_cluster:
                attrs.append(f"lhead={dst_cluster}")
            self.emit(depth, f"{src} -> {dst} [{', '.join(attrs)}];")


def to_dot(model: Model, active: Iterable[str] = ()) -> str:
    """Graphviz dot text for ``model``; ``active`` holds ``path:state`` entries to highlight."""
    writer = _Writer(model, frozenset(active))
    title = f"{model.name or model.file} on {model.computer or '?'}"
    writer.emit(0, "digraph hcsm {")
    writer.emit(1, f"label={_q(title)}; labelloc=t; compound=true; rankdir=LR;")
    writer.emit(1, 'node [fontname="Helvetica", fontsize=10]; edge [fontname="Helvetica"];')
    roots = model.root or tuple(a.name for a in model.automata)
    if model.root:
        writer.container(roots, "", 1)
    else:
        for name in roots:
            writer.container((name,), "", 1)
    writer.emit(0, "}")
    return "\n".join(writer.lines) + "\n"


def write_drawing(model: Model, out: Path, active: Iterable[str] = ()) -> None:
    """Write ``.dot`` text, or ``.svg`` through graphviz ``dot`` (ConfigError if unavailable)."""
    dot_text = to_dot(model, active)
    suffix = out.suffix.lower()
    if suffix in (".dot", ".gv"):
        out.write_text(dot_text, encoding="utf-8")
        return
    if suffix != ".svg":
        raise ConfigError(f"unsupported drawing format {out.suffix!r}: use .dot, .gv or .svg")
    program = shutil.which("dot")
    if program is None:
        raise ConfigError("SVG output needs the graphviz 'dot' program on PATH; write .dot instead")
    done = subprocess.run(
        [program, "-Tsvg", "-o", str(out)], input=dot_text, text=True, capture_output=True
    )
    if done.returncode != 0:
        raise ConfigError(f"dot failed: {done.stderr.strip()}")
