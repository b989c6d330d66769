from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_control.automata import automaton_path
from hdrc3_control.event_protocol import REASONS
from hdrc3_hcsm.loader import LoadStatus, check_file, load_file
from hdrc3_hcsm.tables import compile_model

FILES = sorted(p.name for p in automaton_path().parent.glob("*.hcsm"))


@pytest.mark.parametrize("name", FILES)
def test_every_automaton_file_checks_clean(name: str) -> None:
    result = check_file(automaton_path(name))
    assert result.status is LoadStatus.OK, [str(d) for d in result.diagnostics]
    # libraries (every file but pfc.hcsm) only get "no root: checked as a library"
    others = [str(d) for d in result.diagnostics if d.code != "W003"]
    assert not others


def test_pfc_model_has_the_automata_of_figure_12() -> None:
    model = compile_model(load_file(automaton_path()))
    expected = {
        "Root", "Run", "Power-Switch", "Sync", "Sync-Drc", "Auto-Switch", "Mode-Switch",
        "Control-Mode", "User-Interface", "Ui-Timer", "Traj3D", "Traj3D-Flyto", "Landing", "Track",
    }  # fmt: skip
    assert expected <= set(model.automata)


def test_reason_table_names_existing_transitions() -> None:
    text = "".join(Path(automaton_path(n)).read_text() for n in FILES)
    missing = [tid for tid in REASONS if f"{tid}:" not in text]
    assert not missing
