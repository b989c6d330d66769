"""Starts tied across agents wait for each other, through `hdrc3 tst run` and two tst_managers.

Section 9.4's monitor-pattern in small: uav0 waits 8 s and uav1 2 s, then each runs a node whose
start the mission ties to the other's (``S3 = U3``). uav1's node waits for uav0's (it says so in
its status), and both start at the same recorded time.
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

pytestmark = [pytest.mark.ros, pytest.mark.slow]

WAIT_S = 120.0
MISSION = """world revinge
agents uav0, uav1

m(P, TS, TE) = with P1, A1, A2, P2, B1, B2, S3, U3 concurrent
  a(P1, A1, A2) = with S1, S2, S4 sequence
    a1(S1, S2) = wait(S1, S2, 8);
    a2(S3, S4) = wait(S3, S4, 3)
  where P1 = uav0;
  b(P2, B1, B2) = with U1, U2, U4 sequence
    b1(U1, U2) = wait(U1, U2, 2);
    b2(U3, U4) = wait(U3, U4, 3)
  where P2 = uav1
where P = uav0 and S3 = U3
"""


def test_a_start_tied_to_another_agents_waits_for_it(
    hdrc3_cli: Callable[..., Any], tmp_path: Path
) -> None:
    file = tmp_path / "together.tst"
    file.write_text(MISSION, encoding="utf-8")
    launch = hdrc3_cli(
        "launch", "--agents", "uav0,uav1", "--world", "revinge", "--speed", "max",
        "--nodes", "world_sim,tst_manager",
    )  # fmt: skip
    try:
        launch.wait_for_line("READY", timeout=WAIT_S)
        run = hdrc3_cli(
            "tst", "run", str(file), "--agents", "uav0,uav1", "--mission", "together",
            "--out", str(tmp_path / "out"),
        )  # fmt: skip
        code = run.finish(timeout=WAIT_S)
        text = "\n".join(run.lines)
        assert code == 0, text
        assert "uav1/b2 wait running: waiting for uav0/a1.TE, uav0/a2.TS" in text
        assert "mission together succeeded" in text
    finally:
        launch.interrupt(timeout=30)
    with (tmp_path / "out" / "timeline.csv").open(encoding="utf-8") as rows:
        table = {row["node"]: row for row in csv.DictReader(rows)}
    times = {n: (float(table[n]["start_s"]), float(table[n]["end_s"])) for n in table}
    assert times["a2"][0] == times["b2"][0]  # S3 = U3, as recorded by each agent's manager
    assert times["b2"][0] >= times["a1"][1] >= 8.0 > times["b1"][1]
