"""Steps every RMAX executor is made of: wait for a command, be airborne, fly straight.

Generators an executor's :meth:`~hdrc3_tst.executor.ActionExecutor.run` delegates to with
``yield from``; each returns the step's outcome as a :class:`~hdrc3_tst.executor.Status`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Generator

from hdrc3_platform_server.codes import FclCommand
from hdrc3_tst.executor import (
    COMMAND_BOUND_S,
    SUCCEEDED,
    ActionContext,
    Status,
    failed,
    flight_bound,
)
from hdrc3_tst.platform_port import Command, CommandState

Steps = Generator[None, None, Status]
DATA_TIMEOUT_S = 10.0
"""Mission seconds an executor waits for the first Data Interface sample."""
NOT_ACCEPTED_IN = "not accepted in Mode-Switch:"
"""How the PFC's mode switch (``hdrc3_control/automata/mode_switch.hcsm``) refuses an event."""
SETTLING_STATES = ("Stop-Ctrl-ST", "Braking-ST", "Wait-Hover-ST", "Stabilizing-ST")
"""Its states between a stopped command and a stable hover: a flight is accepted after them."""
SETTLE_RETRY_S = 1.0
SETTLE_WAIT_S = 20.0
"""Mission seconds a flight refused while the PFC settles into a hover is retried."""


def finish(
    ctx: ActionContext,
    command: Command,
    within: float = COMMAND_BOUND_S,
    until: Callable[[Command], bool] = lambda c: c.state.ended,
) -> Steps:
    """Wait until ``until(command)`` (default: it ended); its outcome as a Status.

    A command that neither ends nor reaches ``until`` within ``within`` mission seconds is
    stopped (the Platform Server owes it an outcome: this keeps a mission from waiting forever
    when it never comes) and fails the node.
    """
    deadline = ctx.now + within
    while not (until(command) or command.state.ended):
        if ctx.now > deadline:
            ctx.platform.stop(command, f"no outcome in {within:.0f} s")
            return failed(f"{command.label}: no outcome in {within:.0f} s")
        yield
    if command.state is CommandState.FAILED:
        return failed(f"{command.label}: {command.reason}")
    return SUCCEEDED


def airborne(ctx: ActionContext) -> Steps:
    """Succeed when the aircraft flies; take off first when it is on the ground."""
    while (state := ctx.state()) is None:
        if ctx.elapsed > DATA_TIMEOUT_S:
            return failed(f"no Data Interface sample from {ctx.agent} in {DATA_TIMEOUT_S:g} s")
        yield
    if state.failsafe:
        return failed(f"{ctx.agent} is in a navigation failsafe: {state.failsafe}")
    if not state.on_ground:
        return SUCCEEDED
    return (yield from finish(ctx, ctx.send(FclCommand.TAKEOFF)))


def settling(command: Command) -> bool:
    """Whether the PFC refused ``command`` only because it is still braking into a hover."""
    return (
        command.state is CommandState.FAILED
        and NOT_ACCEPTED_IN in command.reason
        and any(state in command.reason for state in SETTLING_STATES)
    )


def fly_to(ctx: ActionContext, point: tuple[float, ...], speed: float) -> Steps:
    """Straight flight to a local ENU point, hovering there at the end.

    A flight the PFC refuses while it still brakes into a hover (after a cancel or an
    emergency brake, e.g. a recovery's first step) is sent again every ``SETTLE_RETRY_S``
    mission seconds for up to ``SETTLE_WAIT_S``.
    """
    lon, lat, alt = ctx.frame.to_wgs84(point[0], point[1], point[2])
    state = ctx.state()
    length = math.dist(point, (state.east, state.north, state.up)) if state else 0.0
    give_up = ctx.now + SETTLE_WAIT_S
    while True:
        command = ctx.send(
            FclCommand.TRAJ3D_FLYTO, longitude=lon, latitude=lat, altitude=alt, velocity=speed
        )
        outcome = yield from finish(ctx, command, flight_bound(length, speed))
        if not settling(command) or ctx.now > give_up:
            return outcome
        again = ctx.now + SETTLE_RETRY_S
        while ctx.now < again:
            yield
