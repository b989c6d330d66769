"""The constraint server: capabilities, the mission's time constraints, schedule and energy."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3_delegation.constraint_server import (
    AgentProfile,
    ConstraintServer,
    EvaluationStatus,
)
from hdrc3_delegation.fakes import StraightLineMotion
from hdrc3_delegation.task_cost import TaskCoster
from hdrc3_tst.actions import Capability

EXAMPLES = Path(__file__).parents[3] / "examples" / "tst"
MISSION = (EXAMPLES / "example_6_1_delegated.tst").read_text()
NEAR = (-200.0, -100.0, 0.0)
FAR = (300.0, 300.0, 0.0)


def server(
    name: str = "uav0",
    position: tuple[float, float, float] = NEAR,
    capabilities: frozenset[Capability] = frozenset(Capability),
    energy: float = 40e6,
) -> ConstraintServer:
    profile = AgentProfile(name, capabilities, energy)
    return ConstraintServer(profile, TaskCoster(StraightLineMotion()), position)


def test_a_bid_is_the_marginal_completion_time() -> None:
    near = server().evaluate("m", MISSION, [], ["tau2"], 0.0)
    far = server(position=FAR).evaluate("m", MISSION, [], ["tau2"], 0.0)
    assert near.acceptable and far.acceptable
    assert near.bid is not None and far.bid is not None
    assert near.bid.completion < far.bid.completion
    assert near.bid.completion == pytest.approx(near.bid.duration)
    both = server().evaluate("m", MISSION, ["tau2.P=uav0"], ["tau4"], 0.0)
    assert both.bid is not None
    assert both.bid.completion > near.bid.completion + 20.0, "tau4 comes after tau2"
    assert both.bid.slack == pytest.approx(900.0 - both.bid.completion, abs=1.0)


@pytest.mark.parametrize(
    ("kwargs", "fixes", "nodes", "status", "named"),
    [
        (
            {"capabilities": frozenset({Capability.FLIGHT})},
            [],
            ["tau2"],
            "refused",
            "no camera, ptu",
        ),
        ({"energy": 1e6}, [], ["tau2"], "refused", "MJ, more than its budget"),
        ({"position": (-9000.0, -9000.0, 0.0)}, [], ["tau2"], "refused", "TE0 <= 900"),
        ({}, ["tau2.P=uav1"], ["tau2"], "refused", "may not run tau2"),
        ({}, ["tau2.P=uav0"], ["tau3"], "refused", "cannot run tau2 and tau3 at once"),
        ({}, ["tau2.X=1"], ["tau2"], "not_understood", "no parameter"),
        ({}, ["garbage"], ["tau2"], "not_understood", "malformed binding"),
        ({}, [], ["tau9"], "not_understood", "no node 'tau9'"),
        ({}, [], [], "not_understood", "no node offered"),
    ],
)
def test_refusals_name_the_constraint(
    kwargs: dict[str, object], fixes: list[str], nodes: list[str], status: str, named: str
) -> None:
    evaluation = server(**kwargs).evaluate("m", MISSION, fixes, nodes, 0.0)  # type: ignore[arg-type]
    assert evaluation.status is EvaluationStatus(status)
    assert named in evaluation.reason
    if evaluation.status is EvaluationStatus.REFUSED:
        assert evaluation.constraints


def test_the_deadline_refusal_names_both_sides_of_the_conflict() -> None:
    evaluation = server(position=(-9000.0, -9000.0, 0.0)).evaluate("m", MISSION, [], ["tau2"], 0.0)
    assert any("needs" in c and "tau2" in c for c in evaluation.constraints)
    assert any("TE0 <= 900" in c for c in evaluation.constraints)


def test_a_mission_that_does_not_parse_is_not_understood_with_its_position() -> None:
    evaluation = server().evaluate("m", "tau0(TS0, TE0) = fly-to(", [], ["tau0"], 0.0)
    assert evaluation.status is EvaluationStatus.NOT_UNDERSTOOD
    assert "<m>:1:" in evaluation.reason


def test_commitments_delay_later_missions_until_released() -> None:
    cs = server()
    first = cs.commit("m1", MISSION, [], ["tau2"], 0.0)
    assert first.acceptable and first.bid is not None
    later = cs.evaluate("m2", MISSION, [], ["tau2"], 0.0)
    assert later.bid is not None
    assert later.bid.completion > first.bid.completion + 60.0
    cs.release("m1")
    again = cs.evaluate("m2", MISSION, [], ["tau2"], 0.0)
    assert again.bid is not None
    assert again.bid.completion == pytest.approx(first.bid.completion)
