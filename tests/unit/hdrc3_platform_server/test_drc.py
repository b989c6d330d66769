"""The DRC automaton file: valid, consistent with the PFC's and PPC's declarations."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_control import ppc_kernel
from hdrc3_hcsm.loader import LoadStatus, check_file, load_file
from hdrc3_hcsm.validation import validate_system
from hdrc3_platform_server.drc import DrcKernel, FlightState, PlatformState, model_path
from hdrc3_platform_server.fakes import ARITY, PFC_IDS, PPC_IDS
from hdrc3_platform_server.platform_status import PlatformStatus

PFC_EVENTS = Path(__file__).parents[3] / "hdrc3_control" / "automata" / "pfc_events.hcsm"


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


@pytest.mark.skipif(not PFC_EVENTS.exists(), reason="control kernel declarations not present")
def test_event_ids_agree_with_the_pfc() -> None:
    drc, pfc = ids(model_path()), ids(PFC_EVENTS)
    shared = set(drc) & set(pfc)
    assert set(ARITY) | set(PFC_IDS) <= shared | {"Mode-Changed-EV"}
    assert {name: drc[name] for name in shared} == {name: pfc[name] for name in shared}


def test_fake_ids_are_the_models() -> None:
    drc = ids(model_path())
    for name, event_id in {**PFC_IDS, **PPC_IDS}.items():
        assert drc[name] == event_id


def test_kernel_starts_idle_and_unknown() -> None:
    kernel = DrcKernel(PlatformStatus())
    kernel.step(0.0)
    assert kernel.flight() is FlightState.IDLE
    assert kernel.platform() is PlatformState.UNKNOWN
