"""The delegation protocol end to end on an in-memory bus: auctions, awards, partitions."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from hdrc3_delegation.acl import AclMessage, Performative
from hdrc3_delegation.authentication import Authenticator, Verdict
from hdrc3_delegation.constraint_server import AgentProfile, ConstraintServer
from hdrc3_delegation.contract_net import (
    LANGUAGE,
    PROTOCOL,
    Contractor,
    Delegation,
    Phase,
    Timing,
    content,
)
from hdrc3_delegation.fakes import FakeManager, LocalBus, StraightLineMotion
from hdrc3_delegation.keystore import Keystore
from hdrc3_delegation.task_cost import TaskCoster
from hdrc3_tst.actions import Capability
from hdrc3_tst.check import load_text

MISSION = (Path(__file__).parents[3] / "examples" / "tst" / "example_6_1_delegated.tst").read_text()
KEYS = Keystore({a: bytes([i]) * 32 for i, a in enumerate(["gcs", "uav0", "uav1", "uav2"])})
POSITIONS = {"uav0": (-200.0, -100.0, 0.0), "uav1": (-100.0, -150.0, 0.0), "uav2": (0.0, 0.0, 0.0)}
TIMING = Timing(answer_s=5.0, award_s=10.0, start_s=5.0, execution_s=100.0)


def fleet(no_camera: tuple[str, ...] = ("uav2",), max_agents: int | None = 2) -> LocalBus:
    contractors = {}
    for agent, position in POSITIONS.items():
        caps = frozenset({Capability.FLIGHT}) if agent in no_camera else frozenset(Capability)
        cs = ConstraintServer(AgentProfile(agent, caps), TaskCoster(StraightLineMotion()), position)
        contractors[agent] = (
            Contractor(agent, cs, FakeManager(), TIMING),
            Authenticator(agent, KEYS),
        )
    bus = LocalBus(Authenticator("gcs", KEYS), contractors)
    tst = load_text(MISSION).tst
    assert tst is not None
    bus.delegation = Delegation("gcs", "c1", "m", MISSION, tst, list(POSITIONS), max_agents, TIMING)
    return bus


def manager(bus: LocalBus, agent: str) -> FakeManager:
    port = bus.contractors[agent][0].port
    assert isinstance(port, FakeManager)
    return port


def start(bus: LocalBus) -> Delegation:
    assert bus.delegation is not None
    bus.send(bus.delegator_auth, bus.delegation.start(bus.now))
    return bus.delegation


def finish(bus: LocalBus, nodes: tuple[str, ...] = (), state: str = "succeeded") -> None:
    """Managers report ``nodes`` (default: all) finished; everybody ticks."""
    delegation = bus.delegation
    assert delegation is not None
    for node, agent in delegation.assignment.items():
        if not nodes or node in nodes:
            manager(bus, agent).states.setdefault(delegation.instance, {})[node] = state
    bus.tick(bus.now + 1.0)


def executed(bus: LocalBus) -> list[tuple[str, str, str]]:
    """(agent, mission, node) of every execute request the managers got."""
    return sorted((a, *e) for a in POSITIONS for e in manager(bus, a).executed)


def test_example_6_1_goes_to_two_capable_agents_and_runs_once() -> None:
    bus = fleet()
    delegation = start(bus)
    assert delegation.phase is Phase.EXECUTING, delegation.events
    assignment = delegation.assignment
    assert set(assignment.values()) == {"uav0", "uav1"}
    assert assignment["tau2"] != assignment["tau3"], "concurrent scans on two aircraft"
    for agent in ("uav0", "uav1"):
        (created,) = manager(bus, agent).created
        assert created[0] == "m" and set(created[1]) == set(delegation.fixes)
    assert manager(bus, "uav2").created == []
    assert any("uav2 has no camera" in e for e in delegation.events)
    # the delegator runs tau0 and tau1 (they span agents): first both scans, then tau4
    scans = [(assignment["tau2"], "m", "tau2"), (assignment["tau3"], "m", "tau3")]
    assert executed(bus) == sorted(scans)
    finish(bus, ("tau2",))
    assert executed(bus) == sorted(scans), "tau4 waits for the whole concurrent tau1"
    finish(bus, ("tau3",))
    assert executed(bus) == sorted([*scans, (assignment["tau4"], "m", "tau4")])
    assert delegation.phase is Phase.EXECUTING
    finish(bus, ("tau4",))
    assert delegation.phase is Phase.DONE
    assert all(check.accepted for _, _, check in bus.log)


def test_without_a_limit_the_cheapest_bidder_wins_each_node() -> None:
    bus = fleet(no_camera=(), max_agents=None)
    delegation = start(bus)
    assert delegation.phase is Phase.EXECUTING
    assert len(set(delegation.assignment.values())) >= 2


def test_a_winner_partitioned_before_its_award_is_replaced_and_never_executes() -> None:
    bus = fleet(no_camera=())
    bus.cut = (Performative.ACCEPT_PROPOSAL, "uav0", 0)
    delegation = start(bus)
    assert delegation.phase is Phase.AWARD and "uav0" in bus.partitioned
    bus.tick(TIMING.award_s + 1.0)
    assert delegation.phase is Phase.EXECUTING, delegation.events
    assert delegation.round == 1 and "uav0" in delegation.excluded
    assignment = delegation.assignment
    assert {assignment["tau2"], assignment["tau3"]} == {"uav1", "uav2"}
    assert manager(bus, "uav1").aborted, "round 0's replica is aborted on cancel"
    assert {(m, n) for _, m, n in executed(bus)} == {("m-r1", "tau2"), ("m-r1", "tau3")}
    bus.now += 5.0
    before = len(bus.log)
    bus.heal()
    late = [m for m, r, _ in bus.log[before:] if r == "gcs" and m.sender == "uav0"]
    assert [m.performative for m in late] == [Performative.FAILURE]
    assert "after its reply-by" in late[0].content
    assert manager(bus, "uav0").created == [] and manager(bus, "uav0").executed == []
    finish(bus)
    assert delegation.phase is Phase.DONE


def test_an_agent_silent_during_the_auction_is_excluded() -> None:
    bus = fleet(no_camera=())
    bus.partitioned.add("uav1")
    delegation = start(bus)
    assert delegation.phase is Phase.AUCTION
    bus.tick(TIMING.answer_s + 1.0)
    assert delegation.excluded == {"uav1": "did not answer a cfp by reply-by"}
    assert delegation.phase is Phase.EXECUTING
    assert "uav1" not in delegation.assignment.values()


def test_a_winner_silent_in_a_later_auction_is_replaced_before_any_award() -> None:
    bus = fleet(no_camera=())
    bus.cut = (Performative.CFP, "uav0", 1)  # uav0 bids for tau2, then goes silent
    delegation = start(bus)
    assert delegation.winners and delegation.phase is Phase.AUCTION
    bus.tick(TIMING.answer_s + 1.0)
    assert delegation.excluded == {"uav0": "did not answer a cfp by reply-by"}
    assert delegation.phase is Phase.EXECUTING, delegation.events
    assert "uav0" not in delegation.assignment.values()
    awarded = {r for m, r, _ in bus.log if m.performative is Performative.ACCEPT_PROPOSAL}
    assert awarded == {"uav1", "uav2"}
    assert not [m for m, _ in bus.held if m.performative is Performative.ACCEPT_PROPOSAL]


def test_an_open_goal_node_is_refused_before_any_cfp() -> None:
    text = MISSION.replace(
        "tau4(P4, TS4, TE4) = fly-to(TS4, TE4, Speed4, Dest4)",
        "tau4(P4, TS4, TE4) = goal at(uav0, Dest4)",
    )
    tst = load_text(text).tst
    assert tst is not None
    delegation = Delegation("gcs", "c", "m", text, tst, list(POSITIONS), None, TIMING)
    assert delegation.start(0.0) == []
    assert delegation.phase is Phase.FAILED and "tau4 is a goal node" in delegation.reason


def test_nobody_capable_fails_with_every_reason() -> None:
    bus = fleet(no_camera=("uav0", "uav1", "uav2"))
    delegation = start(bus)
    assert delegation.phase is Phase.FAILED
    assert "nobody can take tau2" in delegation.reason
    assert delegation.reason.count("has no camera") == 3


def test_a_failed_node_fails_the_delegation_and_cancels_the_rest() -> None:
    bus = fleet()
    delegation = start(bus)
    finish(bus, state="failed")
    assert delegation.phase is Phase.FAILED
    assert "failed" in delegation.reason
    assert any("failed: set by the test" in e for e in delegation.events), "the reason travels"
    cancels = [m for m, _, _ in bus.log if m.performative is Performative.CANCEL]
    assert cancels


def test_the_execution_deadline_fails_the_delegation() -> None:
    bus = fleet()
    delegation = start(bus)
    bus.tick(TIMING.execution_s + 10.0)
    assert delegation.phase is Phase.FAILED and "in time" in delegation.reason


ORDERED = """world revinge
agents uav0, uav1, uav2
point OverH1 = H1 at 12
point OverH2 = H2 at 12
m(P0, TS0, TE0) = with P1, TS1, TE1, P2, TS2, TE2 concurrent
  x(P1, TS1, TE1) = fly-to(TS1, TE1, 3, OverH1);
  y(P2, TS2, TE2) = fly-to(TS2, TE2, 3, OverH2)
