"""Planner results as values: status, timed concurrent plan, statistics, IPC formatting."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from enum import Enum


class PlanStatus(Enum):
    """Outcome of one planning call."""

    SOLVED = "solved"
    UNSOLVABLE_PROVEN = "unsolvable"
    TIMEOUT = "timeout"
    INVALID_INPUT = "invalid-input"


@dataclass(frozen=True)
class Occurrence:
    """A timed action occurrence ``[start, end] name(args)`` performed by ``agent``."""

    start: float
    end: float
    name: str
    args: tuple[str, ...]
    agent: str | None = None

    @property
    def duration(self) -> float:
        """``end - start`` in seconds (plan time units)."""
        return self.end - self.start

    @property
    def label(self) -> str:
        """``(name arg ...)``."""
        return "(" + " ".join((self.name, *self.args)) + ")"

    def ipc(self) -> str:
        """``0.000: (fly-to heli1 depot1) [12.000]``."""
        return f"{self.start:.3f}: {self.label} [{self.duration:.3f}]"


@dataclass(frozen=True)
class Statistics:
    """Search effort figures."""

    nodes_expanded: int = 0
    nodes_generated: int = 0
    pruned_by_control: int = 0
    pruned_by_cycle: int = 0
    ground_operators: int = 0
    ground_atoms: int = 0
    grounding_seconds: float = 0.0
    search_seconds: float = 0.0
    cpu_seconds: float = 0.0


class PlanningPhase(Enum):
    """What a planning call is doing (reported to a progress hook)."""

    GROUNDING = "grounding"
    SEARCHING = "searching"


@dataclass(frozen=True)
class PlanningProgress:
    """A planning call's phase and effort so far."""

    phase: PlanningPhase
    stats: Statistics
    elapsed: float
    """Wall seconds since the call began."""

    def line(self) -> str:
        """One line for a status display."""
        s = self.stats
        if self.phase is PlanningPhase.GROUNDING:  # reported once: no clock that stands still
            return f"grounding (reading took {self.elapsed:.1f} s)"
        return (
            f"searching: {s.nodes_expanded:,} expanded, {s.nodes_generated:,} generated, "
            f"{s.pruned_by_control:,} pruned by control rules ({self.elapsed:.1f} s)"
        )


ProgressHook = Callable[[PlanningProgress], None]
"""Called at the start of each phase, then about every :data:`PROGRESS_PERIOD_S` of search."""
PROGRESS_PERIOD_S = 0.25


@dataclass(frozen=True)
class PlanResult:
    """Result of a planning call; ``plan`` is in insertion order, hence sorted by start time."""

    status: PlanStatus
    plan: tuple[Occurrence, ...] = ()
    stats: Statistics = field(default_factory=Statistics)
    reason: str = ""

    @property
    def makespan(self) -> float:
        """Latest end time of the plan (0 for an empty plan)."""
        return max((o.end for o in self.plan), default=0.0)

    @property
    def solved(self) -> bool:
        """Whether a plan was found."""
        return self.status is PlanStatus.SOLVED

    def ipc_lines(self) -> list[str]:
        """The plan in IPC format, one occurrence per line."""
        return [o.ipc() for o in self.plan]

    def summary_lines(self) -> list[str]:
        """Status and statistics as ``; key: value`` comment lines."""
        s = self.stats
        lines = [
            f"; status: {self.status.value}",
            f"; actions: {len(self.plan)}",
            f"; makespan: {self.makespan:.3f}",
            f"; nodes expanded: {s.nodes_expanded}",
            f"; nodes generated: {s.nodes_generated}",
            f"; pruned by control rules: {s.pruned_by_control}",
            f"; pruned by cycle check: {s.pruned_by_cycle}",
            f"; ground operators: {s.ground_operators}",
            f"; grounding time: {s.grounding_seconds:.3f} s",
            f"; search time: {s.search_seconds:.3f} s",
            f"; cpu time: {s.cpu_seconds:.3f} s",
        ]
        if self.reason:
            lines.insert(1, f"; reason: {self.reason}")
        return lines
