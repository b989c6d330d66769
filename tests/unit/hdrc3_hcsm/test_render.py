from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from hdrc3_base.errors import ConfigError
from hdrc3_hcsm.loader import load_file
from hdrc3_hcsm.models import model_path
from hdrc3_hcsm.parser import parse_text
from hdrc3_hcsm.render import to_dot, write_drawing


def test_dot_has_regions_superstates_and_numbered_transitions() -> None:
    dot = to_dot(load_file(model_path("pfc_modes.hcsm")))
    assert dot.startswith("digraph hcsm {") and dot.rstrip().endswith("}")
    assert dot.count("{") == dot.count("}")
    assert 'label="A: Mode-Switch  (region 1)"; style=dashed;' in dot
    assert 'label="B: Control-Mode  (region 2)"; style=dashed;' in dot
    assert 'label="Traj3D-ST"; style=bold;' in dot
    assert (
        '"Mode-Switch/Traj3D-ST/Traj3D:Traj3D-Exit-ST" [label="Traj3D-Exit-ST", shape=doublecircle'
        in dot
    )
    assert 'label="A.7 exit / SEND PFC-Hover-EV, SEND Ctrl-Start-EV"' in dot
    assert "ltail=cluster_" in dot
    for tid in [f"B.{i}" for i in range(1, 14)] + [f"C.{i}" for i in range(1, 5)]:
        assert f'label="{tid} ' in dot
    assert "fillcolor" not in dot


def test_active_configuration_is_highlighted() -> None:
    active = ("Mode-Switch:Traj3D-ST", "Mode-Switch/Traj3D-ST/Traj3D:Traj3D-Check-ST")
    dot = to_dot(load_file(model_path("pfc_modes.hcsm")), active)
    assert dot.count("fillcolor=gold") == 2
    assert "bgcolor=" in dot
    line = next(x for x in dot.splitlines() if 'Traj3D:Traj3D-Check-ST" [label' in x)
    assert "fillcolor=gold" in line


def test_library_without_root_draws_every_automaton() -> None:
    text = (
        "model L on PFC; computers PFC; automaton A X { init S-ST; } automaton B Y { init T-ST; }"
    )
    model = parse_text(text, "lib.hcsm").model
    assert model is not None
    dot = to_dot(model)
    assert 'label="A: X"' in dot and 'label="B: Y"' in dot


def test_write_dot_and_svg_rules(tmp_path: Path) -> None:
    model = load_file(model_path("pfc_modes.hcsm"))
    write_drawing(model, tmp_path / "m.dot")
    assert (tmp_path / "m.dot").read_text().startswith("digraph")
    with pytest.raises(ConfigError, match="unsupported"):
        write_drawing(model, tmp_path / "m.png")
    if shutil.which("dot") is None:
        with pytest.raises(ConfigError, match="graphviz 'dot'"):
            write_drawing(model, tmp_path / "m.svg")
    else:
        write_drawing(model, tmp_path / "m.svg")
        assert "<svg" in (tmp_path / "m.svg").read_text()


def test_every_edge_joins_declared_nodes() -> None:
    import re

    dot = to_dot(load_file(model_path("pfc_modes.hcsm")))
    nodes = set(re.findall(r'^\s*("[^"]+") \[', dot, flags=re.M))
    edges = re.findall(r'^\s*("[^"]+") -> ("[^"]+")', dot, flags=re.M)
    assert len(edges) == 27 + 3  # transitions + one init arrow per automaton
    assert all(a in nodes and b in nodes for a, b in edges)
