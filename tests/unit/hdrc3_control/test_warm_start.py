"""The PFC's warm-start record: file round trip, bad files, age checks."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from hdrc3_control.warm_start import WarmStart, read_warm_start, write_warm_start

RECORD = WarmStart(time=30.0, baro_bias=-1.25, baro_bias_sigma=0.1)


def test_round_trip(tmp_path: Path) -> None:
    path = tmp_path / "uav0.control_kernel.checkpoint"
    write_warm_start(path, RECORD)
    write_warm_start(path, RECORD)  # replaced, no temporary file left behind
    assert read_warm_start(path).record == RECORD
    assert [p.name for p in tmp_path.iterdir()] == [path.name]


@pytest.mark.parametrize(
    ("content", "reason"),
    [
        (None, "no warm-start record"),
        (b"", "cannot read"),
        (b"\x00\xff garbage", "cannot read"),
        (b"[1, 2]", "not a warm-start record"),
        (b'{"format": 2, "time": 1, "baro_bias": 0, "baro_bias_sigma": 1}', "format 1"),
        (b'{"format": 1, "time": 1, "baro_bias": 0}', "bad field"),
        (b'{"format": 1, "time": "x", "baro_bias": 0, "baro_bias_sigma": 1}', "bad field"),
        (b'{"format": 1, "time": 1, "baro_bias": NaN, "baro_bias_sigma": 1}', "non-finite"),
        (b'{"format": 1, "time": 1, "baro_bias": 0, "baro_bias_sigma": 0}', "non-positive"),
    ],
)
def test_a_bad_file_is_a_cold_start_with_a_reason(
    tmp_path: Path, content: bytes | None, reason: str
) -> None:
    path = tmp_path / "record"
    if content is not None:
        path.write_bytes(content)
    loaded = read_warm_start(path)
    assert loaded.record is None and reason in loaded.reason


@pytest.mark.parametrize(
    ("now", "usable"),
    [(30.0, True), (149.0, True), (151.0, False), (29.0, False), (math.inf, False)],
)
def test_a_record_is_used_only_at_most_max_age_after_it(now: float, usable: bool) -> None:
    assert (RECORD.usable_at(now, 120.0) is None) is usable
