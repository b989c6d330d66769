"""PFCM: segment offers, Request-Segment, virtual leader, and safety braking in the sim."""

from __future__ import annotations

from dataclasses import dataclass
from types import ModuleType

import numpy as np
import pytest

from hdrc3_control.commands import EstimatedState
from hdrc3_control.path_following import OfferStatus, PathEvent, PathFollower, PathStatus
from hdrc3_control.path_segment import PathSegment

AB = PathSegment.straight((0.0, 0.0, 20.0), (100.0, 0.0, 20.0), 8.0, 3.0, 0)
BC = PathSegment((100.0, 0.0, 20.0), (130.0, 30.0, 20.0), (1, 0, 0), (0, 1, 0), 3.0, 0.0, 1)
FAR = PathSegment.straight((150.0, 0.0, 20.0), (200.0, 0.0, 20.0), 8.0, 0.0, 2)
SINGLE = PathSegment.straight((0.0, 0.0, 20.0), (50.0, 0.0, 20.0), 5.0, 0.0, 3)
# replacement (issue 13): AB_FAST with BD queued; TIGHT (entry 4 m/s) may replace BD
AB_FAST = PathSegment.straight((0.0, 0.0, 20.0), (100.0, 0.0, 20.0), 8.0, 8.0, 10)
BD = PathSegment.straight((100.0, 0.0, 20.0), (200.0, 0.0, 20.0), 8.0, 0.0, 11)
TIGHT = PathSegment((100.0, 0.0, 20.0), (110.0, 10.0, 20.0), (1, 0, 0), (0, 1, 0), 5.0, 0.0, 12)
BE = PathSegment.straight((100.0, 0.0, 20.0), (150.0, 0.0, 20.0), 8.0, 8.0, 13)
EF = PathSegment.straight((150.0, 0.0, 20.0), (200.0, 0.0, 20.0), 8.0, 0.0, 14)


def _at(x: float, y: float = 0.0, v: float = 0.0) -> EstimatedState:
    return EstimatedState(0.0, (x, y, 20.0), (v, 0.0, 0.0), 0.0, 0.0, np.pi / 2)


def test_request_segment_as_soon_as_a_segment_is_accepted() -> None:
    pf = PathFollower()
    pf.start(_at(0.0), AB)
    out = pf.update(_at(0.0), 10.0)
    assert out.events == (PathEvent.REQUEST_SEGMENT,)
    assert out.status is PathStatus.FOLLOWING
    assert 10.0 < out.timeout < 10.0 + 100.0 / 3.0
    assert pf.update(_at(0.0), 10.02).events == ()


def test_single_segment_requests_nothing() -> None:
    pf = PathFollower()
    pf.start(_at(0.0), SINGLE)
    out = pf.update(_at(0.0), 0.0)
    assert out.events == () and out.timeout == float("inf")


@pytest.mark.parametrize(
    ("first", "offers", "expected"),
    [
        (AB, [BC], [OfferStatus.ACCEPTED]),
        (AB, [BC, BC], [OfferStatus.ACCEPTED, OfferStatus.REPLACED]),
        (AB, [BC, FAR], [OfferStatus.ACCEPTED, OfferStatus.DISCONTINUOUS]),
        (AB, [FAR], [OfferStatus.DISCONTINUOUS]),
        (SINGLE, [BC], [OfferStatus.NOT_EXPECTED]),
    ],
)
def test_offer_statuses(
    first: PathSegment, offers: list[PathSegment], expected: list[OfferStatus]
) -> None:
    pf = PathFollower()
    pf.start(_at(0.0), first)
    pf.update(_at(0.0), 0.0)
    assert [pf.offer(s) for s in offers] == expected


def test_virtual_leader_tracks_the_closest_point_and_switches_segments() -> None:
    pf = PathFollower()
    pf.start(_at(0.0), AB)
    pf.update(_at(0.0), 0.0)
    assert pf.offer(BC) is OfferStatus.ACCEPTED
    events: list[PathEvent] = []
    x, t = 0.0, 0.0
    for _ in range(700):  # a kinematic vehicle 1 m beside the path at 8 m/s
        t += 0.02
        x += 0.16
        out = pf.update(_at(x, 1.0, 8.0), t)
        events += out.events
        if out.segment_id == 0:
            assert out.control_point[0] == pytest.approx(min(x, 100.0), abs=0.3)
            assert out.cross_track == pytest.approx(1.0, abs=0.3)
    assert PathEvent.SEGMENT_SWITCHED in events
    assert pf.current is BC and pf.pending is None


def test_safety_braking_when_the_next_segment_is_late() -> None:
    pf = PathFollower()
    pf.start(_at(60.0, 0.0, 8.0), AB)
    out = pf.update(_at(60.0, 0.0, 8.0), 0.0)
    assert out.status is PathStatus.FOLLOWING
    first_timeout = out.timeout
    t, x = 0.0, 60.0
    while out.status is PathStatus.FOLLOWING:
        t += 0.02
        x += 0.16
        out = pf.update(_at(x, 0.0, 8.0), t)
    assert out.status is PathStatus.SAFETY_BRAKING
    assert t == pytest.approx(first_timeout, abs=0.1)
    for _ in range(100):  # the vehicle keeps 8 m/s: the reference brakes from here on
        t += 0.02
        x += 0.16
        out = pf.update(_at(x, 0.0, 8.0), t)
    assert out.speed_ref < 7.0
    assert pf.offer(BC) is OfferStatus.TOO_LATE


