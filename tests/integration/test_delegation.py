"""Delegation on the real node chain (issue 17): three agents' gateways, TST managers, aircraft.

One launch of three RMAXes, each with its gateway (constraint server + contractor), TST
manager, path planner and PPC; the test is the ground operator ``gcs``. It checks, over DDS:

- forged, replayed, stale and malformed speech acts are refused by a gateway and answered by
  nothing; a signed act with an unknown performative gets ``not-understood``;
- ``examples/tst/delegate_two_pads.tst`` delegated to any two of the three: each branch goes to
  the aircraft standing on its pad (the auction's lowest bid), both fly it, and it ends done;
- the same mission again while the winner of a branch is cut off right before its award (the
  award is held back, as a partitioned network would, and delivered after its reply-by): the
  operator reallocates to the third aircraft, and the late award is refused, so the cut-off
  agent's TST manager never holds the mission (nothing runs twice);
- the whole mission delegated to uav0 alone: uav0's gateway cannot fly both concurrent branches,
  so it auctions them among itself and its peers, proposes their bids together, awards them when
  awarded and relays their progress; the TST managers of two aircraft run the branches.
"""

from __future__ import annotations

import dataclasses
import hashlib
import hmac
import json
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

import pytest

pytestmark = [pytest.mark.ros, pytest.mark.slow]

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tst"
MISSION = EXAMPLES / "delegate_two_pads.tst"
AGENTS = ("uav0", "uav1", "uav2")
FLIGHT_WAIT_S = 240.0
TIMING_S = 8.0
"""cfp reply-by (award: twice that): the path planner prices flights within it under load."""


class Rig:
    """The ground operator's side of the test: a delegator node and a TST client."""

    def __init__(self, process: Any, keystore: Path) -> None:
        from hdrc3_delegation.authentication import Authenticator
        from hdrc3_delegation.keystore import load_keystore
        from hdrc3_delegation.ros_operator import RosDelegator
        from hdrc3_tst.mission_client import TstClient

        self.process = process
        self.keys = load_keystore(keystore)
        self.operator = RosDelegator(process, Authenticator("gcs", self.keys))
        self.client = TstClient(process)

    def delegation(self, mission: str, responsible: str = "") -> Any:
        """To any two of the agents, or the whole mission to ``responsible``."""
        from hdrc3_delegation.contract_net import Delegation, Timing
        from hdrc3_tst.check import load_file

        tst = load_file(MISSION).tst
        assert tst is not None
        timing = Timing(answer_s=TIMING_S, award_s=2 * TIMING_S, execution_s=FLIGHT_WAIT_S)
        if responsible:  # its own auction of the two branches must fit in the cfp's reply-by
            timing = dataclasses.replace(timing, answer_s=4 * TIMING_S, award_s=4 * TIMING_S)
        text = MISSION.read_text(encoding="utf-8")
        asked, most = ((responsible,), None) if responsible else (AGENTS, 2)
        conversation = f"{mission}@gcs"
        return Delegation(
            "gcs", conversation, mission, text, tst, asked, most, timing, whole=bool(responsible)
        )

    def answers(self, conversation: str) -> list[Any]:
        return [m for m in self.operator.received if m.conversation_id == conversation]


@pytest.fixture
def rig(
    hdrc3_cli: Callable[..., Any], ros_domain: int, tmp_path: Path
) -> Iterator[tuple[Rig, Any]]:
    from hdrc3.safety_pilot import hand_over
    from hdrc3_base.ros_runtime import RosProcess
    from hdrc3_delegation.keystore import write_keystore

    keystore = tmp_path / "keys.toml"
    write_keystore(keystore, ("gcs", *AGENTS))
    launch = hdrc3_cli(
        "launch", "--agents", ",".join(AGENTS), "--world", "revinge", "--speed", "max",
        "--nodes", "world_sim,control_kernel,platform_server,perception_kernel,tst_manager,"
        "path_planner", "--keystore", str(keystore), "--seed", "2",
    )  # fmt: skip
    launch.wait_for_line("READY", timeout=180)
    with RosProcess(domain_id=ros_domain, handle_signals=False) as process:
        rig = Rig(process, keystore)
        try:
            assert rig.operator.wait_for_gateways(AGENTS, 60.0) == ()
            for agent in AGENTS:
                rig.client.follow(agent)  # which TST manager holds and runs which node
                hand_over(process, rig.client.node, agent)
            yield rig, launch
        finally:
            launch.interrupt()
            print("\n".join(launch.lines[-60:]))


def signed_cfp(rig: Rig, conversation: str, now: float, **changes: Any) -> Any:
    from hdrc3_delegation.acl import AclMessage, Performative
    from hdrc3_delegation.contract_net import LANGUAGE, PROTOCOL, content

    body = content(mission="probe", tst=MISSION.read_text(), fixes=[], nodes=["a1", "a2"])
    msg = AclMessage(
        Performative.CFP, "gcs", ("uav0",), body, LANGUAGE, "", PROTOCOL, conversation, "t",
        reply_by=now + 30.0,
    )  # fmt: skip
    return (
        rig.operator.auth.sign(msg, now)
        if not changes
        else dataclasses.replace(rig.operator.auth.sign(msg, now), **changes)
    )


def publish(rig: Rig, messages: Sequence[Any]) -> None:
    from hdrc3_delegation.messages import to_msg
    from hdrc3_delegation.node import ACL_QOS, inbox
    from hdrc3_interfaces.msg import AclMessage as AclMessageMsg

    publisher = rig.operator.node.create_publisher(AclMessageMsg, inbox("uav0"), ACL_QOS)
    for msg in messages:
        publisher.publish(to_msg(msg) if not isinstance(msg, AclMessageMsg) else msg)


