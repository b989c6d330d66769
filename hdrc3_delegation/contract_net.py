"""The delegation protocol (section 10): FIPA contract net with sequential auctions, sans I/O.

**Delegator** (:class:`Delegation`, the ground operator or any agent delegating a TST): the nodes
whose agent ``P`` is open are grouped by their ``P`` variable into units; each unit is auctioned
in the tree's order: ``cfp`` to every candidate (``reply-by`` = now + ``answer_s``), ``propose``
(a :class:`~hdrc3_delegation.constraint_server.Bid`) or ``refuse`` (the violated constraint
named) back. The lowest completion time wins (energy, then the name, break ties); later units are
priced with the earlier winners bound, so a bid is the agent's marginal cost given what it won.
With ``max_agents`` the auction asks only the agents already chosen once that many won. A node
whose ``P`` only composites use runs on the agent of its first action. Then every winner gets an
``accept-proposal`` with the complete bindings and must ``agree`` (its constraint server commits
and its TST manager holds the mission) before ``reply-by``; a refusal, failure or silence
excludes that agent, ``cancel`` goes to the others, and the whole auction runs again without it
(at most ``max_rounds``). Once all agreed, a ``request`` starts the root on its agent; the
contractors ``inform`` of each of their nodes' states and that they are done (or ``failure``).

**Contractor** (:class:`Contractor`): answers ``cfp`` from its constraint server; on
``accept-proposal`` commits and creates the mission on its TST manager through a
:class:`ContractorPort`, unless the award arrived after its ``reply-by``: an award that a partition
delayed is refused, which is why a task reallocated meanwhile is never executed twice.

Both sides are driven by ``handle(msg, now)`` and ``tick(now)`` that return the messages to send
(unsigned; the gateway signs them), so the protocol is tested without ROS and without waiting.
"""

from __future__ import annotations

import enum
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Protocol

from hdrc3_delegation.acl import AclMessage, Performative
from hdrc3_delegation.constraint_server import Bid, ConstraintServer, EvaluationStatus
from hdrc3_tst.model import NodeKind, NodeState, timepoints
from hdrc3_tst.resolver import ResolvedTst

_COORDINATED = (NodeKind.SEQUENCE, NodeKind.CONCURRENT)
"""Composite nodes the delegator itself runs when their children are on several agents."""
_ENDED_BADLY = (NodeState.FAILED.value, NodeState.ABORTED.value)
_FINISHED = frozenset(s.value for s in NodeState if s.finished)
_STARTED = _FINISHED | {NodeState.RUNNING.value, NodeState.PAUSED.value}
_REFUSALS = (Performative.REFUSE, Performative.FAILURE, Performative.NOT_UNDERSTOOD)
ANSWERS = frozenset(
    {
        Performative.AGREE,
        Performative.CONFIRM,
        Performative.DISCONFIRM,
        Performative.INFORM,
        Performative.PROPOSE,
        *_REFUSALS,
    }
)
"""Acts that answer another: never answered themselves (no not-understood ping-pong)."""
LANGUAGE = "hdrc3-delegation+json"
ONTOLOGY = "hdrc3-tst"
PROTOCOL = "fipa-contract-net"
WHOLE = "*"
"""The one unit of a whole-mission delegation (every node to one responsible agent)."""


@dataclass(frozen=True)
class Timing:
    """Deadlines of the protocol, seconds on the agents' clocks."""

    answer_s: float = 5.0
    """cfp -> propose/refuse."""
    award_s: float = 10.0
    """accept-proposal -> agree (the contractor creates the mission on its TST manager)."""
    proposal_valid_s: float = 60.0
    """How long a contractor holds its proposal open."""
    start_s: float = 10.0
    """request (execute) -> agree."""
    execution_s: float = 3600.0
    """Longest wait for the contractors' done after the start."""
    max_rounds: int = 3


class Phase(enum.Enum):
    """Where a delegation is."""

    AUCTION = "auction"
    PRICED = "priced"
    """Every unit has a winner; held until :meth:`Delegation.award` (a contractor's own
    delegation waits for its delegator's award)."""
    AWARD = "award"
    AGREED = "agreed"
    """Every winner agreed; held until :meth:`Delegation.begin`."""
    STARTING = "starting"
    EXECUTING = "executing"
    DONE = "done"
    FAILED = "failed"

    @property
    def finished(self) -> bool:
        """Done or failed."""
        return self in (Phase.DONE, Phase.FAILED)


def content(**values: Any) -> str:
    """Message content in :data:`LANGUAGE`."""
    return json.dumps(values, sort_keys=True, separators=(",", ":"))


def parse_content(msg: AclMessage) -> dict[str, Any] | str:
    """The content as a JSON object, or the reason it is not one of this language."""
    if msg.language != LANGUAGE:
        return f"language {msg.language!r} is not {LANGUAGE}"
    try:
        value = json.loads(msg.content)
    except json.JSONDecodeError as exc:
        return f"content is not JSON: {exc.msg} at column {exc.colno}"
    return value if isinstance(value, dict) else "content is not a JSON object"


@dataclass
class _Unit:
    var: str
    nodes: tuple[str, ...]
    fixed: str = ""
    """The agent the mission itself names for these nodes ("" if open)."""


@dataclass
class _Auction:
    unit: int
    tag: str
    asked: set[str]
    deadline: float
    bids: dict[str, Bid] = field(default_factory=dict)
    refusals: dict[str, str] = field(default_factory=dict)


