"""A foreach over the mission's agents through `hdrc3 tst run` and two real tst_managers.

Section 9.4's ``foreach av where [t] can-scan(av) do conc ...``: uav0's manager asks the query,
resolves one instance per agent, runs its own and asks uav1's manager to execute the other,
which resolves the same instance from its id alone.
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

m(P, TS, TE) = foreach Av where [TS] can-fly(Av) do conc
  s(Av, U1, U2) = wait(U1, U2, 3)
where P = uav0
"""


def test_foreach_instances_run_on_every_agent(
    hdrc3_cli: Callable[..., Any], tmp_path: Path
) -> None:
    file = tmp_path / "each.tst"
    file.write_text(MISSION, encoding="utf-8")
    launch = hdrc3_cli(
        "launch", "--agents", "uav0,uav1", "--world", "revinge", "--speed", "max",
        "--nodes", "world_sim,tst_manager",
    )  # fmt: skip
    try:
        launch.wait_for_line("READY", timeout=WAIT_S)
        run = hdrc3_cli(
            "tst", "run", str(file), "--agents", "uav0,uav1", "--mission", "each",
            "--out", str(tmp_path / "out"),
        )  # fmt: skip
        code = run.finish(timeout=WAIT_S)
        text = "\n".join(run.lines)
        assert code == 0, text
        assert "uav1/m[uav1]/s wait running" in text
        assert "mission each succeeded" in text
        launch.wait_for_line("each/m: 2 instances: uav0, uav1", timeout=WAIT_S)
    finally:
        launch.interrupt(timeout=30)
    with (tmp_path / "out" / "timeline.csv").open(encoding="utf-8") as rows:
        table = {row["node"]: row for row in csv.DictReader(rows)}
    assert {n: table[n]["agent"] for n in ("m", "m[uav0]/s", "m[uav1]/s")} == {
        "m": "uav0",
        "m[uav0]/s": "uav0",
        "m[uav1]/s": "uav1",
    }
    for node in ("m", "m[uav0]/s", "m[uav1]/s"):
        assert table[node]["state"] == "succeeded", table[node]
    for node in ("m[uav0]/s", "m[uav1]/s"):  # wait(3) holds on each agent's recorded times
        assert float(table[node]["end_s"]) - float(table[node]["start_s"]) == pytest.approx(3.0)
