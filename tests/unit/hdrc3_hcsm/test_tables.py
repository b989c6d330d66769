from __future__ import annotations

import pytest

from hdrc3_hcsm.errors import ModelError
from hdrc3_hcsm.loader import load_file
from hdrc3_hcsm.models import model_path
from hdrc3_hcsm.parser import parse_text
from hdrc3_hcsm.tables import EXIT_INDEX, PULSE_INDEX, OpCode, compile_model


def test_compiled_tables_are_dict_lookups_by_state_and_event() -> None:
    compiled = compile_model(load_file(model_path("pfc_modes.hcsm")))
    events = compiled.events
    assert events.names[:2] == ("pulse", "exit") and (PULSE_INDEX, EXIT_INDEX) == (0, 1)
    assert events.by_id[1022] == events.index["Traj3D-EV"]
    assert events.id_of("Traj3D-EV") == 1022
    ms = compiled.automata["Mode-Switch"]
    hovering = ms.states.index("Hovering-ST")
    [a6] = ms.table[hovering][events.index["Traj3D-EV"]]
    assert a6.tid == "A.6" and ms.states[a6.target] == "Traj3D-ST"
    assert [a.op for a in a6.actions] == [OpCode.PUT, OpCode.SEND]
    assert a6.actions[1].remote is None  # local SEND
    # Interest of Mode Switch includes the events its nested Traj3D reacts to.
    assert events.index["Ctrl-Stopped-EV"] in ms.interest
    assert ms.regions[ms.states.index("Traj3D-ST")] == ("Traj3D",)
    cm = compiled.automata["Control-Mode"]
    assert events.index["Traj3D-EV"] not in cm.interest


def test_library_cannot_be_compiled() -> None:
    model = parse_text("model L on PFC; computers PFC; automaton A X { init S; }").model
    assert model is not None
    with pytest.raises(ModelError, match="runnable"):
        compile_model(model)
