"""`hdrc3 monitor eval` on CSV traces and MCAP recordings, run in-process."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3.cli.main import main
from hdrc3_dyknow.fake_recording import FakeSample, write_fake_recording

OBLIGATION = "always(not p implies eventually[0,1000] always[0,999] p)"
CSV = """time_ms,p,speed(uav0),speed(uav1),carrying(uav0,box1)
0,false,1,2,false
100,true,3,4,true
250,true,3,70,true
"""


@pytest.fixture
def trace(tmp_path: Path) -> Path:
    path = tmp_path / "trace.csv"
    path.write_text(CSV, encoding="utf-8")
    return path


@pytest.mark.parametrize(
    ("formula", "extra", "code", "lines"),
    [
        (OBLIGATION, [], 0, ["0\tUNDECIDED", "100\tUNDECIDED", "250\tUNDECIDED"]),
        (
            "eventually[0,200] carrying(uav0, box1)",
            [],
            0,
            ["0\tUNDECIDED", "100\tTRUE", "250\tTRUE"],
        ),
        ("always speed(uav1) < 50", [], 1, ["0\tUNDECIDED", "100\tUNDECIDED", "250\tFALSE"]),
        ("exists x in AV: speed(x) > 60", ["--domain", "AV=uav0,uav1"], 1, ["0\tFALSE"]),
        # A sort without --domain holds the objects named in the columns: uav0, uav1, box1.
        ("exists x in THING: x == box1", [], 0, ["0\tTRUE"]),
        ("forall x in AV: always speed(x) < 50", ["--domain", "AV=uav0"], 0, ["0\tUNDECIDED"] * 1),
        ("EXEC until speed(av) > 2", ["--exec-flag", "p", "--bind", "av=uav0"], 1, ["0\tFALSE"]),
    ],
)
def test_eval_csv(
    trace: Path,
    capsys: pytest.CaptureFixture[str],
    formula: str,
    extra: list[str],
    code: int,
    lines: list[str],
) -> None:
    assert main(["monitor", "eval", "--formula", formula, "--trace", str(trace), *extra]) == code
    printed = capsys.readouterr().out.splitlines()
    assert printed[: len(lines)] == lines
    assert len(printed) == 3


def test_eval_prints_residuals(trace: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["monitor", "eval", "--formula", "eventually[0,500] speed(uav1) > 50"]
    assert main([*argv, "--trace", str(trace), "--residual"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first == "0\tUNDECIDED\teventually[0,500] speed(uav1) > 50"


def test_eval_mcap(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "flight.mcap"
    climb = [FakeSample("uav0", t, altitude=t / 100) for t in range(0, 1000, 100)]
    write_fake_recording(path, climb)
    argv = ["monitor", "eval", "--mcap", str(path)]
    mapping = ["--map", "altitude(uav0)=/uav0/helicopter_state.altitude"]
    reached = "eventually[0,800] altitude(uav0) >= 7.0"
    assert main([*argv, *mapping, "--formula", reached]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[6:8] == ["600\tUNDECIDED", "700\tTRUE"]
    everyone = "forall x in AV: eventually[0,800] altitude(x) >= 7.0"  # AV: objects of --map
    assert main([*argv, *mapping, "--formula", everyone]) == 0
    assert capsys.readouterr().out.splitlines()[7] == "700\tTRUE"
    too_slow = "eventually[0,500] altitude(uav0) >= 7.0"
    assert main([*argv, *mapping, "--formula", too_slow, "--period-ms", "250"]) == 1
    assert capsys.readouterr().out.splitlines() == [
        "0\tUNDECIDED",
        "250\tUNDECIDED",
        "500\tFALSE",  # no later state can fall in [0, 500] any more
        "750\tFALSE",
    ]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--formula", "always p and"], "--formula:1:13: unexpected end of formula"),
        (["--formula", "always q"], "unknown fluent 'q'"),
        (["--formula", "forall b in BOX: p", "--domain", "BOX"], "expected NAME=VALUE"),
        (["--formula", "p", "--period-ms", "5"], "apply to --mcap only"),
    ],
)
def test_eval_bad_input_exits_2(
    trace: Path, capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    assert main(["monitor", "eval", "--trace", str(trace), *args]) == 2
    assert message in capsys.readouterr().err


def test_eval_quantifier_without_objects_needs_domain(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "flat.csv"
    path.write_text("time_ms,p\n0,true\n", encoding="utf-8")
    assert main(["monitor", "eval", "--trace", str(path), "--formula", "forall x in AV: p"]) == 2
    assert "--domain AV=" in capsys.readouterr().err


def test_eval_missing_files_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    absent = str(tmp_path / "absent")
    assert main(["monitor", "eval", "--formula", "p", "--trace", absent]) == 2
    mapping = ["--map", "a=/t.x"]
    assert main(["monitor", "eval", "--formula", "p", "--mcap", absent, *mapping]) == 2
    assert capsys.readouterr().err.count("error:") == 2


def test_eval_prints_large_and_fractional_times_plainly(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "clock.csv"
    path.write_text("time_ms,p\n1700000000000,true\n1700000000000.25,true\n", encoding="utf-8")
    assert main(["monitor", "eval", "--trace", str(path), "--formula", "always p"]) == 0
    assert capsys.readouterr().out.split() == [
        "1700000000000",
        "UNDECIDED",
        "1700000000000.25",
        "UNDECIDED",
    ]
