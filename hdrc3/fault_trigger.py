"""Faults injected at a point of a running mission: ``hdrc3 tst run --fault``.

A fault is written ``AGENT:SENSOR:MODE@NODE+SECONDS``: world_sim's ``inject_fault`` switch
(``SimInjectFault``) for ``SENSOR`` of ``AGENT`` in ``MODE`` (a ``MODE_*`` name of the service,
lower case: ``release``, ``hook_fail``, ``drop``, ...), sent ``SECONDS`` of sim time after the TST
node ``NODE`` started running, e.g. ``uav0:hook:release@d/3+6`` (box released in flight six
seconds into the carrying flight). The trigger only injects; what the stack makes of the fault
comes from its own sensors (the scenarios of chapter section 9.3).
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

_FAULT = re.compile(
    r"^(?P<agent>[^:@]+):(?P<sensor>[^:@]+):(?P<mode>[^:@]+)@(?P<node>[^@]+)\+(?P<s>[^+]+)$"
)
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
    node_id: str
    delay_s: float

    def __str__(self) -> str:
        return f"{self.agent}:{self.sensor}:{self.mode}@{self.node_id}+{self.delay_s:g}"


def parse_fault(text: str) -> TimedFault:
    """Parse ``AGENT:SENSOR:MODE@NODE+SECONDS``.

    Raises:
        ConfigError: Malformed text, an unknown mode or a delay that is not a number >= 0.

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
    return TimedFault(match["agent"], match["sensor"], match["mode"], match["node"], delay)


class FaultTrigger:
    """Injects each fault once, ``delay_s`` of sim time after its node started running."""

    def __init__(
        self, node: Node, faults: Sequence[TimedFault], log: Callable[[str], None]
    ) -> None:
        """Subscribe ``/clock`` on ``node``; ``log`` gets one line per injection and answer."""
        self._faults = list(faults)
        self._log = log
        self._armed: dict[int, float] = {}
        self._sent: set[int] = set()
        self._now = math.nan
        self._client = node.create_client(SimInjectFault, INJECT_SERVICE)
        if self._faults:
            node.create_subscription(Clock, "/clock", self._on_clock, 10)

    def on_status(self, msg: Any) -> None:
        """A ``TstNodeStatus``: arm the faults of a node that started running."""
        for i, fault in enumerate(self._faults):
            if (
                i not in self._armed
                and msg.node_id == fault.node_id
                and msg.state == "running"
                and math.isfinite(msg.start)  # begun, not waiting to begin
                and math.isfinite(self._now)
            ):
                self._armed[i] = self._now + fault.delay_s

    def _on_clock(self, msg: Any) -> None:
        self._now = stamp_s(msg.clock)
        for i, due in self._armed.items():
            if i not in self._sent and self._now >= due:
                self._sent.add(i)
                self._inject(self._faults[i])

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
        return [f for i, f in enumerate(self._faults) if i not in self._sent]