class Delegation:
    """The delegator's side of one delegated mission."""

    def __init__(
        self,
        me: str,
        conversation: str,
        mission: str,
        text: str,
        tst: ResolvedTst,
        candidates: Sequence[str],
        max_agents: int | None = None,
        timing: Timing | None = None,
        whole: bool = False,
        hold: bool = False,
    ) -> None:
        """``tst`` is the loaded mission (its open ``P`` variables are what is auctioned).

        ``whole``: one agent is asked to take responsibility for the whole mission; it may
        re-delegate parts of it (the cfp says so). ``hold``: stop at :attr:`Phase.PRICED` and
        :attr:`Phase.AGREED` until :meth:`award` and :meth:`begin` (a re-delegating contractor).
        """
        self.me = me
        self.conversation = conversation
        self.mission = mission
        self.text = text
        self.tst = tst
        self.candidates = tuple(candidates)
        self.max_agents = max_agents
        self.timing = timing or Timing()
        self.whole = whole
        self._award_held = self._start_held = hold
        self.phase = Phase.AUCTION
        self.round = 0
        self.reason = ""
        self.excluded: dict[str, str] = {}
        self.events: list[str] = []
        self.messages_sent = 0
        self.units = self._units()
        self.winners: dict[str, str] = {}
        """Unit variable -> agent."""
        self.won: dict[str, Bid] = {}
        """Unit variable -> the winning bid."""
        self.fixes: list[str] = []
        self.agreed: set[str] = set()
        self.done: dict[str, str] = {}
        """Agent -> outcome of all its nodes."""
        self.node_states: dict[str, str] = {}
        self.node_reasons: dict[str, str] = {}
        """Node -> why it failed or was aborted, as its agent reported."""
        self._auction: _Auction | None = None
        self._deadline = math.inf
        self._held_by: dict[str, str] = {}
        """Roots of subtrees one agent holds and runs -> the agent."""
        self._requested: dict[str, float] = {}
        """Subtree roots requested -> deadline of their agree (inf once agreed)."""

    # --- the mission's units ---------------------------------------------------------------
    def _units(self) -> list[_Unit]:
        if self.whole:
            everything = tuple(n.node_id for _, n in self.tst.tree.walk())
            return [_Unit(WHOLE, everything)]
        units: dict[str, _Unit] = {}
        values = self.tst.network.values
        for _, node in self.tst.tree.walk():
            if node.kind is not NodeKind.ACTION:
                continue
            var = node.params["P"]
            unit = units.setdefault(var, _Unit(var, (), str(values.get(var, ""))))
            unit.nodes += (node.node_id,)
        return list(units.values())

    @property
    def assignment(self) -> dict[str, str]:
        """Node id -> agent, for every node decided so far (all of them once awarded)."""
        values = self.tst.network.values
        out: dict[str, str] = {}
        for _, node in self.tst.tree.walk():
            var = WHOLE if self.whole else node.params["P"]
            agent = self.winners.get(var) or values.get(var)
            if agent:
                out[node.node_id] = str(agent)
        return out

    @property
    def bid(self) -> Bid | None:
        """The winners' bids together, None before every unit has one.

        The last completion, the work and the energy summed, the smallest slack.
        """
        if not self.units or len(self.won) < len(self.units):
            return None
        bids = list(self.won.values())
        return Bid(
            max(b.completion for b in bids),
            sum(b.duration for b in bids),
            sum(b.energy for b in bids),
            min(b.slack for b in bids),
        )

    def award(self, now: float) -> list[AclMessage]:
        """Release a held award (every unit priced: the awards go out now, else when they are)."""
        self._award_held = False
        return self._award(now) if self.phase is Phase.PRICED else []

    def begin(self, now: float) -> list[AclMessage]:
        """Release a held start (every winner agreed: execution starts now, else when they do)."""
        self._start_held = False
        return self._start(now) if self.phase is Phase.AGREED else []

    def cancel(self, reason: str) -> list[AclMessage]:
        """End the delegation: every awarded agent is cancelled."""
        if self.phase.finished:
            return []
        return self._fail_and_cancel(reason)

    @property
    def instance(self) -> str:
        """The mission's id on the TST managers in this round (a new id per reallocation)."""
        return self.mission if self.round == 0 else f"{self.mission}-r{self.round}"

    # --- driving ----------------------------------------------------------------------------
    def start(self, now: float) -> list[AclMessage]:
        """Begin the first auction round."""
        if not self.units:
            return self._fail("the mission has no action node to delegate")
        values = self.tst.network.values
        unpriced = [
            n
            for _, n in self.tst.tree.walk()
            if n.kind in (NodeKind.GOAL, NodeKind.FOREACH) and n.params["P"] not in values
        ]
        if unpriced:  # expanded only at run time: no constraint server can price them now
            node = unpriced[0]
            return self._fail(
                f"{node.node_id} is a {node.kind.value} node with an open agent: "
                "delegating goal and foreach nodes is not built (bind its P in the file)"
            )
        return self._next_unit(now)

    def handle(self, msg: AclMessage, now: float) -> list[AclMessage]:
        """An authenticated message of this conversation."""
        if msg.conversation_id != self.conversation or self.phase.finished:
            return []
        body = parse_content(msg)
        if isinstance(body, str):
            return self._send(
                [msg.reply(self.me, Performative.NOT_UNDERSTOOD, content(reason=body))]
            )
        if msg.performative is Performative.INFORM and "node" in body:
            return self._on_progress(msg, body, now)
        auction = self._auction
        if self.phase is Phase.AUCTION and auction is not None and msg.in_reply_to == auction.tag:
            return self._on_bid(auction, msg, body, now)
        if self.phase is Phase.AWARD and msg.in_reply_to == f"award-{self.round}":
            return self._on_award_answer(msg, body, now)
        if self.phase in (Phase.STARTING, Phase.EXECUTING):
            return self._on_execution(msg, body, now)
        self.events.append(f"ignored {msg} in phase {self.phase.value}")
        return []

    def tick(self, now: float) -> list[AclMessage]:
        """Deadlines."""
        if self.phase is Phase.AUCTION and self._auction and now > self._auction.deadline:
            return self._close_auction(self._auction, now)
        if self.phase is Phase.AWARD and now > self._deadline:
            silent = sorted(set(self._award_agents()) - self.agreed)
            reason = "did not agree by reply-by"
            return self._reallocate({a: reason for a in silent}, now)
        late = sorted(n for n, deadline in self._requested.items() if now > deadline)
        if self.phase in (Phase.STARTING, Phase.EXECUTING) and late:
            return self._fail_and_cancel(f"{', '.join(late)} not started by reply-by")
        if self.phase is Phase.EXECUTING and now > self._deadline:
            return self._fail_and_cancel("the contractors did not finish in time")
        return []

    # --- auction ----------------------------------------------------------------------------
    def _eligible(self, unit: _Unit) -> list[str]:
        if unit.fixed:
            return [unit.fixed] if unit.fixed not in self.excluded else []
        chosen = set(self.winners.values())
        pool = [a for a in self.candidates if a not in self.excluded]
        if self.max_agents is not None and len(chosen) >= self.max_agents:
            pool = [a for a in pool if a in chosen]
        return pool

    def _next_unit(self, now: float) -> list[AclMessage]:
        index = sum(u.var in self.winners for u in self.units)
        if index == len(self.units):
            if self._award_held:
                self.phase = Phase.PRICED
                self.events.append("priced: every unit has a winner")
                return []
            return self._award(now)
        unit = self.units[index]
        asked = self._eligible(unit)
        if not asked:
            return self._fail(f"no agent left to ask for {', '.join(unit.nodes)}")
        tag = f"cfp-{self.round}-{index}"
        deadline = now + self.timing.answer_s
        self._auction = _Auction(index, tag, set(asked), deadline)
        cfp = AclMessage(
            Performative.CFP,
            self.me,
            tuple(asked),
            content(
                mission=self.instance,
                tst=self.text,
                fixes=self.fixes,
                nodes=list(unit.nodes),
                **({"whole": True} if self.whole else {}),
            ),
            LANGUAGE,
            ONTOLOGY,
            PROTOCOL,
            self.conversation,
            tag,
            reply_by=deadline,
        )
        self.events.append(f"cfp {', '.join(unit.nodes)} -> {', '.join(asked)}")
        return self._send([cfp])

    def _on_bid(
        self, auction: _Auction, msg: AclMessage, body: dict[str, Any], now: float
    ) -> list[AclMessage]:
        if msg.sender not in auction.asked:
            return []
        if msg.performative is Performative.PROPOSE:
            bid = _bid(body)
            if bid is None:
                auction.refusals[msg.sender] = "malformed proposal"
            else:
                auction.bids[msg.sender] = bid
                parts = body.get("parts")
                via = ""
                if isinstance(parts, dict) and parts:  # a responsible agent's re-delegation
                    via = "; by " + ", ".join(f"{n}={a}" for n, a in sorted(parts.items()))
                self.events.append(
                    f"propose {msg.sender}: done at +{bid.completion:.0f} s, "
                    f"{bid.energy / 1e6:.2f} MJ{via}"
                )
        elif msg.performative in (Performative.REFUSE, Performative.NOT_UNDERSTOOD):
            reason = str(body.get("reason", "no reason given"))
            auction.refusals[msg.sender] = reason
            self.events.append(f"{msg.performative.value} {msg.sender}: {reason}")
        else:
            return []
        if set(auction.bids) | set(auction.refusals) >= auction.asked:
            return self._close_auction(auction, now)
        return []

    def _close_auction(self, auction: _Auction, now: float) -> list[AclMessage]:
        unit = self.units[auction.unit]
        for agent in sorted(auction.asked - set(auction.bids) - set(auction.refusals)):
            self.excluded[agent] = "did not answer a cfp by reply-by"
            self.events.append(f"{agent} did not answer by reply-by: excluded")
        self._auction = None
        if not auction.bids:
            why = "; ".join(f"{a}: {r}" for a, r in sorted(auction.refusals.items()))
            return self._fail(f"nobody can take {', '.join(unit.nodes)} ({why or 'no answer'})")
        winner = min(
            auction.bids, key=lambda a: (auction.bids[a].completion, auction.bids[a].energy, a)
        )
        self.winners[unit.var] = winner
        self.won[unit.var] = auction.bids[winner]
        if not unit.fixed and not self.whole:
            self.fixes.append(f"{unit.nodes[0]}.P={winner}")
        self.events.append(f"won {', '.join(unit.nodes)}: {winner}")
        return self._next_unit(now)

    # --- award ------------------------------------------------------------------------------
    def _award_agents(self) -> list[str]:
        return sorted(set(self.winners.values()))

    def _bind_composites(self) -> None:
        """``P`` of nodes only composites use: the agent of their first action."""
        if self.whole:  # one agent answers for every node: no P is bound here
            return
        values = self.tst.network.values
        for _, node in self.tst.tree.walk():
            var = node.params["P"]
            if var in self.winners or var in values:
                continue
            assignment = self.assignment
            first = next(
                (n for _, n in self.tst.tree.walk(node.node_id) if n.node_id in assignment), None
            )
            if first is not None:
                self.winners[var] = assignment[first.node_id]
                self.fixes.append(f"{node.node_id}.P={self.winners[var]}")

    def _award(self, now: float) -> list[AclMessage]:
        lost = sorted(set(self.winners.values()) & set(self.excluded))
        if lost:  # a winner went silent in a later auction: no award to an unreachable agent
            return self._reallocate({}, now)
        self._bind_composites()
        self.phase = Phase.AWARD
        self._deadline = now + self.timing.award_s
        self.agreed = set()
        assignment = self.assignment
        out = []
        for agent in self._award_agents():
            nodes = [n for n, a in assignment.items() if a == agent]
            out.append(
                AclMessage(
                    Performative.ACCEPT_PROPOSAL,
                    self.me,
                    (agent,),
                    content(
                        mission=self.instance,
                        tst=self.text,
                        fixes=self.fixes,
                        nodes=nodes,
                        **({"whole": True} if self.whole else {}),
                    ),
                    LANGUAGE,
                    ONTOLOGY,
                    PROTOCOL,
                    self.conversation,
                    f"award-{self.round}",
                    reply_by=self._deadline,
                )
            )
        losers = sorted(set(self.candidates) - set(self._award_agents()) - set(self.excluded))
        if losers:
            out.append(
                AclMessage(
                    Performative.REJECT_PROPOSAL,
                    self.me,
                    tuple(losers),
                    content(mission=self.instance),
                    LANGUAGE,
                    ONTOLOGY,
                    PROTOCOL,
                    self.conversation,
                )
            )
        self.events.append("award: " + ", ".join(f"{n}={a}" for n, a in assignment.items()))
        return self._send(out)

    def _on_award_answer(
        self, msg: AclMessage, body: dict[str, Any], now: float
    ) -> list[AclMessage]:
        if msg.sender not in self._award_agents():
            return []
        if msg.performative is Performative.AGREE:
            self.agreed.add(msg.sender)
            self.events.append(f"agree {msg.sender}")
            if self.agreed >= set(self._award_agents()):
                if self._start_held:
                    self.phase = Phase.AGREED
                    self.events.append("agreed: every winner committed")
                    return []
                return self._start(now)
            return []
        if msg.performative not in _REFUSALS:
            return []
        reason = str(body.get("reason", msg.performative.value))
        return self._reallocate({msg.sender: reason}, now)

    def _reallocate(self, failed: dict[str, str], now: float) -> list[AclMessage]:
        for agent, reason in failed.items():
            self.excluded[agent] = reason
            self.events.append(f"{agent} dropped: {reason}")
        out = self._cancel(self._award_agents(), "reallocating")
        self.round += 1
        if self.round >= self.timing.max_rounds:
            self._fail(f"no allocation after {self.round} rounds")
            return out
        self.events.append(f"round {self.round}: reallocating without {', '.join(sorted(failed))}")
        self.phase = Phase.AUCTION
        self.winners = {}
        self.won = {}
        self.fixes = []
        self.agreed = set()
        return out + self._next_unit(now)

    def _cancel(self, agents: Sequence[str], reason: str) -> list[AclMessage]:
        if not agents:
            return []
        return self._send(
            [
                AclMessage(
                    Performative.CANCEL,
                    self.me,
                    tuple(agents),
                    content(mission=self.instance, reason=reason),
                    LANGUAGE,
                    ONTOLOGY,
                    PROTOCOL,
                    self.conversation,
                )
            ]
        )

    # --- execution --------------------------------------------------------------------------
    def _start(self, now: float) -> list[AclMessage]:
        """Run the nodes no single agent holds; ask each agent to run its own subtrees."""
        self.phase = Phase.STARTING
        self._deadline = now + self.timing.start_s
        self._held_by = self._subtree_holders()
        mixed = [
            n
            for _, n in self.tst.tree.walk()
            if n.node_id not in self._held_by
            and n.kind not in _COORDINATED
            and not any(self._under_held(n.node_id, r) for r in self._held_by)
        ]
        if mixed:
            kind = mixed[0].kind.value
            return self._fail_and_cancel(
                f"{mixed[0].node_id} ({kind}) spans agents: only a sequence or concurrent node may"
            )
        return self._drive(now)

    def _subtree_holders(self) -> dict[str, str]:
        """Roots of the largest subtrees whose nodes all one agent holds -> that agent."""
        assignment = self.assignment
        out: dict[str, str] = {}

        def visit(node_id: str) -> None:
            agents = {assignment.get(n.node_id) for _, n in self.tst.tree.walk(node_id)}
            if len(agents) == 1 and None not in agents:
                out[node_id] = assignment[node_id]
                return
            for child in self.tst.tree.nodes[node_id].children:
                visit(child.node_id)

        visit(self.tst.tree.root)
        return out

    def _due(self, root: str) -> bool:
        """Whether the held ``root`` may be requested now (a dispatcher's rule).

        It may once every start and end that the constraints put before its start, of a node
        another agent runs, has happened by that agent's reports. The contractor's replica may
        not hear the other agents (another host): the request tells it that all of them
        happened (``released``). Nodes this delegator runs itself are ordered by its own
        traversal.
        """
        tree = self.tst.tree
        inside = {n.node_id for _, n in tree.walk(root)}
        held = {
            n.node_id for r in self._held_by for _, n in tree.walk(r) if n.node_id not in inside
        }
        events = timepoints(tree.nodes.values())
        for var in self.tst.network.stn.no_later_than(tree.nodes[root].params["TS"]):
            node_id, param = events.get(var, ("", ""))
            if node_id not in held:
                continue
            state = self.node_states.get(node_id, NodeState.CREATED.value)
            happened = _FINISHED if param == "TE" else _STARTED
            if state not in happened:
                return False
        return True

    def _under_held(self, node_id: str, root: str) -> bool:
        return any(n.node_id == node_id for _, n in self.tst.tree.walk(root))

    def _drive(self, now: float) -> list[AclMessage]:
        """Advance the delegator's own nodes; request held subtrees as they become due."""
        out: list[AclMessage] = []
        state = self._advance(self.tst.tree.root, now, out)
        everyone = set(self.done) >= set(self._award_agents())
        if state == NodeState.SUCCEEDED.value and everyone:  # every contractor reported done
            self.phase = Phase.DONE
            self.events.append("delegation done")
        elif state in _ENDED_BADLY:
            failed = [n for n, s in self.node_states.items() if s in _ENDED_BADLY]
            return self._send(out) + self._fail_and_cancel(
                f"{', '.join(failed) or self.tst.tree.root} {state}"
            )
        return self._send(out)

    def _advance(self, node_id: str, now: float, out: list[AclMessage]) -> str:
        """The node's state, after starting what is due (sequence and concurrent semantics)."""
        agent = self._held_by.get(node_id)
        if agent is not None:
            if node_id not in self._requested and not self._due(node_id):
                return NodeState.CREATED.value
            if node_id not in self._requested:
                self._requested[node_id] = now + self.timing.start_s
                self.events.append(f"request {agent}: execute {node_id}")
                out.append(
                    AclMessage(
                        Performative.REQUEST,
                        self.me,
                        (agent,),
                        content(mission=self.instance, execute=node_id),
                        LANGUAGE,
                        ONTOLOGY,
                        PROTOCOL,
                        self.conversation,
                        f"execute-{node_id}",
                        reply_by=self._requested[node_id],
                    )
                )
            state = self.node_states.get(node_id, NodeState.RUNNING.value)
            return NodeState.RUNNING.value if state == NodeState.CREATED.value else state
        children = [c.node_id for c in self.tst.tree.nodes[node_id].children]
        if self.tst.tree.nodes[node_id].kind is NodeKind.SEQUENCE:
            for child in children:
                state = self._advance(child, now, out)
                if state != NodeState.SUCCEEDED.value:
                    return state
            return NodeState.SUCCEEDED.value
        states = [self._advance(child, now, out) for child in children]
        bad = [s for s in states if s in _ENDED_BADLY]
        if bad:
            return bad[0]
        done = all(s == NodeState.SUCCEEDED.value for s in states)
        return NodeState.SUCCEEDED.value if done else NodeState.RUNNING.value

    def _on_execution(self, msg: AclMessage, body: dict[str, Any], now: float) -> list[AclMessage]:
        if msg.sender not in self._award_agents():
            return []
        if msg.performative is Performative.AGREE and msg.in_reply_to.startswith("execute-"):
            self._requested[msg.in_reply_to.removeprefix("execute-")] = math.inf
            self.phase = Phase.EXECUTING
            self._deadline = now + self.timing.execution_s
            self.events.append(f"started by {msg.sender}: {body.get('execute', '')}")
            return []
        if msg.performative is Performative.INFORM and body.get("done"):
            self.done[msg.sender] = str(body.get("outcome", ""))
            self.events.append(f"done {msg.sender}: {self.done[msg.sender]}")
            if self.done[msg.sender] != NodeState.SUCCEEDED.value:
                return self._fail_and_cancel(f"{msg.sender}'s nodes {self.done[msg.sender]}")
            return self._drive(now)
        if msg.performative in _REFUSALS:
            reason = str(body.get("reason", msg.performative.value))
            return self._fail_and_cancel(f"{msg.sender}: {reason}")
        return []

    def _on_progress(self, msg: AclMessage, body: dict[str, Any], now: float) -> list[AclMessage]:
        """A contractor's node changed state (only this round's mission counts)."""
        if body.get("mission") != self.instance or msg.sender not in self._award_agents():
            return []
        node, state = str(body["node"]), str(body.get("state", ""))
        self.node_states[node] = state
        self.node_reasons[node] = str(body.get("reason", ""))
        reason = f": {body['reason']}" if body.get("reason") else ""
        self.events.append(f"{msg.sender}: {node} {state}{reason}")
        if self.phase in (Phase.STARTING, Phase.EXECUTING):
            return self._drive(now)
        return []

    # --- endings ----------------------------------------------------------------------------
    def _fail(self, reason: str) -> list[AclMessage]:
        self.phase = Phase.FAILED
        self.reason = reason
        self.events.append(f"failed: {reason}")
        return []

    def _fail_and_cancel(self, reason: str) -> list[AclMessage]:
        out = self._cancel(self._award_agents(), reason)
        self._fail(reason)
        return out

    def _send(self, messages: list[AclMessage]) -> list[AclMessage]:
        self.messages_sent += len(messages)
        return messages


