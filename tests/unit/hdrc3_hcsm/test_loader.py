from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_hcsm.loader import LoadStatus, check_file, load_file
from hdrc3_hcsm.models import model_path

DECLS = "computers PFC;\nevent Go-EV = 1;\n"
LEAF = 'include "decls.hcsm";\nautomaton B Leaf { init L-ST; B.1: L-ST -> L-ST on Go-EV; }\n'
TOP = (
    'model T on PFC;\ninclude "decls.hcsm";\ninclude "leaf.hcsm";\n'
    "automaton A Top { init S-ST; A.1: S-ST -> S-ST on pulse / SEND Go-EV; }\n"
    "root Top | Leaf;\n"
)


def write(tmp: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        (tmp / name).write_text(text)
    return tmp / "top.hcsm"


def test_diamond_includes_are_merged_once(tmp_path: Path) -> None:
    top = write(tmp_path, {"decls.hcsm": DECLS, "leaf.hcsm": LEAF, "top.hcsm": TOP})
    model = load_file(top)
    assert [e.name for e in model.events] == ["Go-EV"]
    assert [a.name for a in model.automata] == ["Leaf", "Top"]
    assert model.automata[0].pos.file.endswith("leaf.hcsm")


@pytest.mark.parametrize(
    ("files", "code", "where"),
    [
        ({"leaf.hcsm": LEAF}, "E005", "top.hcsm:2:9"),  # decls.hcsm missing, reported at include
        (
            {"decls.hcsm": DECLS + 'include "top.hcsm";\n', "leaf.hcsm": LEAF},
            "E003",
            "decls.hcsm:3:9",
        ),
        ({"decls.hcsm": "model X on PFC;\n" + DECLS, "leaf.hcsm": LEAF}, "E004", "decls.hcsm:1:1"),
        ({"decls.hcsm": DECLS + "event ;\n", "leaf.hcsm": LEAF}, "E001", "decls.hcsm:3:7"),
    ],
)
def test_include_errors_point_into_the_right_file(
    tmp_path: Path, files: dict[str, str], code: str, where: str
) -> None:
    top = write(tmp_path, {**files, "top.hcsm": TOP})
    result = check_file(top)
    assert result.status is LoadStatus.INVALID
    hits = [d for d in result.diagnostics if d.code == code]
    assert hits, [str(d) for d in result.diagnostics]
    assert str(hits[0]).startswith(str(tmp_path / where))


@pytest.mark.parametrize(
    "name", ["pfc_declarations.hcsm", "control_mode.hcsm", "traj3d.hcsm", "mode_switch.hcsm"]
)
def test_shipped_libraries_check_on_their_own(name: str) -> None:
    result = check_file(model_path(name))
    assert result.status is LoadStatus.OK
    assert [d.code for d in result.diagnostics] == ["W003"]


@pytest.mark.parametrize("path", ["", "nul\x00byte", "missing.hcsm", "."])
def test_unreadable_includes_are_diagnostics(tmp_path: Path, path: str) -> None:
    text = f'include "{path}";'
    result = check_file(write(tmp_path, {"top.hcsm": text}))
    assert result.status is LoadStatus.INVALID
    assert [d.code for d in result.diagnostics] == ["E005"]
