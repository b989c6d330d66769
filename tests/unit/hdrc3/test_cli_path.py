from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from hdrc3.cli.main import main

WORLD = str(Path(__file__).parents[1] / "hdrc3_navigation" / "small_world.toml")


@pytest.fixture(scope="module")
def cache(tmp_path_factory: pytest.TempPathFactory) -> str:
    return str(tmp_path_factory.mktemp("cli-roadmaps"))


def base(cache: str) -> list[str]:
    return ["--world", WORLD, "--nodes", "300", "--cache-dir", cache]


def test_roadmap_is_built_then_cached(cache: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["path", "roadmap", *base(cache)]) == 0
    assert "roadmap built: " in capsys.readouterr().out
    assert main(["path", "roadmap", *base(cache)]) == 0
    out = capsys.readouterr().out
    assert "roadmap cached: " in out and " nodes, " in out and "build time" in out


def test_plan_json_has_the_documented_fields(
    cache: str, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["path", "plan", *base(cache), "--from=-60,0,15", "--to", "60,0,15", "--json",
            "--max-alt", "22", "--no-fly=-30,-100;30,-100;30,-20;-30,-20"]  # fmt: skip
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "solved" and out["planner"] == "prm+rrt"
    assert out["planning_ms"] > 0 and out["length_m"] > 120.0
    segs = out["segments"]
    assert segs[0]["start"] == [-60.0, 0.0, 15.0] and segs[-1]["end"] == [60.0, 0.0, 15.0]
    for seg in segs:
        assert set(seg) == {
            "start", "end", "start_direction", "end_direction",
            "target_velocity", "end_velocity", "coefficients",
        }  # fmt: skip
        a, b, c, d = (np.array(v) for v in seg["coefficients"])
        assert d == pytest.approx(seg["start"])
        assert a + b + c + d == pytest.approx(seg["end"])
        for s in np.linspace(0, 1, 11):
            assert (((a * s + b) * s + c) * s + d)[2] <= 22.0 + 1e-6


@pytest.mark.parametrize(
    ("extra", "code", "status"),
    [
        (["--from=0,0,10", "--to", "60,0,15"], 4, "start_in_obstacle"),
        (["--from=-60,0,15", "--to", "65,-65,20"], 4, "goal_in_no_fly_zone"),
        (
            ["--from=-60,0,15", "--to", "60,0,15", "--min-alt", "30", "--max-alt", "20"],
            4,
            "invalid",
        ),
        (["--from=-60,0,15", "--to", "60,0,15", "--timeout", "0.000001"], 3, "timeout"),
        (["--from=-60,0,15", "--to", "60,0,15", "--start-direction", "nan,0,0"], 4, "invalid"),
    ],
)
def test_plan_failures_have_statuses_and_exit_codes(
    cache: str, capsys: pytest.CaptureFixture[str], extra: list[str], code: int, status: str
) -> None:
    assert main(["path", "plan", *base(cache), *extra, "--json"]) == code
    assert json.loads(capsys.readouterr().out)["status"] == status


@pytest.mark.parametrize(
    "extra",
    [
        ["--from", "1,2", "--to", "60,0,15"],
        ["--from=-60,0,15", "--to", "60,0,x"],
        ["--from=-60,0,15", "--to", "60,0,15", "--no-fly", "1,2;3,4"],
        ["--from=-60,0,15", "--to", "60,0,15", "--no-fly", "1,2;3"],
    ],
)
def test_malformed_arguments_exit_2(
    cache: str, capsys: pytest.CaptureFixture[str], extra: list[str]
) -> None:
    assert main(["path", "plan", *base(cache), *extra]) == 2
    assert "error" in capsys.readouterr().err


def test_unknown_world_exits_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["path", "roadmap", "--world", "atlantis"]) == 2
    assert "atlantis" in capsys.readouterr().err


def test_gis_words_name_every_operation_of_the_service() -> None:
    from hdrc3.cli.path import GIS_OPERATIONS
    from hdrc3_interfaces.srv import GisUpdate

    values = {getattr(GisUpdate.Request, name) for name in GIS_OPERATIONS.values()}
    assert values == {0, 1, 2, 3}  # the four operations of GisUpdate.srv, each once


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["add-zone", "--name", "z"], "needs --polygon"),
        (["add-zone", "--name", "z", "--polygon", "1,2;3,4"], "at least 3 vertices"),
        (["add-obstacle", "--name", "z", "--polygon", "1,2;x,4;5,6"], "--polygon"),
        (["remove-zone", "--name", "z", "--agent", "bad agent"], "agent"),
    ],
)
def test_gis_bad_arguments_exit_2_with_the_reason(
    argv: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["path", "gis", *argv]) == 2
    assert message in capsys.readouterr().err


@pytest.mark.ros
def test_gis_without_a_planner_says_so(ros_domain: int, capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["path", "gis", "remove-zone", "--name", "z", "--timeout", "0.5"]
    assert main(argv) == 4
    assert "no service /uav0/path_planner/gis_update" in capsys.readouterr().out