@pytest.mark.parametrize("seed", [7, 8])
def test_withheld_segment_stops_before_the_end_and_hovers(harness: ModuleType, seed: int) -> None:
    f = harness.SimFlight(seed=seed, placement=harness.FIGURE7_START)
    f.start_engine()
    up = harness.takeoff(f, 12.0)
    path = harness.figure7_path(f.state().position)
    run = harness.fly_path(f, path, up.integral, withhold_from=1)
    last = run.outputs[-1]
    assert last.status is PathStatus.STOPPED
    assert [e for o in run.outputs for e in o.events] == [
        PathEvent.REQUEST_SEGMENT,
        PathEvent.SAFETY_BRAKING,
        PathEvent.STOPPED,
    ]
    end = np.array(path[0].end)
    est_x = np.array([s.position[0] for s in f.log.estimate[run.first_tick :]])
    assert est_x.max() <= end[0] + 0.5  # never past the end of the current segment
    hold = harness.hover(
        f, harness.HoverSetpoint(last.hover_point, f.state().heading), 8.0, run.integral
    )
    assert hold.outputs[-1].status.name == "STABLE"


def _fly_along_x(pf: PathFollower, x_to: float, speed: float = 8.0) -> list[PathEvent]:
    """A kinematic vehicle on y = 0 at ``speed`` from x = 0 to ``x_to``; the events raised."""
    events: list[PathEvent] = []
    x, t = 0.0, 0.0
    while x < x_to:
        out = pf.update(_at(x, 0.0, speed), t)
        events += out.events
        t += 0.02
        x += speed * 0.02
    return events


@dataclass(frozen=True)
class Replacement:
    """Offer ``offer`` with ``queued`` pending (None: nothing) once the vehicle reaches ``at``."""

    first: PathSegment
    queued: PathSegment | None
    at: float
    offer: PathSegment
    status: OfferStatus
    current: PathSegment
    """Segment in flight after the offer."""
    pending: PathSegment | None
    """Pending segment after the offer."""


REPLACEMENTS = {
    "before the switch: replaced": Replacement(
        AB_FAST, BD, 20.0, TIGHT, OfferStatus.REPLACED, AB_FAST, TIGHT
    ),
    "after the switch: the next segment": Replacement(
        AB, BE, 110.0, EF, OfferStatus.ACCEPTED, BE, EF
    ),
    "discontinuous replacement: refused": Replacement(
        AB_FAST, BD, 20.0, FAR, OfferStatus.DISCONTINUOUS, AB_FAST, BD
    ),
    "too close to brake to the new entry speed": Replacement(
        AB_FAST, BD, 95.0, TIGHT, OfferStatus.TOO_LATE_TO_REPLACE, AB_FAST, BD
    ),
    "during safety braking: too late": Replacement(
        AB, None, 90.0, BC, OfferStatus.TOO_LATE, AB, None
    ),
}


@pytest.mark.parametrize("case", REPLACEMENTS.values(), ids=REPLACEMENTS.keys())
def test_a_queued_segment_is_replaced_until_the_switch(case: Replacement) -> None:
    pf = PathFollower()
    pf.start(_at(0.0, 0.0, 8.0), case.first)
    if case.queued is not None:
        assert pf.offer(case.queued) is OfferStatus.ACCEPTED
    events = _fly_along_x(pf, case.at)
    if case.queued is None:
        assert pf.status is PathStatus.SAFETY_BRAKING
    assert (PathEvent.SEGMENT_SWITCHED in events) == (case.current is not case.first)
    assert pf.offer(case.offer) is case.status
    assert pf.current is case.current and pf.pending is case.pending


def test_a_replacement_rebuilds_the_profile_and_is_flown() -> None:
    pf = PathFollower()
    pf.start(_at(0.0, 0.0, 8.0), AB_FAST)
    assert pf.offer(BD) is OfferStatus.ACCEPTED
    _fly_along_x(pf, 20.0)
    assert pf.update(_at(20.0, 0.0, 8.0), 2.5).speed_ref == pytest.approx(8.0)
    assert pf.offer(TIGHT) is OfferStatus.REPLACED
    x, t, refs = 20.0, 2.5, []
    while pf.current is AB_FAST:  # the reference slows for TIGHT's entry (4.0 m/s)
        t += 0.02
        x += 0.02 * 8.0
        out = pf.update(_at(x, 0.0, 8.0), t)
        refs.append(out.speed_ref)
        assert x < 101.0
    assert refs[-2] < 4.5 and out.events[0] is PathEvent.SEGMENT_SWITCHED
    assert pf.current is TIGHT and pf.pending is None