def _bid(body: dict[str, Any]) -> Bid | None:
    try:
        values = [float(body[k]) for k in ("completion", "duration", "energy", "slack")]
    except (KeyError, TypeError, ValueError):
        return None
    if not all(math.isfinite(v) or v == math.inf for v in values) or values[0] < 0:
        return None
    return Bid(*values)


@dataclass(frozen=True)
class NodeReport:
    """A node's state on a contractor's TST manager, and why it failed or was aborted."""

    state: str
    reason: str = ""


class ContractorPort(Protocol):
    """What a contractor's gateway does on its own platform (the TST manager, the legacy side)."""

    def create(self, mission: str, text: str, fixes: Sequence[str]) -> str:
        """Create the mission replica with these bindings; "" or the reason it failed."""

    def execute(self, mission: str, node_id: str) -> str:
        """Start a node; "" or the reason it failed."""

    def abort(self, mission: str, reason: str) -> None:
        """Abort the mission."""

    def node_states(self, mission: str) -> dict[str, NodeReport]:
        """The latest state of each of the mission's nodes this agent's manager reported."""


@dataclass
class _Contract:
    delegator: str
    conversation: str
    mission: str
    nodes: tuple[str, ...]
    actions: tuple[str, ...]
    """The elementary nodes among them: the contract is done when these are."""
    template: AclMessage
    reported: dict[str, str] = field(default_factory=dict)
    executing: bool = False


