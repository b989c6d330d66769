"""Missions across two real tst_managers through `hdrc3 tst run` (no aircraft: waits only).

A foreach over the mission's agents (section 9.4's ``foreach av where [t] can-scan(av) do conc
...``): uav0's manager asks the query, resolves one instance per agent, runs its own and asks
uav1's manager to execute the other, which resolves the same instance from its id alone.

Starts tied across agents (section 9.4's monitor-pattern in small): uav0 waits 8 s and uav1
2 s, then each runs a concurrent node whose start the mission ties to the other's (``S3 = U3``)
and whose children start with it (as monitor-single's hover, measurement and look-at do). uav1's
node waits for uav0's, and all six start at the same recorded time. Which of the two says
"waiting for" in its status depends on the managers' ticks and on when each replica hears of
the other's times (the durations are fixed, so a replica that knows when a1 began sees b2's
window open at 8 s); the recorded times do not. The same with four aircraft flying:
``test_radiation_monitoring.py`` (``make flights``).
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

pytestmark = [pytest.mark.ros, pytest.mark.slow]

WAIT_S = 120.0
FOREACH = """world revinge
agents uav0, uav1

m(P, TS, TE) = foreach Av where [TS] can-fly(Av) do conc
  s(Av, U1, U2) = wait(U1, U2, 3)
where P = uav0
"""


TOGETHER = """world revinge
agents uav0, uav1

m(P, TS, TE) = with P1, A1, A2, P2, B1, B2, S3, U3 concurrent
  a(P1, A1, A2) = with S1, S2, S4 sequence
    a1(S1, S2) = wait(S1, S2, 8);
    a2(S3, S4) = with T1, T2, T3, T4 concurrent
      a3(T1, T2) = wait(T1, T2, 3);
      a4(T3, T4) = wait(T3, T4, 3)
    where T1 = S3 and T3 = S3
  where P1 = uav0;
  b(P2, B1, B2) = with U1, U2, U4 sequence
    b1(U1, U2) = wait(U1, U2, 2);
    b2(U3, U4) = with V1, V2, V3, V4 concurrent
      b3(V1, V2) = wait(V1, V2, 3);
      b4(V3, V4) = wait(V3, V4, 3)
    where V1 = U3 and V3 = U3
  where P2 = uav1
where P = uav0 and S3 = U3
"""


def _run(
    hdrc3_cli: Callable[..., Any], tmp_path: Path, text: str, mission: str
) -> tuple[str, dict[str, dict[str, str]]]:
    """Launch two tst_managers, run the mission through `hdrc3 tst run`: its output, timeline."""
    file = tmp_path / f"{mission}.tst"
    file.write_text(text, encoding="utf-8")
    launch = hdrc3_cli(
        "launch", "--agents", "uav0,uav1", "--world", "revinge", "--speed", "max",
        "--nodes", "world_sim,tst_manager",
    )  # fmt: skip
    try:
        launch.wait_for_line("READY", timeout=WAIT_S)
        run = hdrc3_cli(
            "tst", "run", str(file), "--agents", "uav0,uav1", "--mission", mission,
            "--out", str(tmp_path / "out"),
        )  # fmt: skip
        code = run.finish(timeout=WAIT_S)
    finally:
        launch.interrupt()
    output = "\n".join(run.lines + launch.lines)
    assert code == 0, output
    assert f"mission {mission} succeeded" in output
    with (tmp_path / "out" / "timeline.csv").open(encoding="utf-8") as rows:
        return output, {row["node"]: row for row in csv.DictReader(rows)}


def test_foreach_instances_run_on_every_agent(
    hdrc3_cli: Callable[..., Any], tmp_path: Path
) -> None:
    output, table = _run(hdrc3_cli, tmp_path, FOREACH, "each")
    assert "uav1/m[uav1]/s wait running" in output
    assert "each/m: 2 instances: uav0, uav1" in output
    assert {n: table[n]["agent"] for n in ("m", "m[uav0]/s", "m[uav1]/s")} == {
        "m": "uav0",
        "m[uav0]/s": "uav0",
        "m[uav1]/s": "uav1",
    }
    for node in ("m", "m[uav0]/s", "m[uav1]/s"):
        assert table[node]["state"] == "succeeded", table[node]
    for node in ("m[uav0]/s", "m[uav1]/s"):  # wait(3) holds on each agent's recorded times
        assert float(table[node]["end_s"]) - float(table[node]["start_s"]) == pytest.approx(3.0)


def test_a_start_tied_to_another_agents_waits_for_it(
    hdrc3_cli: Callable[..., Any], tmp_path: Path
) -> None:
    _, table = _run(hdrc3_cli, tmp_path, TOGETHER, "together")
    times = {n: (float(table[n]["start_s"]), float(table[n]["end_s"])) for n in table}
    # S3 = U3, as recorded by each agent's manager, and the children with their parents
    starts = [times[n][0] for n in ("a2", "a3", "a4", "b2", "b3", "b4")]
    assert max(starts) - min(starts) < 1e-6, times  # (one is now - epoch, one a fixed time)
    assert times["b2"][0] >= times["a1"][1] >= 8.0 > times["b1"][1]
