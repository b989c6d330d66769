"""Algorithm 1: the main execution loop of one computer.

Communicate, ExecuteStateMachine, RunControlFunctions; called periodically (50 Hz on the PFC)
with the current time.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from hdrc3_hcsm.control_function import FlagConsumer
from hdrc3_hcsm.event import PostStatus
from hdrc3_hcsm.interpreter import Interpreter, StepResult
from hdrc3_hcsm.transport import SendStatus, Transport


@dataclass(frozen=True)
class CommunicationResult:
    """What Communicate did in one iteration."""

    sent: int
    undeliverable: int
    received: int
    rejected: int


@dataclass(frozen=True)
class IterationResult:
    """One iteration of the main loop."""

    communication: CommunicationResult
    step: StepResult


class MainLoop:
    """One computer's loop: the framework owns the order, the parts stay replaceable."""

    def __init__(
        self,
        interpreter: Interpreter,
        consumers: Sequence[FlagConsumer] = (),
        transport: Transport | None = None,
    ) -> None:
        self.interpreter = interpreter
        self.consumers = tuple(consumers)
        self.transport = transport
        self.iterations = 0

    def communicate(self) -> CommunicationResult:
        """Send the events SENT to other computers; queue received ones as external events."""
        outgoing = self.interpreter.take_outbox()
        if self.transport is None:
            return CommunicationResult(0, len(outgoing), 0, 0)
        sent = sum(self.transport.send(e) is SendStatus.SENT for e in outgoing)
        received = self.transport.receive()
        accepted = sum(self.interpreter.post_wire(e) is PostStatus.ACCEPTED for e in received)
        return CommunicationResult(sent, len(outgoing) - sent, accepted, len(received) - accepted)

    def run_control_functions(self, now: float) -> None:
        """Let every consumer act on this iteration's flags, then unset the flags."""
        interp = self.interpreter
        with interp.memory.lock:
            for consumer in self.consumers:
                consumer.run(interp.flags, interp.memory, now)
        interp.flags.clear()

    def iterate(self, now: float) -> IterationResult:
        """One pass of Algorithm 1 at time ``now`` (seconds)."""
        self.iterations += 1
        communication = self.communicate()
        step = self.interpreter.execute(now)
        self.run_control_functions(now)
        return IterationResult(communication, step)
