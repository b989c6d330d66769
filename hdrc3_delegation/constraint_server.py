"""An agent's constraint server (section 10): whether it can take TST nodes, and at what cost.

A delegation request names a mission (the TST text and the agent bindings made so far) and the
nodes offered to this agent. The server answers from its own knowledge only:

1. **Understanding**: the text must load (parse, resolve, propagate) and the bindings must fit.
2. **Capabilities**: every action of the offered nodes must use only what the platform has
   (``ActionSpec.needs`` of the action registry: flight, camera, PTU, hook).
3. **Time**: the mission's own constraint network (the TST's STN) is extended with this agent's
   schedule: each of its nodes lasts at least what :class:`TaskCoster` prices it at, from where the
   previous one ends; its nodes follow one another in the tree's temporal order (one aircraft
   flies one thing at a time); the first starts after the agent's earlier commitments end. An
   inconsistent network names the constraints that conflict (e.g. the mission's deadline and the
   duration of a scan), and the refusal carries them.
4. **Resources**: the energy of all its commitments must fit its budget.

The bid is the earliest time its last offered node can end (the marginal makespan an auction
compares), with the energy and the slack to the node's latest end. :meth:`commit` checks again
with the final bindings and books the nodes; :meth:`release` gives them back.
"""

from __future__ import annotations

import dataclasses
import enum
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from hdrc3_delegation.task_cost import ActionCost, TaskCoster, Vec3
from hdrc3_tst.actions import ACTIONS, Capability
from hdrc3_tst.check import CheckStatus, load_text
from hdrc3_tst.distribution import parse_fix
from hdrc3_tst.model import Node, NodeKind
from hdrc3_tst.network import FixStatus
from hdrc3_tst.resolver import ResolvedTst, temporal_order
from hdrc3_tst.stn import ORIGIN, Inconsistent
from hdrc3_tst.worlds import WorldCache

DEFAULT_ENERGY_BUDGET_J = 40e6
"""About an hour of RMAX flight at cruise power (12 kW)."""


class EvaluationStatus(enum.Enum):
    """The server's answer to a delegation request."""

    ACCEPTABLE = "acceptable"
    REFUSED = "refused"
    """Understood, but a constraint cannot be met (named in ``constraints``)."""
    NOT_UNDERSTOOD = "not_understood"
    """The mission text, a binding or a node name is malformed."""


@dataclass(frozen=True)
class AgentProfile:
    """What an agent's constraint server knows of its own platform."""

    name: str
    capabilities: frozenset[Capability] = frozenset(Capability)
    energy_budget: float = DEFAULT_ENERGY_BUDGET_J


@dataclass(frozen=True)
class Bid:
    """The agent's price for the offered nodes."""

    completion: float
    """Earliest end of the last offered node, s after the mission starts."""
    duration: float
    """Seconds of the agent's own actions in this mission."""
    energy: float
    """Joules of all the agent's nodes in this mission."""
    slack: float
    """Smallest margin between an offered node's earliest and latest end, s (inf: none)."""


@dataclass(frozen=True)
class Evaluation:
    """Acceptable with a bid, or why not."""

    status: EvaluationStatus
    bid: Bid | None = None
    reason: str = ""
    constraints: tuple[str, ...] = ()
    costs: tuple[ActionCost, ...] = ()
    """What each of the agent's actions in the mission was priced at, in schedule order."""

    @property
    def acceptable(self) -> bool:
        """The agent can take the nodes."""
        return self.status is EvaluationStatus.ACCEPTABLE


@dataclass(frozen=True)
class Commitment:
    """Nodes of one mission this agent has agreed to run."""

    mission: str
    nodes: tuple[str, ...]
    ends_at: float
    """Absolute time (the caller's clock) at which the last node is expected to end."""
    end: Vec3
    energy: float


