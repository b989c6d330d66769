from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3.cli.main import main
from hdrc3_deliberative.generators import (
    LOGISTICS_CONTROL,
    LOGISTICS_DOMAIN,
    UAV_CONTROL,
    UAV_DOMAIN,
    UAV_SCENARIO,
    LogisticsSize,
    logistics_problem,
)
from tests.unit.hdrc3_deliberative.fuel_domain import FUEL_DOMAIN, FUEL_PROBLEM


def test_solves_uav_scenario(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(
        ["plan", str(UAV_DOMAIN), str(UAV_SCENARIO), "--control", str(UAV_CONTROL), "--tst"]
    )
    out = capsys.readouterr().out
    assert code == 0
    assert "0.000: (pick-up-box heli1 food1 supply1) [20.000]" in out
    assert "; status: solved" in out and "; nodes expanded:" in out
    assert '"type": "concurrent"' in out


def test_logistics_with_validation(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    problem = tmp_path / "p.pddl"
    problem.write_text(logistics_problem(LogisticsSize(5, 2, 1), 2))
    code = main(
        [
            "plan",
            str(LOGISTICS_DOMAIN),
            str(problem),
            "--control",
            str(LOGISTICS_CONTROL),
            "--validate",
        ]
    )
    out = capsys.readouterr().out
    assert code == 0
    assert "; validation: valid" in out


def test_sequential_flag(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(
        ["plan", str(UAV_DOMAIN), str(UAV_SCENARIO), "--control", str(UAV_CONTROL), "--sequential"]
    )
    out = capsys.readouterr().out
    assert code == 0
    lines = [line for line in out.splitlines() if line[:1].isdigit()]
    starts = [float(line.split(":")[0]) for line in lines]
    durations = [float(line.rsplit("[", 1)[1].rstrip("]")) for line in lines]
    assert all(abs(starts[i] + durations[i] - starts[i + 1]) < 2e-3 for i in range(len(lines) - 1))


def _write(tmp_path: Path, name: str, text: str) -> str:
    path = tmp_path / name
    path.write_text(text)
    return str(path)


UNREACHABLE = logistics_problem(LogisticsSize(2, 2, 1), 1).replace(
    "(:goal (and", "(:goal (and (in obj1 tru2) (in obj1 tru1)"
)


@pytest.mark.parametrize(
    ("files", "extra", "code", "stream", "fragment"),
    [
        ({"p.pddl": UNREACHABLE}, [], 2, "out", "; status: unsolvable"),
        (
            {"p.pddl": logistics_problem(LogisticsSize(25, 8, 2), 1)},
            ["--timeout", "0.3"],
            3,
            "out",
            "; status: timeout",
        ),
        (
            {"p.pddl": "(define (problem p) (:domain logistics) (:objects a - crate))"},
            [],
            4,
            "err",
            "undefined type 'crate'",
        ),
        (
            {"p.pddl": "(define (problem p)\n  (:domain logistics)"},
            [],
            4,
            "err",
            "p.pddl:2:22: unexpected end of file",
        ),
        ({"p.pddl": UNREACHABLE}, ["--timeout", "-1"], 4, "err", "--timeout must be a positive"),
        ({}, [], 4, "err", "cannot read file"),
    ],
)
def test_exit_codes(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    files: dict[str, str],
    extra: list[str],
    code: int,
    stream: str,
    fragment: str,
) -> None:
    for name, text in files.items():
        _write(tmp_path, name, text)
    assert main(["plan", str(LOGISTICS_DOMAIN), str(tmp_path / "p.pddl"), *extra]) == code
    captured = capsys.readouterr()
    assert fragment in (captured.out if stream == "out" else captured.err)


@pytest.mark.parametrize(
    ("mode", "code"), [([], 0), (["--cycle-check", "path"], 0), (["--cycle-check", "global"], 2)]
)
def test_cycle_check_option(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], mode: list[str], code: int
) -> None:
    """A goal that wants less fuel: only the global better-or-equal check loses the plan."""
    domain = _write(tmp_path, "d.tal", FUEL_DOMAIN)
    problem = _write(tmp_path, "p.tal", FUEL_PROBLEM.replace("GOAL", "at(s, b) and fuel(s) <= 38"))
    assert main(["plan", domain, problem, *mode]) == code
    capsys.readouterr()