@dataclass
class _Responsibility:
    """A whole mission this agent answers for, allocated by its own delegation (section 10)."""

    upward: AclMessage
    """The delegator's cfp: every answer goes to its conversation."""
    mission: str
    nodes: tuple[str, ...]
    nested: Delegation
    expires: float
    """Until the award: when the proposal lapses."""
    proposed: bool = False
    awarded: AclMessage | None = None
    agreed: bool = False
    request: AclMessage | None = None
    relayed: dict[str, str] = field(default_factory=dict)
    logged: int = 0
    """The own delegation's events already copied into the contractor's."""


@dataclass
class Contractor:
    """A contractor's side: bids from the constraint server, commitments, progress reports.

    With ``peers``, a cfp for a whole mission (``whole`` in its content) is not priced by this
    agent alone: it delegates the mission itself, held (:class:`Delegation` with ``hold``), to
    itself and its peers (never back to its delegator). It proposes the winners' bids together
    once every part has a winner, awards them when it is awarded, starts them when asked, and
    informs its delegator of their progress: a network of responsibilities (section 10).
    """

    me: str
    server: ConstraintServer
    port: ContractorPort
    timing: Timing = field(default_factory=Timing)
    peers: tuple[str, ...] = ()
    """Agents this one may re-delegate to."""
    contracts: dict[str, _Contract] = field(default_factory=dict)
    """Mission -> what this agent agreed to."""
    responsible: dict[str, _Responsibility] = field(default_factory=dict)
    """Delegator's conversation -> a whole mission this agent re-delegates."""
    events: list[str] = field(default_factory=list)

    def handle(self, msg: AclMessage, now: float) -> list[AclMessage]:
        """One authenticated message addressed to this agent."""
        nested = next(
            (r for r in self.responsible.values() if r.nested.conversation == msg.conversation_id),
            None,
        )
        if nested is not None and msg.performative in ANSWERS:  # to this agent as delegator
            return nested.nested.handle(msg, now) + self._relay(nested, now)
        duty = self.responsible.get(msg.conversation_id)
        asks = msg.performative is not Performative.CFP and msg.performative not in ANSWERS
        if duty is not None and asks:
            return self._as_responsible(duty, msg, now)
        if msg.performative in ANSWERS:
            self.events.append(f"unexpected {msg} (an answer; not answered)")
            return []
        if msg.protocol != PROTOCOL:
            return [
                _answer(
                    self.me, msg, Performative.NOT_UNDERSTOOD, f"protocol {msg.protocol!r} unknown"
                )
            ]
        body = parse_content(msg)
        if isinstance(body, str):
            return [_answer(self.me, msg, Performative.NOT_UNDERSTOOD, body)]
        handler = {
            Performative.CFP: self._on_cfp,
            Performative.ACCEPT_PROPOSAL: self._on_award,
            Performative.REJECT_PROPOSAL: self._on_reject,
            Performative.CANCEL: self._on_cancel,
            Performative.REQUEST: self._on_request,
        }.get(msg.performative)
        if handler is None:
            return [_not_for_contractors(self.me, msg)]
        return handler(msg, body, now)

    def tick(self, now: float) -> list[AclMessage]:
        """Report the state changes of the nodes this agent holds, and when all are done."""
        out: list[AclMessage] = []
        for key, duty in list(self.responsible.items()):
            if duty.awarded is None and now > duty.expires:
                self.events.append(f"{duty.mission}: proposal lapsed, re-delegation dropped")
                del self.responsible[key]
                out += duty.nested.cancel("the proposal lapsed")
                continue
            out += duty.nested.tick(now) + self._relay(duty, now)
        for mission, contract in list(self.contracts.items()):
            reports = self.port.node_states(mission)
            for node in contract.nodes:
                report = reports.get(node)
                if report is not None and contract.reported.get(node) != report.state:
                    contract.reported[node] = report.state
                    body = content(
                        mission=mission, node=node, state=report.state, reason=report.reason
                    )
                    out.append(_inform(contract, body))
            finished = [contract.reported.get(n, "") for n in contract.actions]
            if all(s and NodeState(s).finished for s in finished):
                failed = [s for s in finished if s != NodeState.SUCCEEDED.value]
                outcome = failed[0] if failed else NodeState.SUCCEEDED.value
                out.append(_inform(contract, content(mission=mission, done=True, outcome=outcome)))
                self.events.append(f"{mission}: done ({outcome})")
                del self.contracts[mission]
                self.server.release(mission)
        return out

    def _fields(self, body: dict[str, Any]) -> tuple[str, str, list[str], list[str]] | str:
        mission, text = body.get("mission"), body.get("tst")
        fixes, nodes = body.get("fixes", []), body.get("nodes")
        if not isinstance(mission, str) or not mission or not isinstance(text, str):
            return "content needs a mission name and its tst text"
        if not isinstance(fixes, list) or not isinstance(nodes, list):
            return "content needs fixes and nodes as lists of text"
        if not all(isinstance(v, str) for v in fixes + nodes):
            return "content needs fixes and nodes as lists of text"
        return mission, text, [str(f) for f in fixes], [str(n) for n in nodes]

    def _on_cfp(self, msg: AclMessage, body: dict[str, Any], now: float) -> list[AclMessage]:
        fields = self._fields(body)
        if isinstance(fields, str):
            return [_answer(self.me, msg, Performative.NOT_UNDERSTOOD, fields)]
        if msg.reply_by and now > msg.reply_by:
            return [_answer(self.me, msg, Performative.REFUSE, "the cfp's reply-by has passed")]
        if body.get("whole") is True and self.peers:
            return self._take_whole(msg, fields, now)
        mission, text, fixes, nodes = fields
        evaluation = self.server.evaluate(mission, text, fixes, nodes, now)
        if evaluation.status is EvaluationStatus.NOT_UNDERSTOOD:
            return [_answer(self.me, msg, Performative.NOT_UNDERSTOOD, evaluation.reason)]
        if not evaluation.acceptable or evaluation.bid is None:
            reply = msg.reply(
                self.me,
                Performative.REFUSE,
                content(
                    nodes=nodes, reason=evaluation.reason, constraints=list(evaluation.constraints)
                ),
            )
            return [reply]
        bid = evaluation.bid
        self.events.append(
            "priced "
            + ", ".join(f"{c.node_id} {c.duration:.0f} s" for c in evaluation.costs)
            + f" from {tuple(round(v, 1) for v in self.server.position or ())}"
        )
        proposal = msg.reply(
            self.me,
            Performative.PROPOSE,
            content(
                nodes=nodes,
                completion=bid.completion,
                duration=bid.duration,
                energy=bid.energy,
                slack=bid.slack if math.isfinite(bid.slack) else 1e18,
            ),
        )
        return [_with_deadline(proposal, now + self.timing.proposal_valid_s)]

    # --- re-delegation (section 10: a network of responsibilities) -----------------------
    def _take_whole(
        self, msg: AclMessage, fields: tuple[str, str, list[str], list[str]], now: float
    ) -> list[AclMessage]:
        """Delegate a whole mission on, held until this agent's own delegator decides."""
        mission, text, _, nodes = fields
        if msg.conversation_id in self.responsible:
            return []  # a cfp sent again: the first one is being answered
        tst = self.server.load(mission, text)
        if isinstance(tst, str):
            return [_answer(self.me, msg, Performative.NOT_UNDERSTOOD, tst)]
        others = [p for p in self.peers if p not in (self.me, msg.sender)]
        nested = Delegation(
            self.me,
            f"{msg.conversation_id}/{self.me}",
            mission,
            text,
            tst,
            (self.me, *others),
            timing=self.timing,
            hold=True,
        )
        window = (msg.reply_by - now) if msg.reply_by else self.timing.answer_s
        # the inner auctions share the delegator's reply-by, one after the other
        nested.timing = replace(self.timing, answer_s=window / (len(nested.units) + 1))
        duty = _Responsibility(
            msg, mission, tuple(nodes), nested, now + window + self.timing.proposal_valid_s
        )
        self.responsible[msg.conversation_id] = duty
        self.events.append(
            f"{mission}: re-delegating the whole mission among {', '.join(nested.candidates)}"
        )
        return nested.start(now) + self._relay(duty, now)

    def _as_responsible(
        self, duty: _Responsibility, msg: AclMessage, now: float
    ) -> list[AclMessage]:
        """The delegator's award, rejection, cancel or start of a mission re-delegated here."""
        nested, key = duty.nested, duty.upward.conversation_id
        if msg.performative is Performative.ACCEPT_PROPOSAL:
            if msg.reply_by and now > msg.reply_by:
                del self.responsible[key]
                late = _answer(self.me, msg, Performative.FAILURE, "the award arrived late")
                return [*nested.cancel("the award arrived late"), late]
            duty.awarded = msg
            if msg.reply_by:  # the parts' agrees must come before this agent's own
                nested.timing = replace(nested.timing, award_s=0.8 * (msg.reply_by - now))
            return nested.award(now) + self._relay(duty, now)
        if msg.performative is Performative.REQUEST:
            node = parse_content(msg)
            execute = node.get("execute") if isinstance(node, dict) else None
            if execute not in duty.nodes or not duty.agreed:
                return [_answer(self.me, msg, Performative.REFUSE, f"{execute!r} is not held")]
            duty.request = msg
            agree = msg.reply(
                self.me, Performative.AGREE, content(mission=duty.mission, execute=execute)
            )
            return [*nested.begin(now), agree, *self._relay(duty, now)]
        if msg.performative in (Performative.REJECT_PROPOSAL, Performative.CANCEL):
            del self.responsible[key]
            self.events.append(f"{duty.mission}: {msg.performative.value} by {msg.sender}")
            out = nested.cancel(f"{msg.performative.value} by {msg.sender}")
            if msg.performative is Performative.CANCEL:
                out.append(
                    msg.reply(
                        self.me, Performative.INFORM, content(mission=duty.mission, cancelled=True)
                    )
                )
            return out
        return [_not_for_contractors(self.me, msg)]

    def _relay(self, duty: _Responsibility, now: float) -> list[AclMessage]:
        """Tell the delegator what the re-delegated mission's own delegation reached."""
        nested, upward = duty.nested, duty.upward
        self.events += [f"{duty.mission} re-delegation: {e}" for e in nested.events[duty.logged :]]
        duty.logged = len(nested.events)
        out = self._relay_states(duty)
        if nested.phase is Phase.FAILED:
            del self.responsible[upward.conversation_id]
            why = f"re-delegation failed: {nested.reason}"
            self.events.append(f"{duty.mission}: {why}")
            asked = duty.request or duty.awarded or (None if duty.proposed else upward)
            failure = Performative.REFUSE if asked is upward else Performative.FAILURE
            return out + ([_answer(self.me, asked, failure, why)] if asked is not None else [])
        bid = nested.bid
        if not duty.proposed and nested.phase is Phase.PRICED and bid is not None:
            duty.proposed = True
            duty.expires = now + self.timing.proposal_valid_s
            proposal = upward.reply(
                self.me,
                Performative.PROPOSE,
                content(
                    nodes=list(duty.nodes),
                    completion=bid.completion,
                    duration=bid.duration,
                    energy=bid.energy,
                    slack=bid.slack if math.isfinite(bid.slack) else 1e18,
                    parts=nested.assignment,
                ),
            )
            out.append(_with_deadline(proposal, duty.expires))
        awarded = duty.awarded
        if awarded is not None and not duty.agreed and nested.phase is Phase.AGREED:
            duty.agreed = True
            agree = content(mission=duty.mission, nodes=list(duty.nodes))
            out.append(awarded.reply(self.me, Performative.AGREE, agree))
        if awarded is not None and nested.phase is Phase.DONE:
            del self.responsible[upward.conversation_id]
            self.events.append(f"{duty.mission}: done (re-delegated)")
            done = content(mission=duty.mission, done=True, outcome=NodeState.SUCCEEDED.value)
            out.append(replace(awarded.reply(self.me, Performative.INFORM), content=done))
        return out

    def _relay_states(self, duty: _Responsibility) -> list[AclMessage]:
        """Inform the delegator of every node state the parts reported since the last time."""
        nested, awarded = duty.nested, duty.awarded
        if awarded is None or duty.request is None:
            return []
        states = dict(nested.node_states)
        if nested.phase is Phase.DONE:  # the spanning root, run by this agent's own delegation
            states[nested.tst.tree.root] = NodeState.SUCCEEDED.value
        template, out = awarded.reply(self.me, Performative.INFORM), []
        for node, state in states.items():
            if duty.relayed.get(node) != state:
                duty.relayed[node] = state
                reason = nested.node_reasons.get(node, "")
                body = content(mission=duty.mission, node=node, state=state, reason=reason)
                out.append(replace(template, content=body))
        return out

    def _on_award(self, msg: AclMessage, body: dict[str, Any], now: float) -> list[AclMessage]:
        fields = self._fields(body)
        if isinstance(fields, str):
            return [_answer(self.me, msg, Performative.NOT_UNDERSTOOD, fields)]
        mission, text, fixes, nodes = fields
        if body.get("whole") is True and self.peers:  # its responsibility lapsed or never was
            why = "no proposal of this agent for the whole mission stands"
            return [_answer(self.me, msg, Performative.FAILURE, why)]
        if msg.reply_by and now > msg.reply_by:
            self.events.append(f"{mission}: award arrived {now - msg.reply_by:.1f} s late, refused")
            return [
                _answer(self.me, msg, Performative.FAILURE, "the award arrived after its reply-by")
            ]
        held = self.contracts.get(mission)
        if held is not None and held.conversation == msg.conversation_id:
            return [
                msg.reply(
                    self.me, Performative.AGREE, content(mission=mission, nodes=list(held.nodes))
                )
            ]
        actions = [n for n in nodes if self._is_action(mission, text, n)]
        evaluation = self.server.commit(mission, text, fixes, actions or nodes, now)
        if not evaluation.acceptable:
            return [_answer(self.me, msg, Performative.REFUSE, evaluation.reason)]
        reason = self.port.create(mission, text, fixes)
        if reason:
            self.server.release(mission)
            return [
                _answer(self.me, msg, Performative.FAILURE, f"the TST manager refused: {reason}")
            ]
        template = msg.reply(self.me, Performative.INFORM)
        self.contracts[mission] = _Contract(
            msg.sender, msg.conversation_id, mission, tuple(nodes), tuple(actions), template
        )
        self.events.append(f"{mission}: committed to {', '.join(nodes)}")
        return [msg.reply(self.me, Performative.AGREE, content(mission=mission, nodes=nodes))]

    def _is_action(self, mission: str, text: str, node_id: str) -> bool:
        tst = self.server.load(mission, text)
        return not isinstance(tst, str) and (
            node_id in tst.tree.nodes and tst.tree.nodes[node_id].kind is NodeKind.ACTION
        )

    def _on_reject(self, msg: AclMessage, body: dict[str, Any], now: float) -> list[AclMessage]:
        self.events.append(f"{body.get('mission', '?')}: proposal rejected by {msg.sender}")
        return []

    def _on_cancel(self, msg: AclMessage, body: dict[str, Any], now: float) -> list[AclMessage]:
        mission = str(body.get("mission", ""))
        contract = self.contracts.pop(mission, None)
        if contract is None or contract.conversation != msg.conversation_id:
            if contract is not None:
                self.contracts[mission] = contract
            return []
        self.port.abort(mission, f"cancelled by {msg.sender}: {body.get('reason', '')}")
        self.server.release(mission)
        self.events.append(f"{mission}: cancelled by {msg.sender}")
        return [msg.reply(self.me, Performative.INFORM, content(mission=mission, cancelled=True))]

    def _on_request(self, msg: AclMessage, body: dict[str, Any], now: float) -> list[AclMessage]:
        mission, node = str(body.get("mission", "")), body.get("execute")
        contract = self.contracts.get(mission)
        if contract is None or contract.conversation != msg.conversation_id:
            return [_answer(self.me, msg, Performative.REFUSE, f"no commitment to {mission!r}")]
        if not isinstance(node, str) or node not in contract.nodes:
            return [
                _answer(
                    self.me, msg, Performative.REFUSE, f"{node!r} is not a node this agent holds"
                )
            ]
        if msg.reply_by and now > msg.reply_by:
            return [
                _answer(
                    self.me, msg, Performative.FAILURE, "the request arrived after its reply-by"
                )
            ]
        reason = self.port.execute(mission, node)
        if reason:
            return [_answer(self.me, msg, Performative.FAILURE, reason)]
        contract.executing = True
        return [msg.reply(self.me, Performative.AGREE, content(mission=mission, execute=node))]


def _answer(me: str, msg: AclMessage, performative: Performative, reason: str) -> AclMessage:
    reply = msg.reply(me, performative, content(reason=reason))
    if reply.language != LANGUAGE:
        reply = replace(reply, language=LANGUAGE, ontology=ONTOLOGY, protocol=PROTOCOL)
    return reply


def _not_for_contractors(me: str, msg: AclMessage) -> AclMessage:
    """``not-understood``: a performative a contractor never receives in this protocol."""
    reason = f"{msg.performative.value} is not part of {PROTOCOL} for a contractor"
    return _answer(me, msg, Performative.NOT_UNDERSTOOD, reason)


def _inform(contract: _Contract, body: str) -> AclMessage:
    return replace(contract.template, content=body)


def _with_deadline(msg: AclMessage, reply_by: float) -> AclMessage:
    return replace(msg, reply_by=reply_by)
