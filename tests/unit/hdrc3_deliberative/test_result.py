from __future__ import annotations

from hdrc3_deliberative.result import Occurrence, PlanResult, PlanStatus, Statistics


def test_ipc_format_and_summary() -> None:
    plan = (
        Occurrence(0.0, 12.0, "fly-to", ("heli1", "depot1"), "heli1"),
        Occurrence(12.0, 32.5, "pick-up-box", ("heli1", "box1", "depot1"), "heli1"),
    )
    result = PlanResult(PlanStatus.SOLVED, plan, Statistics(nodes_expanded=3, pruned_by_control=5))
    assert result.ipc_lines() == [
        "0.000: (fly-to heli1 depot1) [12.000]",
        "12.000: (pick-up-box heli1 box1 depot1) [20.500]",
    ]
    assert result.makespan == 32.5
    summary = "\n".join(result.summary_lines())
    assert "; status: solved" in summary and "; nodes expanded: 3" in summary
    assert "; pruned by control rules: 5" in summary


def test_empty_and_failed_results() -> None:
    result = PlanResult(PlanStatus.TIMEOUT, reason="no plan within 1 s")
    assert result.makespan == 0.0 and not result.solved
    assert "; reason: no plan within 1 s" in result.summary_lines()
