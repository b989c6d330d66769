"""The DRC automaton file: valid, consistent with the PFC's and PPC's declarations."""

from __future__ import annotations

from pathlib import Path

from hdrc3_control import ppc_kernel
from hdrc3_control.automata import automaton_path
from hdrc3_control.kernel import MODE_CHANGED_ID
from hdrc3_hcsm.loader import LoadStatus, check_file, load_file
from hdrc3_hcsm.validation import validate_system
from hdrc3_platform_server.drc import DrcKernel, FlightState, PlatformState, model_path
from hdrc3_platform_server.platform_status import PlatformStatus


def ids(path: Path) -> dict[str, int]:
    result = check_file(path)
    assert result.model is not None
    return {e.name: e.event_id for e in result.model.events}


def test_drc_model_is_clean() -> None:
    result = check_file(model_path())
    assert result.status is LoadStatus.OK
    assert result.diagnostics == ()


def test_drc_and_ppc_form_a_valid_system() -> None:
    models = [load_file(model_path()), load_file(ppc_kernel.model_path())]
    assert validate_system(models) == ()


def test_drc_and_pfc_form_a_valid_system() -> None:
    """Every event the DRC sends the PFC is declared there with the same id, and back."""
    models = [load_file(model_path()), load_file(automaton_path())]
    assert validate_system(models) == ()


def test_mode_changed_id_is_the_drc_models() -> None:
    # the PFC kernel sends Mode-Changed-EV itself, outside its automata (kernel.py)
    assert ids(model_path())["Mode-Changed-EV"] == MODE_CHANGED_ID


def test_kernel_starts_idle_and_unknown() -> None:
    kernel = DrcKernel(PlatformStatus())
    kernel.step(0.0)
    assert kernel.flight() is FlightState.IDLE
    assert kernel.platform() is PlatformState.UNKNOWN
