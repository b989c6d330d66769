"""Loading TALF end to end: the status of each kind of input."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_deliberative.talf_diagnostics import TalfStatus
from hdrc3_deliberative.talf_load import load_file, load_text
from hdrc3_tst.actions import ACTIONS

MISSION = "agents uav0, uav1\npoint D = H1 at 20\nmission m: [t, t2] by P pick-up-box(D)"


@pytest.mark.parametrize(
    ("text", "capabilities", "status", "codes"),
    [
        (MISSION, None, TalfStatus.OK, []),
        (MISSION, {"uav0": frozenset({"flight"})}, TalfStatus.OK, []),  # uav1 has everything
        (
            MISSION,
            {"uav0": frozenset({"flight"}), "uav1": frozenset({"camera"})},
            TalfStatus.UNSATISFIABLE,
            ["T110"],
        ),
        ("mission m: [t, t2] pick-up-box(D)", None, TalfStatus.INVALID, ["T101"]),
        ("mission m: [t, t2", None, TalfStatus.SYNTAX_ERROR, ["T001"]),
    ],
)
def test_statuses(
    text: str,
    capabilities: dict[str, frozenset[str]] | None,
    status: TalfStatus,
    codes: list[str],
) -> None:
    result = load_text(text, ACTIONS, "m.talf", capabilities)
    assert result.status is status
    assert [d.code for d in result.diagnostics] == codes
    assert (result.tree is None) == (status in (TalfStatus.INVALID, TalfStatus.SYNTAX_ERROR))


def test_missing_file(tmp_path: Path) -> None:
    result = load_file(tmp_path / "none.talf", ACTIONS)
    assert result.status is TalfStatus.UNREADABLE
