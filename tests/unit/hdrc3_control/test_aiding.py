"""Aiding book-keeping: sources in use, the filter's travel memory, consistent rejections."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdrc3_control.aiding import AidingLog, AidingSource, PositionHistory, Verdict, consistent


@pytest.mark.parametrize(
    ("time", "expected"),
    [
        (1.0, (0.0, 0.0, 0.0)),
        (1.05, (0.5, 0.0, 0.0)),  # between two entries
        (1.2, (2.0, 0.0, 0.0)),
        (5.0, (2.0, 0.0, 0.0)),  # after the last: the last
        (0.9, None),  # older than the memory
    ],
)
def test_position_history(time: float, expected: tuple[float, float, float] | None) -> None:
    history = PositionHistory(span=1.0)
    for k in range(3):
        history.add(1.0 + 0.1 * k, np.array([float(k), 0.0, 0.0]))
    got = history.at(time)
    assert (got is None) if expected is None else np.allclose(got, expected)  # type: ignore[arg-type]


def test_the_history_forgets_beyond_its_span() -> None:
    history = PositionHistory(span=0.5)
    for k in range(20):
        history.add(0.1 * k, np.zeros(3))
    assert history.at(1.3) is None and history.at(1.45) is not None


@pytest.mark.parametrize(
    ("innovations", "spread", "agree"),
    [
        ([np.array([2.0, 1.0, 0.0]), np.array([2.1, 0.9, 0.05])], 0.3, True),
        ([np.array([2.0, 1.0, 0.0]), np.array([-2.0, 1.0, 0.0])], 0.3, False),
        ([], 0.3, False),
    ],
)
def test_consistent(innovations: list[np.ndarray], spread: float, agree: bool) -> None:
    assert consistent(innovations, spread) is agree


def test_the_log_says_which_sources_were_used() -> None:
    log = AidingLog()
    log.note(AidingSource.GPS, Verdict.ACCEPTED, 1.0)
    log.note(AidingSource.VISION, Verdict.REJECTED, 1.9, 2.5)
    log.note(AidingSource.BARO, Verdict.ACCEPTED, 1.8)
    assert log.used(2.0, 0.5) == (AidingSource.BARO,)
    log.note(AidingSource.VISION, Verdict.ACCEPTED, 2.0, 0.03)
    assert log.used(2.0, 0.5) == (AidingSource.VISION, AidingSource.BARO)
    assert log.count(AidingSource.VISION, Verdict.REJECTED) == 1
    assert log.count(AidingSource.GROUND, Verdict.ACCEPTED) == 0
    report = log.report(2.0, 0.5)
    vision = report["sources"]["vision"]  # type: ignore[index]
    assert vision["accepted"] == 1 and vision["innovation_m"] == 0.03 and vision["age_s"] == 0.0
    assert report["used"] == ["vision", "baro"]
    assert not math.isinf(log.stats[AidingSource.GPS].last_accepted)


def test_seen_age_counts_every_verdict_age_only_accepted_ones() -> None:
    log = AidingLog()
    log.note(AidingSource.VISION, Verdict.ACCEPTED, 1.0)
    log.note(AidingSource.VISION, Verdict.REJECTED, 4.0)
    assert log.age(AidingSource.VISION, 5.0) == pytest.approx(4.0)
    assert log.seen_age(AidingSource.VISION, 5.0) == pytest.approx(1.0)
    assert log.seen_age(AidingSource.GPS, 5.0) == math.inf
