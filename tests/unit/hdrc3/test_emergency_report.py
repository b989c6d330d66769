"""Scoring the flagship: deliveries, closest approach, the issue's targets."""

from __future__ import annotations

import math

import pytest

from hdrc3.emergency_mission import Body
from hdrc3.emergency_report import DELIVERED_WITHIN_M, Delivery, Evaluation, min_separation


@pytest.mark.parametrize(
    ("final", "held_by", "delivered"),
    [
        ((10.0, 0.0), "", True),
        ((10.0 + DELIVERED_WITHIN_M + 0.1, 0.0), "", False),
        ((10.0, 0.0), "uav0", False),  # still on the hook
        (None, "", False),  # never seen
    ],
)
def test_a_box_is_delivered_on_the_ground_near_its_drop_point(
    final: tuple[float, float] | None, held_by: str, delivered: bool
) -> None:
    assert Delivery("box1", "Body1", (10.0, 0.0), final, held_by).delivered is delivered


@pytest.mark.parametrize(
    ("tracks", "closest"),
    [
        ({"uav0": [(1.2, 0.0, 0.0, 20.0)], "uav1": [(1.7, 30.0, 40.0, 20.0)]}, 50.0),
        # on the ground (< 2 m up) the aircraft stand on their pads: not an approach in the air
        ({"uav0": [(1.0, 0.0, 0.0, 0.5)], "uav1": [(1.0, 3.0, 0.0, 0.5)]}, math.inf),
        ({"uav0": [(1.0, 0.0, 0.0, 20.0)], "uav1": [(2.0, 3.0, 0.0, 20.0)]}, math.inf),
    ],
)
def test_the_closest_approach_compares_airborne_aircraft_in_the_same_second(
    tracks: dict[str, list[tuple[float, float, float, float]]], closest: float
) -> None:
    assert min_separation(tracks) == pytest.approx(closest)


def _evaluation(found: int, false_positives: int, delivered: bool) -> Evaluation:
    body = Body("Body1", 0.0, 0.0, 1.0)
    ev = Evaluation(people=[("body03", 0.0, 0.0), ("body04", 9.0, 9.0)])
    ev.found = {pid: (body, 1.0) for pid in ("body03", "body04")[:found]}
    ev.false_positives = [body] * false_positives
    final = (0.0, 0.0) if delivered else None
    ev.deliveries = [Delivery("box1", "Body1", (0.0, 0.0), final, "")]
    ev.tracks = {"uav0": [(0.0, 0.0, 0.0, 0.0), (600.0, 0.0, 0.0, 0.0)]}
    return ev


@pytest.mark.parametrize(
    ("ev", "wall", "met"),
    [
        (_evaluation(2, 1, True), 500.0, [True, True, True, True, True]),
        (_evaluation(1, 0, True), 500.0, [False, True, True, True, True]),
        (_evaluation(2, 2, False), 500.0, [False, False, True, True, True]),
        (_evaluation(2, 0, True), 1000.0, [True, True, True, False, False]),
    ],
)
def test_the_targets_say_which_were_met(ev: Evaluation, wall: float, met: list[bool]) -> None:
    assert [ok for _, ok in ev.targets(wall)] == met
    assert ev.sim_seconds == 600.0
