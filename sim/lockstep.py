"""The lockstep barrier between world_sim and the controllers of its aircraft.

World_sim publishes the outputs of tick ``k`` (sensor samples, ground truth, then ``/clock`` =
``t_k``) and may only advance once every *lockstepped* agent has answered with a command stamped
``t_k``. This module holds that bookkeeping without any ROS: which agents are waited for, which
answers arrived for the current tick, and what to do with early, late or duplicate answers.

Which agents are lockstepped:
- **explicit** (a required set was given): exactly those agents, from the first tick on, so a
  run is deterministic from t = 0 (the sim does not advance until each has answered);
- **automatic** (no required set): the agents whose command topic currently has a publisher;
  the set is sampled once per tick before waiting starts, so joining is timing dependent.
Agents not in the set keep flying their latest command (zero-order hold).
"""

from __future__ import annotations

import enum
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Generic, TypeVar

from hdrc3_base.errors import ConfigError

CommandT = TypeVar("CommandT")


class Verdict(enum.Enum):
    """What the barrier did with an offered command."""

    ACCEPTED = "accepted"
    """Stamped for the current tick (lockstepped agent) or latest command of a free agent."""
    STALE = "stale"
    """Stamped for an earlier tick: ignored."""
    EARLY = "early"
    """Stamped for a tick not reached yet: ignored (a controller cannot know the future)."""
    DUPLICATE = "duplicate"
    """A second answer for the same tick: ignored, the first one counts."""
    UNKNOWN_AGENT = "unknown_agent"


@dataclass(frozen=True, slots=True)
class Offer(Generic[CommandT]):
    """A command as received: agent, stamp (ns of sim time) and payload."""

    agent: str
    stamp_ns: int
    command: CommandT


class LockstepBarrier(Generic[CommandT]):
    """Per-tick collection of controller answers."""

    def __init__(self, agents: Iterable[str], required: Iterable[str] = ()) -> None:
        """Barrier for ``agents``; ``required`` non-empty selects the explicit mode."""
        self.agents = tuple(agents)
        self._latest: dict[str, CommandT] = {}
        self.required: frozenset[str] = frozenset()
        self.set_required(required)
        self.tick_ns = 0
        self._waiting: frozenset[str] = self.required
        self._answered: dict[str, CommandT] = {}

    def set_required(self, required: Iterable[str]) -> None:
        """Switch to explicit mode with ``required`` (empty: automatic mode)."""
        wanted = frozenset(required)
        unknown = sorted(wanted - set(self.agents))
        if unknown:
            raise ConfigError(f"lockstep agent(s) {', '.join(unknown)} not simulated")
        self.required = wanted

    @property
    def explicit(self) -> bool:
        """True when a required set is fixed."""
        return bool(self.required)

    def begin_tick(self, tick_ns: int, connected: Iterable[str] = ()) -> frozenset[str]:
        """Start waiting for answers stamped ``tick_ns``; return the agents waited for.

        ``connected`` lists agents whose command topic has a publisher (used in automatic mode).
        """
        self.tick_ns = tick_ns
        self._answered = {}
        if self.explicit:
            self._waiting = self.required
        else:
            self._waiting = frozenset(a for a in connected if a in self.agents)
        return self._waiting

    @property
    def waiting_for(self) -> frozenset[str]:
        """Lockstepped agents of this tick."""
        return self._waiting

    def release(self, agent: str) -> None:
        """Stop waiting for ``agent`` this tick (automatic mode: its controller disappeared)."""
        self._waiting = self._waiting - {agent}

    def offer(self, offer: Offer[CommandT]) -> Verdict:
        """Take one received command."""
        agent = offer.agent
        if agent not in self.agents:
            return Verdict.UNKNOWN_AGENT
        if agent not in self._waiting:
            # free agent: latest command wins, whatever its stamp
            self._latest[agent] = offer.command
            return Verdict.ACCEPTED
        if offer.stamp_ns < self.tick_ns:
            return Verdict.STALE
        if offer.stamp_ns > self.tick_ns:
            return Verdict.EARLY
        if agent in self._answered:
            return Verdict.DUPLICATE
        self._answered[agent] = offer.command
        self._latest[agent] = offer.command
        return Verdict.ACCEPTED

    def ready(self) -> bool:
        """True once every lockstepped agent answered the current tick."""
        return all(a in self._answered for a in self._waiting)

    def missing(self) -> list[str]:
        """Lockstepped agents that have not answered yet."""
        return sorted(a for a in self._waiting if a not in self._answered)

    def commands(self) -> dict[str, CommandT]:
        """Latest command of every agent that ever sent one (to apply for the next tick)."""
        return dict(self._latest)

    def forget(self) -> None:
        """Drop every latest command and answer: after a full reset they must not linger."""
        self._latest.clear()
        self._answered.clear()