@dataclass
class ConstraintServer:
    """One agent's schedule and resources, and the reasoning over them."""

    profile: AgentProfile
    coster: TaskCoster
    position: Vec3 | None = None
    """Where the agent is (local ENU m); None until the Data Interface said."""
    commitments: dict[str, Commitment] = field(default_factory=dict)
    worlds: WorldCache = field(default_factory=WorldCache, repr=False)
    """The worlds' facts the missions are resolved against (share one among servers of a
    process: a world is then loaded once, not once per agent)."""
    _loaded: dict[tuple[str, str], ResolvedTst | str] = field(default_factory=dict, repr=False)

    def evaluate(
        self, mission: str, text: str, fixes: Sequence[str], nodes: Sequence[str], now: float
    ) -> Evaluation:
        """Whether this agent can take ``nodes`` of the mission as bound by ``fixes``."""
        return self._plan(mission, text, fixes, nodes, now)[0]

    def commit(
        self, mission: str, text: str, fixes: Sequence[str], nodes: Sequence[str], now: float
    ) -> Evaluation:
        """Evaluate with the final bindings and, if acceptable, book the nodes."""
        evaluation, last = self._plan(mission, text, fixes, nodes, now)
        if evaluation.acceptable and evaluation.bid is not None:
            self.commitments[mission] = Commitment(
                mission,
                tuple(nodes),
                now + evaluation.bid.completion,
                last.end if last is not None else (self.position or (0.0, 0.0, 0.0)),
                evaluation.bid.energy,
            )
        return evaluation

    def release(self, mission: str) -> None:
        """Give the mission's nodes back (done, failed or cancelled)."""
        self.commitments.pop(mission, None)
        self._loaded = {k: v for k, v in self._loaded.items() if k[0] != mission}

    # --- reasoning --------------------------------------------------------------------------

    def load(self, mission: str, text: str) -> ResolvedTst | str:
        """A private copy of the loaded mission, or why it does not load (loaded once)."""
        key = (mission, text)
        if key not in self._loaded:
            result = load_text(text, f"<{mission}>", worlds=self.worlds)
            if result.status is CheckStatus.OK and result.tst is not None:
                self._loaded[key] = result.tst
            else:
                first = result.diagnostics[0] if result.diagnostics else result.status.value
                self._loaded[key] = f"the mission does not load: {first}"
        loaded = self._loaded[key]
        if isinstance(loaded, str):
            return loaded
        # only the network changes (bindings, this agent's schedule): the tree is shared
        return dataclasses.replace(loaded, network=loaded.network.copy())

    def _plan(
        self, mission: str, text: str, fixes: Sequence[str], nodes: Sequence[str], now: float
    ) -> tuple[Evaluation, ActionCost | None]:
        me = self.profile.name
        tst = self.load(mission, text)
        if isinstance(tst, str):
            return Evaluation(EvaluationStatus.NOT_UNDERSTOOD, reason=tst), None
        unknown = [n for n in nodes if n not in tst.tree.nodes]
        if not nodes or unknown:
            what = f"no node {unknown[0]!r}" if unknown else "no node offered"
            return Evaluation(EvaluationStatus.NOT_UNDERSTOOD, reason=what), None
        if self.position is None:
            reason = f"{me} does not know where it is yet (no Data Interface sample)"
            return Evaluation(EvaluationStatus.REFUSED, reason=reason, constraints=(reason,)), None
        refusal = _bind(tst, fixes, nodes, me)
        if refusal is not None:
            return refusal, None
        mine = [n for _, n in tst.tree.walk() if n.kind is NodeKind.ACTION and _held(tst, n, me)]
        refusal = self._capable(mine)
        if refusal is not None:
            return refusal, None
        order = {var: i for i, var in enumerate(temporal_order(tst.tree))}
        mine.sort(key=lambda n: order[n.params["TS"]])
        refusal = self._serial(tst, mine)
        if refusal is not None:
            return refusal, None
        return self._schedule(mission, tst, mine, nodes, now)

    def _serial(self, tst: ResolvedTst, mine: list[Node]) -> Evaluation | None:
        """One aircraft flies (and points its PTU, holds its hook) for one node at a time.

        Two of its nodes under a common concurrent node start together, so it cannot take both.
        """
        for i, a in enumerate(mine):
            for b in mine[i + 1 :]:
                shared = ACTIONS[a.action].needs & ACTIONS[b.action].needs
                lca = _common_ancestor(tst, a.node_id, b.node_id)
                if shared and tst.tree.nodes[lca].kind is NodeKind.CONCURRENT:
                    reason = (
                        f"{self.profile.name} cannot run {a.node_id} and {b.node_id} at once "
                        f"(both under concurrent {lca}, both use its "
                        f"{', '.join(sorted(c.value for c in shared))})"
                    )
                    return Evaluation(
                        EvaluationStatus.REFUSED, reason=reason, constraints=(reason,)
                    )
        return None

    def _capable(self, actions: list[Node]) -> Evaluation | None:
        for node in actions:
            missing = ACTIONS[node.action].needs - self.profile.capabilities
            if missing:
                names = ", ".join(sorted(c.value for c in missing))
                reason = f"{self.profile.name} has no {names} for {node.action} ({node.node_id})"
                return Evaluation(EvaluationStatus.REFUSED, reason=reason, constraints=(reason,))
        return None

    def _schedule(
        self, mission: str, tst: ResolvedTst, mine: list[Node], offered: Sequence[str], now: float
    ) -> tuple[Evaluation, ActionCost | None]:
        me = self.profile.name
        others = [c for m, c in self.commitments.items() if m != mission]
        ready = max((c.ends_at - now for c in others), default=0.0)
        here = max(others, key=lambda c: c.ends_at).end if others else self.position
        assert here is not None, "checked by _plan"
        energy = sum(c.energy for c in others)
        duration = 0.0
        stn = tst.network.stn
        previous: Node | None = None
        last: ActionCost | None = None
        costs: list[ActionCost] = []
        try:
            if mine and ready > 0:
                stn.add(
                    ORIGIN,
                    mine[0].params["TS"],
                    -ready,
                    False,
                    f"{me} is busy until +{ready:.0f} s",
                )
            for node in mine:
                cost = self.coster.cost(tst, node, here)
                if not cost.feasible:
                    reason = f"{me} cannot fly {node.node_id} ({node.action}): {cost.reason}"
                    return Evaluation(
                        EvaluationStatus.REFUSED, reason=reason, constraints=(reason,)
                    ), None
                stn.add(
                    node.params["TS"],
                    node.params["TE"],
                    -cost.duration,
                    False,
                    f"{me} needs {cost.duration:.0f} s for {node.node_id} ({node.action})",
                )
                if previous is not None:
                    stn.add(
                        previous.params["TE"],
                        node.params["TS"],
                        0.0,
                        False,
                        f"{me} flies {previous.node_id} before {node.node_id}",
                    )
                previous, last, here = node, cost, cost.end
                costs.append(cost)
                energy += cost.energy
                duration += cost.duration
        except Inconsistent as exc:
            labels = tuple(dict.fromkeys(e.label for e in exc.cycle if e.label))
            reason = f"{me} cannot meet: " + "; ".join(labels)
            return Evaluation(EvaluationStatus.REFUSED, reason=reason, constraints=labels), None
        if energy > self.profile.energy_budget:
            reason = (
                f"{me} needs {energy / 1e6:.1f} MJ, more than its budget of "
                f"{self.profile.energy_budget / 1e6:.1f} MJ"
            )
            return Evaluation(EvaluationStatus.REFUSED, reason=reason, constraints=(reason,)), None
        ends = [stn.window(tst.tree.nodes[n].params["TE"]) for n in offered]
        completion = max(w.earliest for w in ends)
        slack = min(w.latest - w.earliest for w in ends)
        bid = Bid(completion, duration, energy, slack if math.isfinite(slack) else math.inf)
        return Evaluation(EvaluationStatus.ACCEPTABLE, bid, costs=tuple(costs)), last


