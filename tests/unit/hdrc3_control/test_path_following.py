"""PFCM: segment offers, Request-Segment, virtual leader, and safety braking in the sim."""

from __future__ import annotations

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
        (AB, [BC, BC], [OfferStatus.ACCEPTED, OfferStatus.BUSY]),
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
