"""`hdrc3 tst check` as the user runs it: a child process, output read line by line."""

from __future__ import annotations

from pathlib import Path
from typing import Any

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tst"


def test_check_example_6_1_as_a_command(hdrc3_cli: Any) -> None:
    child = hdrc3_cli("tst", "check", str(EXAMPLES / "example_6_1.tst"))
    assert child.finish(timeout=120) == 0
    assert child.lines[0] == "tau0: sequence  P=uav0  TS [0, 1200)  TE (0, 1200]"
    assert any(line.startswith("  tau4: fly-to  P=uav0") for line in child.lines)
    assert child.lines[-1].endswith("other constraints)")


def test_check_reports_bad_input_with_exit_4(hdrc3_cli: Any, tmp_path: Path) -> None:
    bad = tmp_path / "bad.tst"
    bad.write_text("world revinge\nt(TS, TE) = scan-area(TS, TE, 3, Nowhere)\n")
    child = hdrc3_cli("tst", "check", str(bad))
    assert child.finish(timeout=120) == 4
    assert child.lines[0] == f"{bad}:2:34: error E102: unknown area 'Nowhere' for t.area"
    assert child.lines[-1] == f"{bad}: invalid"