where TS0 <= TS1 and TE1 <= TS2 and TE2 <= TE0 and TE0 <= 900
"""


def test_a_subtree_is_requested_once_what_must_come_before_it_happened() -> None:
    """y starts after x ends (``TE1 <= TS2``) on two aircraft: the delegator, which hears both,
    requests y only once x's agent reported its end (its replica may not hear x's)."""
    bus = fleet(no_camera=(), max_agents=None)
    tst = load_text(ORDERED).tst
    assert tst is not None
    bus.delegation = Delegation("gcs", "c1", "m", ORDERED, tst, list(POSITIONS), None, TIMING)
    delegation = start(bus)
    assignment = delegation.assignment
    assert assignment["x"] != assignment["y"], delegation.events
    assert executed(bus) == [(assignment["x"], "m", "x")], "y waits for x's end"
    manager(bus, assignment["x"]).states.setdefault("m", {})["x"] = "running"
    bus.tick(bus.now + 1.0)
    assert len(executed(bus)) == 1, "x running is not x ended"
    finish(bus, ("x",))
    assert (assignment["y"], "m", "y") in executed(bus)
    finish(bus, ("y",))
    assert delegation.phase is Phase.DONE


# --- re-delegation: the operator makes one agent responsible for the whole mission ----------
def responsible_fleet(no_camera: tuple[str, ...]) -> tuple[LocalBus, Contractor]:
    """uav0 answers for Example 6.1 and may re-delegate to uav1 and uav2."""
    bus = fleet(no_camera=no_camera, max_agents=None)
    for contractor_, _ in bus.contractors.values():
        contractor_.peers = tuple(POSITIONS)
    tst = load_text(MISSION).tst
    assert tst is not None
    bus.delegation = Delegation("gcs", "c1", "m", MISSION, tst, ["uav0"], None, TIMING, whole=True)
    return bus, bus.contractors["uav0"][0]


def nested(uav0: Contractor) -> Delegation:
    (duty,) = uav0.responsible.values()
    return duty.nested


def test_a_responsible_agent_re_delegates_what_it_cannot_fly() -> None:
    bus, uav0 = responsible_fleet(no_camera=("uav0",))
    delegation = start(bus)
    assert delegation.phase is Phase.EXECUTING, delegation.events
    assert set(delegation.assignment.values()) == {"uav0"}, "the operator sees one contractor"
    parts = nested(uav0)
    assignment = parts.assignment
    assert parts.phase is Phase.EXECUTING and parts.conversation == "c1/uav0"
    assert {assignment["tau2"], assignment["tau3"]} == {"uav1", "uav2"}, "uav0 has no camera"
    scans = sorted((assignment[n], "m", n) for n in ("tau2", "tau3"))
    assert executed(bus) == scans
    for node in ("tau2", "tau3"):
        manager(bus, assignment[node]).states.setdefault("m", {})[node] = "succeeded"
    bus.tick(bus.now + 1.0)
    assert executed(bus) == sorted([*scans, (assignment["tau4"], "m", "tau4")])
    assert delegation.node_states["tau2"] == "succeeded", "progress is relayed to the operator"
    manager(bus, assignment["tau4"]).states.setdefault("m", {})["tau4"] = "succeeded"
    bus.tick(bus.now + 1.0)
    bus.tick(bus.now + 1.0)
    assert delegation.phase is Phase.DONE, delegation.events
    assert uav0.responsible == {}
    assert all(check.accepted for _, _, check in bus.log)
    proposal = next(
        m for m, r, _ in bus.log if r == "gcs" and m.performative is Performative.PROPOSE
    )
    assert '"parts"' in proposal.content
    assert any(f"tau2={assignment['tau2']}" in e for e in delegation.events), "who does what"


def test_a_responsible_agent_that_finds_nobody_refuses_with_the_reason() -> None:
    bus, uav0 = responsible_fleet(no_camera=tuple(POSITIONS))
    delegation = start(bus)
    assert delegation.phase is Phase.FAILED
    assert "re-delegation failed: nobody can take tau2" in delegation.reason
    assert uav0.responsible == {}


def test_a_failed_part_fails_the_operators_delegation_with_the_reason() -> None:
    bus, uav0 = responsible_fleet(no_camera=("uav0",))
    delegation = start(bus)
    assignment = nested(uav0).assignment
    manager(bus, assignment["tau2"]).states.setdefault("m", {})["tau2"] = "failed"
    bus.tick(bus.now + 1.0)
    bus.tick(bus.now + 1.0)
    assert delegation.phase is Phase.FAILED and "re-delegation failed" in delegation.reason
    assert any("tau2 failed: set by the test" in e for e in delegation.events), "reason relayed"
    aborted = [a for a in ("uav1", "uav2") if manager(bus, a).aborted]
    assert aborted, "the parts are cancelled"


def test_an_operators_cancel_reaches_the_parts() -> None:
    bus, uav0 = responsible_fleet(no_camera=("uav0",))
    delegation = start(bus)
    assignment = nested(uav0).assignment
    bus.send(bus.delegator_auth, delegation.cancel("operator abort"))
    assert uav0.responsible == {}
    assert manager(bus, assignment["tau2"]).aborted and manager(bus, assignment["tau3"]).aborted


def test_an_award_after_the_proposal_lapsed_is_a_failure() -> None:
    bus, uav0 = responsible_fleet(no_camera=("uav0",))
    uav0.timing = replace(TIMING, proposal_valid_s=3.0)  # lapses before the award's reply-by
    bus.cut = (Performative.ACCEPT_PROPOSAL, "uav0", 0)  # the operator's award is held back
    delegation = start(bus)
    assert delegation.phase is Phase.AWARD and uav0.responsible
    bus.tick(5.0)
    assert uav0.responsible == {}, "the proposal lapsed: nothing is held for the operator"
    before = len(bus.log)
    bus.heal()
    late = [m for m, r, _ in bus.log[before:] if r == "gcs" and m.sender == "uav0"]
    assert [m.performative for m in late] == [Performative.FAILURE]
    assert "no proposal of this agent for the whole mission stands" in late[0].content
    assert all(not manager(bus, a).created for a in POSITIONS), "nobody committed"


def test_without_peers_a_whole_mission_is_priced_alone() -> None:
    bus, uav0 = responsible_fleet(no_camera=())
    uav0.peers = ()
    delegation = start(bus)
    assert delegation.phase is Phase.FAILED, "one aircraft cannot scan A and B concurrently"
    assert uav0.responsible == {}


def contractor() -> Contractor:
    cs = ConstraintServer(AgentProfile("uav0"), TaskCoster(StraightLineMotion()), (0.0, 0.0, 0.0))
    return Contractor("uav0", cs, FakeManager(), TIMING)


def ask(
    performative: Performative, body: str, language: str = LANGUAGE, reply_by: float = 0.0
) -> AclMessage:
    return AclMessage(
        performative, "gcs", ("uav0",), body, language, "", PROTOCOL, "c", "t", reply_by=reply_by
    )


@pytest.mark.parametrize(
    ("msg", "performative", "reason"),
    [
        (ask(Performative.CFP, "{"), Performative.NOT_UNDERSTOOD, "not JSON"),
        (ask(Performative.CFP, "[]"), Performative.NOT_UNDERSTOOD, "not a JSON object"),
        (ask(Performative.CFP, "{}", language="fipa-sl"), Performative.NOT_UNDERSTOOD, "language"),
        (ask(Performative.CFP, content(mission="m")), Performative.NOT_UNDERSTOOD, "tst text"),
        (
            ask(Performative.CFP, content(mission="m", tst="x(", fixes=[], nodes=["x"])),
            Performative.NOT_UNDERSTOOD,
            "does not load",
        ),
        (
            ask(
                Performative.CFP,
                content(mission="m", tst=MISSION, fixes=[], nodes=["tau2"]),
                reply_by=-1.0 + 1e-9,
            ),
            Performative.REFUSE,
            "reply-by has passed",
        ),
        (ask(Performative.SUBSCRIBE, "{}"), Performative.NOT_UNDERSTOOD, "not part of"),
        (
            ask(Performative.REQUEST, content(mission="m", execute="tau0")),
            Performative.REFUSE,
            "no commitment",
        ),
        (
            ask(
                Performative.ACCEPT_PROPOSAL,
                content(mission="m", tst=MISSION, fixes=[], nodes=["tau2"]),
                reply_by=0.5,
            ),
            Performative.FAILURE,
            "after its reply-by",
        ),
    ],
)
def test_bad_requests_are_answered_with_a_reason(
    msg: AclMessage, performative: Performative, reason: str
) -> None:
    (answer,) = contractor().handle(msg, 1.0)
    assert answer.performative is performative
    assert reason in answer.content
    assert (answer.sender, answer.receivers, answer.in_reply_to) == ("uav0", ("gcs",), "t")


def test_the_bus_refuses_forged_messages() -> None:
    bus = fleet()
    forged = Authenticator("gcs", Keystore({"gcs": b"x" * 32})).sign(
        ask(Performative.CFP, content(mission="m", tst=MISSION, fixes=[], nodes=["tau2"])), 0.0
    )
    bus.route([forged])
    ((_, _, check),) = bus.log
    assert check.verdict is Verdict.BAD_SIGNATURE
