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
        ("incarnation", 7),
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


# (incarnation, sequence) received in order -> verdict, whether it announces a restart
INCARNATION_CASES = {
    "first contact is not a restart": ([(1, 1)], [Verdict.ACCEPTED], [], 0),
    "a restarted sender counts from 1 again": (
        [(1, 1), (1, 2), (1, 3), (2, 1), (2, 2)],
        [Verdict.ACCEPTED] * 5,
        ["DRC"],
        0,
    ),
    "a late event of the old run is stale": (
        [(1, 5), (2, 1), (1, 6), (2, 2)],
        [Verdict.ACCEPTED, Verdict.ACCEPTED, Verdict.STALE, Verdict.ACCEPTED],
        ["DRC"],
        4,
    ),
    "duplicates within the new run are dropped": (
        [(1, 9), (2, 1), (2, 1)],
        [Verdict.ACCEPTED, Verdict.ACCEPTED, Verdict.DUPLICATE],
        ["DRC"],
        8,
    ),
    "a new run's gap counts as lost in that run": (
        [(1, 1), (2, 3)],
        [Verdict.ACCEPTED, Verdict.ACCEPTED],
        ["DRC"],
        2,
    ),
    "two restarts are two notices": (
        [(1, 1), (2, 1), (3, 1)],
        [Verdict.ACCEPTED] * 3,
        ["DRC", "DRC"],
        0,
    ),
    "joining a running sender counts what it missed as lost": (
        [(4, 10), (4, 11)],
        [Verdict.ACCEPTED, Verdict.ACCEPTED],
        [],
        9,
    ),
}


@pytest.mark.parametrize(
    ("received", "verdicts", "restarts", "lost"),
    INCARNATION_CASES.values(),
    ids=INCARNATION_CASES.keys(),
)
def test_incarnation_resets_the_receive_window(
    received: list[tuple[int, int]], verdicts: list[Verdict], restarts: list[str], lost: int
) -> None:
    stats = ChannelStats()
    rx = ChannelIntegrity(stats)
    got = [rx.accept(EV.sealed(seq, incarnation)) for incarnation, seq in received]
    assert got == verdicts
    assert rx.restarts() == restarts
    assert rx.restarts() == []  # read once
    assert stats.restarts == len(restarts)
    assert stats.lost == lost
    assert stats.stale == verdicts.count(Verdict.STALE)


def test_windows_are_per_sender() -> None:
    rx = ChannelIntegrity(ChannelStats())
    assert rx.accept(EV.sealed(3, 1)) is Verdict.ACCEPTED
    assert rx.accept(replace(EV, source="PPC").sealed(1, 9)) is Verdict.ACCEPTED
    assert rx.accept(replace(EV, source="PPC").sealed(1, 8)) is Verdict.ACCEPTED
    assert rx.accept(EV.sealed(4, 1)) is Verdict.ACCEPTED
    assert rx.restarts() == ["PPC"]


def test_every_endpoint_draws_its_own_incarnation() -> None:
    a, b = ChannelIntegrity(ChannelStats()), ChannelIntegrity(ChannelStats())
    assert a.incarnation != b.incarnation and a.incarnation != 0
    assert a.seal(EV).incarnation == a.incarnation


def test_a_replaced_loopback_endpoint_is_heard_as_a_restart() -> None:
    net = LoopbackNetwork()
    drc, pfc = net.endpoint("DRC"), net.endpoint("PFC")
    for _ in range(3):
        drc.send(EV)
    assert len(pfc.receive()) == 3 and pfc.restarts() == []
    drc = net.endpoint("DRC")  # the DRC restarts: its numbering starts at 1 again
    drc.send(replace(EV, data=b"new"))
    got = pfc.receive()
    assert [(e.data, e.sequence) for e in got] == [(b"new", 1)]
    assert pfc.restarts() == ["DRC"]