@pytest.mark.timeout(900)  # above its own bounded waits: launch 180 s, two flights 240 s each, ...
def test_gateways_refuse_bad_speech_acts_then_delegate_and_reallocate_around_a_partition(
    rig: tuple[Rig, Any],
) -> None:
    from hdrc3_delegation.acl import Performative, canonical_fields
    from hdrc3_delegation.authentication import Authenticator
    from hdrc3_delegation.contract_net import Phase
    from hdrc3_delegation.keystore import Keystore
    from hdrc3_delegation.messages import raw_fields, to_msg

    r, launch = rig
    now = time.time()
    # --- bad input: nothing is answered but the valid cfp (once) and the unknown performative
    valid = signed_cfp(r, "valid", now)
    forged = Authenticator("gcs", Keystore({"gcs": b"f" * 32})).sign(
        dataclasses.replace(valid, nonce="", signature="", conversation_id="forged"), now
    )
    stale = signed_cfp(r, "stale", now - 120.0)
    malformed = to_msg(signed_cfp(r, "malformed", now))
    malformed.sender = "Not An Agent"
    unknown = to_msg(signed_cfp(r, "unknown", now))
    unknown.performative = "beg"
    unknown.signature = ""

    key = r.keys.key("gcs")
    assert key is not None
    unknown.signature = hmac.new(
        key, canonical_fields(raw_fields(unknown)), hashlib.sha256
    ).hexdigest()
    publish(r, [valid, valid, forged, stale, malformed, unknown])
    assert r.process.spin_until(lambda: r.answers("valid") and r.answers("unknown"), 60.0), (
        launch.lines[-20:]
    )
    r.process.spin_until(lambda: False, 2.0)  # late answers to the bad ones would show now
    assert [m.performative for m in r.answers("valid")] == ["propose"], r.answers("valid")[
        0
    ].content
    assert [m.performative for m in r.answers("unknown")] == ["not-understood"]
    for conversation in ("forged", "stale", "malformed"):
        assert r.answers(conversation) == []
    deadline = time.monotonic() + 30.0
    refused = "[uav0.gateway]: refused a speech act from "
    while sum(refused in line for line in launch.lines) < 4:
        assert time.monotonic() < deadline, launch.lines[-20:]
        launch.poll_output(0.5)
    log = "\n".join(launch.lines)
    for why in ("'gcs': replayed", "'gcs': bad_signature", "'gcs': stale", "Agent': malformed"):
        assert refused + "'" + why.lstrip("'") in log or why in log, why
    assert all(k.hex() not in log for k in map(r.keys.key, r.keys.agents) if k)

    # --- delegation to any two of three: each branch to the aircraft on its pad
    first = r.delegation("two-pads")
    r.operator.run(first, FLIGHT_WAIT_S)
    assert first.phase is Phase.DONE, "\n".join(first.events)
    assignment = first.assignment
    assert assignment["a1"] == assignment["a2"] != assignment["b1"] == assignment["b2"]
    agents_used = {assignment["a1"], assignment["b1"]}
    assert len(agents_used) == 2
    assert all(first.node_states[n] == "succeeded" for n in ("a1", "a2", "b1", "b2"))

    # --- the winner of branch a is cut off before its award; the third aircraft takes over
    second = r.delegation("two-pads-cut")
    held: list[Any] = []
    send = r.operator.outbox.send

    def partitioned(messages: Sequence[Any]) -> None:
        for msg in messages:
            awarded = json.loads(msg.content).get("nodes", [])
            first_round = second.round == 0
            if msg.performative is Performative.ACCEPT_PROPOSAL and first_round and "a1" in awarded:
                held.append(msg)
            else:
                send([msg])

    r.operator.outbox.send = partitioned  # type: ignore[method-assign]
    r.operator.run(second, FLIGHT_WAIT_S)
    assert second.phase is Phase.DONE, "\n".join(second.events)
    (cut,) = {m.receivers[0] for m in held}
    assert second.round == 1 and cut in second.excluded
    assert cut not in second.assignment.values()
    before = len(r.operator.received)
    send(held)  # the partition heals: the award arrives after its reply-by
    assert r.process.spin_until(lambda: len(r.operator.received) > before, 30.0)
    late = r.operator.received[before:]
    assert [m.performative for m in late] == ["failure"]
    assert "after its reply-by" in late[0].content
    created = r.client.latest("two-pads-cut")
    assert not any(status.agent == cut for status in created.values()), created

    # --- the whole mission to uav0, which re-delegates a branch it cannot fly at the same time
    third = r.delegation("two-pads-whole", responsible="uav0")
    r.operator.run(third, FLIGHT_WAIT_S)
    assert third.phase is Phase.DONE, "\n".join(third.events)
    assert set(third.assignment.values()) == {"uav0"}, "the operator contracted uav0 only"
    assert third.node_states["m"] == "succeeded"
    assert r.process.spin_until(
        lambda: {"a2", "b2"} <= set(r.client.latest("two-pads-whole")), 30.0
    )
    ran = r.client.latest("two-pads-whole")
    assert ran["a2"].agent != ran["b2"].agent, "the branches ran on two aircraft"
    assert {ran[n].state for n in ("a2", "b2")} == {"succeeded"}
    launch.wait_for_line("two-pads-whole re-delegation: won", timeout=30)  # uav0's auction
