"""The conditions the DRC automaton reads from the PFC/PPC data."""

from __future__ import annotations

import pytest

from hdrc3_control.pfc_state import FlightMode
from hdrc3_platform_server.platform_status import (
    CameraSample,
    PfcSample,
    PlatformStatus,
)


def pfc(received: float, **changes: object) -> PfcSample:
    base: dict[str, object] = dict(
        pfc_time=received,
        received=received,
        position_enu=(0.0, 0.0, 10.0),
        velocity_enu=(0.2, 0.1, 0.0),
        latitude=0.0,
        longitude=0.0,
        altitude=0.0,
        roll=0.0,
        pitch=0.0,
        heading=0.0,
        rpm=1400.0,
        on_ground=False,
        auto_flag=True,
        mode=FlightMode.HOVER,
    )
    base.update(changes)
    return PfcSample(**base)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("changes", "stable"),
    [
        ({}, True),
        ({"velocity_enu": (1.5, 0.0, 0.0)}, False),
        ({"velocity_enu": (0.0, 0.0, -1.2)}, False),
        ({"mode": FlightMode.FLYTO}, False),
        ({"auto_flag": False}, False),
        ({"on_ground": True}, False),
    ],
)
def test_hover_stable(changes: dict[str, object], stable: bool) -> None:
    assert pfc(1.0, **changes).hover_stable is stable


def test_freshness_and_ground_conditions() -> None:
    status = PlatformStatus(stale_after=2.0)
    assert not (status.pfc_fresh() or status.on_ground() or status.airborne())
    status.update_pfc(pfc(10.0, on_ground=True))
    status.now = 11.0
    assert status.on_ground() and not status.airborne() and status.auto()
    status.now = 12.5
    assert not status.pfc_fresh() and not status.on_ground()


def test_ppc_freshness() -> None:
    status = PlatformStatus(stale_after=2.0)
    status.update_camera(CameraSample(0, 0.0, 0.0, 0.0, 5.0, 5.0))
    status.now = 6.0
    assert status.ppc_fresh()
    status.now = 8.0
    assert not status.ppc_fresh()
