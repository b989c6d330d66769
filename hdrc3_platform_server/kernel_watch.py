"""Watching the launcher's reports for the death of this agent's kernels (PFC, PPC).

A command running on a control kernel that dies is lost: the restarted kernel starts without
it (``docs/realtime_events.md``, "Restarts"). The restarted kernel's first report tells the
Platform Server so, but only once it is up again and discovered, seconds later. The launcher
sees the exit at once (``/hdrc3/launch_status``), so the server ends the command then, with the
exit in the reason; the later notice of the new incarnation finds nothing left to end.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

COMPUTERS = {"control_kernel": "PFC", "perception_kernel": "PPC"}
"""Node name -> the kernel (computer) it runs."""

NAMES = {"PFC": "control kernel (PFC)", "PPC": "perception kernel (PPC)"}
"""How a reason names each kernel."""


@dataclass(frozen=True, slots=True)
class ProcessReport:
    """One supervised process as the launcher reports it."""

    node_name: str
    """Fully qualified node name (``/uav0/control_kernel``)."""
    alive: bool
    """Starting or running (not waiting for a restart, given up or stopped)."""
    restarts: int
    exit_code: int


@dataclass(frozen=True, slots=True)
class KernelExit:
    """A kernel process of this agent died."""

    computer: str
    reason: str


class KernelWatch:
    """Deaths of one agent's kernel processes, each reported once."""

    def __init__(self, agent: str) -> None:
        """Watch the kernels in ``/<agent>/``."""
        self._prefix = f"/{agent}/"
        self._deaths: dict[str, int] = {}
        """Node -> deaths seen so far (restarts done, plus one while it is down)."""

    def update(self, reports: Iterable[ProcessReport]) -> list[KernelExit]:
        """Take one launcher snapshot; the kernels that died since the last one.

        The first snapshot only tells where things stand: a death before it is not news.
        """
        exits: list[KernelExit] = []
        for report in reports:
            name = report.node_name.removeprefix(self._prefix)
            computer = COMPUTERS.get(name) if report.node_name.startswith(self._prefix) else None
            if computer is None:
                continue
            deaths = report.restarts + (0 if report.alive else 1)
            seen = self._deaths.get(name)
            self._deaths[name] = max(deaths, seen or 0)
            if seen is not None and deaths > seen:
                how = f"exited (code {report.exit_code})" if not report.alive else "restarted"
                exits.append(KernelExit(computer, f"{NAMES[computer]} {how}: the command was lost"))
        return exits
