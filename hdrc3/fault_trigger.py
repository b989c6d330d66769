"""Faults injected at a point of a running mission: ``hdrc3 tst run --fault``.

A fault is written ``AGENT:SENSOR:MODE@NODE+SECONDS``: world_sim's ``inject_fault`` switch
(``SimInjectFault``) for ``SENSOR`` of ``AGENT`` in ``MODE`` (a ``MODE_*`` name of the service,
lower case: ``release``, ``hook_fail``, ``drop``, ...), sent ``SECONDS`` of sim time after a TST
node started running. ``NODE`` is either a node id, e.g. ``uav0:hook:release@d/3+6`` (box
released six seconds into node ``d/3``), or ``ACTION#N``: the ``N``-th node of elementary action
``ACTION`` that runs on ``AGENT``, e.g. ``uav0:hook:release@fly-to#2+6``. The second form does
not depend on the plan's node ids, which change when a goal is planned again (a pick-up that
failed and was replanned shifts every later id). The trigger only injects; what the stack makes
of the fault comes from its own sensors (the scenarios of chapter section 9.3).

:class:`FaultSchedule` decides when (pure); :class:`FaultTrigger` wires it to ROS.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from rclpy.node import Node
from rosgraph_msgs.msg import Clock

from hdrc3_base.errors import ConfigError
from hdrc3_base.stamps import stamp_s
from hdrc3_interfaces.srv import SimInjectFault
from hdrc3_tst.model import NodeState

_FAULT = re.compile(
    r"^(?P<agent>[^:@]+):(?P<sensor>[^:@]+):(?P<mode>[^:@]+)@(?P<node>[^@]+)\+(?P<s>[^+]+)$"
)
_NTH = re.compile(r"^(?P<kind>[^#]+)#(?P<n>[0-9]+)$")
INJECT_SERVICE = "/world_sim/inject_fault"


def fault_modes() -> dict[str, int]:
    """Mode names (``MODE_RELEASE`` -> ``release``) and values of ``SimInjectFault``."""
    request = SimInjectFault.Request
    return {
        name[len("MODE_") :].lower(): int(getattr(request, name))
        for name in dir(request)
        if name.startswith("MODE_")
    }


@dataclass(frozen=True, slots=True)
class TimedFault:
    """One fault to inject when a node has run for a while."""

    agent: str
    sensor: str
    mode: str
    node: str
    """A node id, or an elementary action's name when ``nth`` > 0."""
    delay_s: float
    nth: int = 0
    """> 0: the ``nth`` node of action ``node`` to run on ``agent``."""

    def __str__(self) -> str:
        node = f"{self.node}#{self.nth}" if self.nth else self.node
        return f"{self.agent}:{self.sensor}:{self.mode}@{node}+{self.delay_s:g}"


def parse_fault(text: str) -> TimedFault:
    """Parse ``AGENT:SENSOR:MODE@NODE+SECONDS`` (``NODE``: a node id or ``ACTION#N``).

    Raises:
        ConfigError: Malformed text, an unknown mode, ``N`` < 1 or a delay that is not a
            number >= 0.

    """
    match = _FAULT.match(text.strip())
    if match is None:
        raise ConfigError(f"invalid --fault {text!r}: expected AGENT:SENSOR:MODE@NODE+SECONDS")
    modes = fault_modes()
    if match["mode"] not in modes:
        known = ", ".join(sorted(modes))
        raise ConfigError(f"invalid --fault {text!r}: unknown mode {match['mode']!r} ({known})")
    try:
        delay = float(match["s"])
    except ValueError:
        delay = math.nan
    if not (math.isfinite(delay) and delay >= 0):
        raise ConfigError(f"invalid --fault {text!r}: SECONDS must be a number >= 0")
    node, nth = match["node"], 0
    if "#" in node:
        counted = _NTH.match(node)
        if counted is None or int(counted["n"]) < 1:
            raise ConfigError(f"invalid --fault {text!r}: expected NODE or ACTION#N with N >= 1")
        node, nth = counted["kind"], int(counted["n"])
    return TimedFault(match["agent"], match["sensor"], match["mode"], node, delay, nth)


class FaultSchedule:
    """When each fault is due: ``delay_s`` of sim time after its node started running."""

    def __init__(self, faults: Sequence[TimedFault]) -> None:
        self.faults = list(faults)
        self._due: dict[int, float] = {}
        self._sent: set[int] = set()
        self._started: dict[tuple[str, str], set[str]] = {}
        """(agent, action) -> ids of its nodes that have run."""

    def on_status(
        self, agent: str, node_id: str, kind: str, state: str, start: float, now: float
    ) -> None:
        """Node ``node_id`` of ``agent`` is in ``state`` at sim time ``now``: arm its faults.

        ``start`` is the node's T_S (NaN while a running node waits to begin).
        """
        if state != NodeState.RUNNING.value or not (math.isfinite(start) and math.isfinite(now)):
            return
        runs = self._started.setdefault((agent, kind), set())
        if node_id in runs:
            return
        runs.add(node_id)
        for i, fault in enumerate(self.faults):
            if i in self._due:
                continue
            by_id = not fault.nth and fault.node == node_id
            by_count = fault.nth == len(runs) and (fault.agent, fault.node) == (agent, kind)
            if by_id or by_count:
                self._due[i] = now + fault.delay_s

    def due(self, now: float) -> list[TimedFault]:
        """The faults due at sim time ``now`` and not returned before."""
        out = []
        for i, at in self._due.items():
            if i not in self._sent and now >= at:
                self._sent.add(i)
                out.append(self.faults[i])
        return out

    def pending(self) -> list[TimedFault]:
        """The faults not due yet."""
        return [f for i, f in enumerate(self.faults) if i not in self._sent]


class FaultTrigger:
    """Injects each fault of a :class:`FaultSchedule` once, when it is due (``/clock``)."""

    def __init__(
        self, node: Node, faults: Sequence[TimedFault], log: Callable[[str], None]
    ) -> None:
        """Subscribe ``/clock`` on ``node``; ``log`` gets one line per injection and answer."""
        self.schedule = FaultSchedule(faults)
        self._log = log
        self._now = math.nan
        self._client = node.create_client(SimInjectFault, INJECT_SERVICE)
        if faults:
            node.create_subscription(Clock, "/clock", self._on_clock, 10)

    def on_status(self, msg: Any) -> None:
        """A ``TstNodeStatus``: arm the faults of a node that started running."""
        self.schedule.on_status(msg.agent, msg.node_id, msg.kind, msg.state, msg.start, self._now)

    def _on_clock(self, msg: Any) -> None:
        self._now = stamp_s(msg.clock)
        for fault in self.schedule.due(self._now):
            self._inject(fault)

    def _inject(self, fault: TimedFault) -> None:
        request = SimInjectFault.Request(
            agent=fault.agent, sensor=fault.sensor, mode=fault_modes()[fault.mode]
        )
        self._log(f"fault: injecting {fault} at sim time {self._now:.2f} s")
        if not self._client.service_is_ready():
            self._log(f"fault: {INJECT_SERVICE} is not available; {fault} not injected")
            return
        future: Any = self._client.call_async(request)  # rclpy's Future is untyped
        future.add_done_callback(
            lambda f: self._log(f"fault: {fault}: {f.result().result.reason or 'ok'}")
        )

    def not_injected(self) -> list[TimedFault]:
        """The faults not injected (yet)."""
        return self.schedule.pending()
