"""RenderGate: which agents' renderer lags too far behind the announced camera exposures."""

from __future__ import annotations

import math

import pytest

from hdrc3_base.errors import ConfigError
from sim.render_gate import DEFAULT_LAG_S, MAX_LAG_S, RenderGate

MS = 1_000_000


@pytest.mark.parametrize(
    ("announced", "handled", "behind"),
    [
        ({}, {}, []),  # no exposure announced (no camera topics listened to): nothing held
        ({"uav0": 40 * MS}, {}, []),  # within the lag before the first report
        ({"uav0": 120 * MS}, {}, ["uav0"]),  # no report yet, exposures beyond the lag
        ({"uav0": 200 * MS}, {"uav0": 100 * MS}, []),  # exactly the lag
        ({"uav0": 240 * MS}, {"uav0": 120 * MS}, ["uav0"]),  # three frames behind
        ({"uav0": 240 * MS, "uav1": 240 * MS}, {"uav0": 240 * MS, "uav1": 80 * MS}, ["uav1"]),
        ({"uav0": 40 * MS}, {"uav0": 5_000 * MS}, []),  # reports of a newer stamp: caught up
    ],
)
def test_behind(announced: dict[str, int], handled: dict[str, int], behind: list[str]) -> None:
    gate = RenderGate.from_seconds(0.1)
    for agent, stamp in announced.items():
        gate.announce(agent, stamp)
    for agent, stamp in handled.items():
        gate.report(agent, stamp)
    assert gate.behind() == behind


def test_the_newest_report_counts_and_a_reset_forgets() -> None:
    gate = RenderGate.from_seconds(DEFAULT_LAG_S)
    gate.announce("uav0", 1_000 * MS)
    gate.report("uav0", 960 * MS)
    assert gate.behind() == []
    gate.report("uav0", 40 * MS)  # sim time restarted: the newest report is what holds
    assert gate.behind() == ["uav0"]
    gate.reset()
    assert gate.behind() == [] and not gate.announced and not gate.handled


@pytest.mark.parametrize("lag", [-0.001, MAX_LAG_S + 1.0, math.nan, math.inf])
def test_a_bad_lag_is_a_config_error(lag: float) -> None:
    with pytest.raises(ConfigError, match="render_lag"):
        RenderGate.from_seconds(lag)


def test_zero_lag_holds_until_the_newest_exposure_is_handled() -> None:
    gate = RenderGate.from_seconds(0.0)
    gate.announce("uav0", 40 * MS)
    assert gate.behind() == ["uav0"]
    gate.report("uav0", 40 * MS)
    assert gate.behind() == []
