"""The command registry: complete, and consistent with the automata and the service types."""

from __future__ import annotations

import pytest

from hdrc3_control import ppc_kernel
from hdrc3_control.kernel import load_model as load_pfc_model
from hdrc3_hcsm.loader import load_file
from hdrc3_platform_server.codes import FclCommand, PpclCommand
from hdrc3_platform_server.commands import FCL, PPCL, FclSpec, PpclSpec, wire_arity
from hdrc3_platform_server.drc import load_model

SPECS: list[FclSpec | PpclSpec] = [*FCL.values(), *PPCL.values()]


def test_every_command_has_one_spec() -> None:
    assert list(FCL) == list(FclCommand) and all(c is s.command for c, s in FCL.items())
    assert list(PPCL) == list(PpclCommand) and all(c is s.command for c, s in PPCL.items())


def test_wire_events_are_the_kernels_command_events() -> None:
    pfc = {e.name for e in load_pfc_model().source.events if e.source == "DRC"}
    ppc = {e.name for e in load_file(ppc_kernel.model_path()).events if e.source == "DRC"}
    assert {s.wire_event for s in FCL.values()} == pfc
    assert {s.wire_event for s in PPCL.values()} == ppc
    assert len(wire_arity()) == len(SPECS)


@pytest.mark.parametrize("spec", SPECS, ids=lambda s: s.command.value)
def test_spec_matches_its_service_and_the_drc_model(spec: FclSpec | PpclSpec) -> None:
    events = load_model().events
    assert spec.api_event in events.index and spec.wire_event in events.index
    request = spec.service_type().Request()
    assert spec.values(request) == (0.0,) * len(spec.arguments)  # every field exists
    assert len(set(spec.names)) == len(spec.names)
    assert spec.wire_arity <= len(spec.arguments)


def test_commands_that_return_only_fcl_ok() -> None:
    assert {c for c, s in FCL.items() if s.returns_ok} == {
        FclCommand.CANCEL,
        FclCommand.EMERGENCY_BRAKE,
    }