def _ancestors(tst: ResolvedTst, node_id: str) -> list[str]:
    """The node and its ancestors, up to the root."""
    out = [node_id]
    parent = tst.tree.nodes[node_id].parent
    while parent is not None:
        out.append(parent.node_id)
        parent = tst.tree.nodes[parent.node_id].parent
    return out


def _common_ancestor(tst: ResolvedTst, a: str, b: str) -> str:
    """The lowest node above (or equal to) both."""
    above_a = set(_ancestors(tst, a))
    return next(n for n in _ancestors(tst, b) if n in above_a)


def _held(tst: ResolvedTst, node: Node, agent: str) -> bool:
    return tst.network.values.get(node.params["P"]) == agent


def _bind(
    tst: ResolvedTst, fixes: Sequence[str], nodes: Sequence[str], me: str
) -> Evaluation | None:
    """Apply the delegator's bindings and give this agent the offered nodes."""
    for text in fixes:
        fix = parse_fix(text)
        if fix is None:
            return Evaluation(EvaluationStatus.NOT_UNDERSTOOD, reason=f"malformed binding {text!r}")
        result = tst.set(fix.node_id, fix.param, fix.value)
        if result.status is not FixStatus.OK:
            status = (
                EvaluationStatus.REFUSED
                if result.status is FixStatus.INCONSISTENT
                else EvaluationStatus.NOT_UNDERSTOOD
            )
            return Evaluation(
                status, reason=f"binding {text}: {result.reason}", constraints=result.conflict
            )
    for node_id in nodes:
        result = tst.set(node_id, "P", me)
        if result.status is not FixStatus.OK:
            reason = f"{me} may not run {node_id}: {result.reason}"
            return Evaluation(EvaluationStatus.REFUSED, reason=reason, constraints=result.conflict)
    return None
