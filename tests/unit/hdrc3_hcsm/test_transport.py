from __future__ import annotations

from dataclasses import replace
from typing import Any

import pytest

from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.transport import (
    ChannelIntegrity,
    ChannelStats,
    LoopbackNetwork,
    SendStatus,
    Verdict,
)

EV = WireEvent(42, "Go-EV", b"\x01\x02", "DRC", "PFC")


def test_seal_numbers_per_target_and_checks_crc() -> None:
    integrity = ChannelIntegrity(ChannelStats())
    a, b = integrity.seal(EV), integrity.seal(EV)
    c = integrity.seal(replace(EV, target="PPC"))
    assert (a.sequence, b.sequence, c.sequence) == (1, 2, 1)
    assert a.intact() and a.crc32 != 0


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("data", b"\x01\x03"),
        ("name", "Gone-EV"),
        ("event_id", 43),
        ("sequence", 9),
        ("source", "PPC"),
        ("target", "DRC"),
    ],
)
def test_any_changed_field_breaks_the_checksum(field: str, value: Any) -> None:
    sealed = EV.sealed(1)
    assert not replace(sealed, **{field: value}).intact()


def test_receiver_drops_corrupt_and_duplicates_and_counts_gaps() -> None:
    stats = ChannelStats()
    rx = ChannelIntegrity(stats)
    verdicts = [
        rx.accept(EV.sealed(1)),
        rx.accept(EV.sealed(1)),
        rx.accept(replace(EV.sealed(2), data=b"x")),
        rx.accept(EV.sealed(4)),
    ]
    assert verdicts == [Verdict.ACCEPTED, Verdict.DUPLICATE, Verdict.CORRUPT, Verdict.ACCEPTED]
    assert (stats.received, stats.duplicates, stats.corrupt, stats.lost) == (2, 1, 1, 2)


def test_loopback_delivers_in_order_and_reports_no_route() -> None:
    net = LoopbackNetwork()
    drc, pfc = net.endpoint("DRC"), net.endpoint("PFC")
    for i in range(3):
        assert drc.send(replace(EV, data=bytes([i]))) is SendStatus.SENT
    assert drc.send(replace(EV, target="PPC")) is SendStatus.NO_ROUTE
    got = pfc.receive()
    assert [e.data for e in got] == [b"\x00", b"\x01", b"\x02"]
    assert [e.sequence for e in got] == [1, 2, 3]
    assert pfc.receive() == []
    assert (drc.stats.sent, drc.stats.no_route, pfc.stats.received) == (3, 1, 3)
