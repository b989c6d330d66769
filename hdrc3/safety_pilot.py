"""The simulated safety pilot: the RC transmitter of `world_sim` (engine and mode switches).

On the real RMAX a safety pilot starts the engine and hands over with the manual/autonomous
switch (§6.1.1); in simulation `world_sim` offers the transmitter as `/<agent>/rc/set`.
"""

from __future__ import annotations

import enum

from rclpy.node import Node

from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import SERVICE_WAIT_S, RosProcess
from hdrc3_interfaces.msg import PfcState, SimResult
from hdrc3_interfaces.srv import SimSetRc


class Switch(enum.Enum):
    """A position of one RC switch, or KEEP to leave it."""

    KEEP = "keep"
    MANUAL = "manual"
    AUTONOMOUS = "autonomous"
    ON = "on"
    OFF = "off"


_MODE = {
    Switch.KEEP: SimSetRc.Request.KEEP,
    Switch.MANUAL: SimSetRc.Request.MODE_MANUAL,
    Switch.AUTONOMOUS: SimSetRc.Request.MODE_AUTONOMOUS,
}
_ENGINE = {
    Switch.KEEP: SimSetRc.Request.KEEP,
    Switch.ON: SimSetRc.Request.ENGINE_ON,
    Switch.OFF: SimSetRc.Request.ENGINE_OFF,
}


def set_rc(
    process: RosProcess, node: Node, agent: str, mode: Switch, engine: Switch, timeout_s: float
) -> tuple[int, str]:
    """Flip the simulated transmitter's switches; return world_sim's (code, reason).

    Raises:
        ConfigError: A switch position that does not belong to the switch, or no `world_sim`
            serving the agent.
    """
    if mode not in _MODE or engine not in _ENGINE:
        raise ConfigError(f"invalid RC switch positions: mode {mode.value}, engine {engine.value}")
    client = node.create_client(SimSetRc, f"/{agent}/rc/set")
    if not process.spin_until(client.service_is_ready, SERVICE_WAIT_S):
        raise ConfigError(
            f"no service /{agent}/rc/set: unknown agent {agent!r} or world_sim is not running "
            "(same ROS_DOMAIN_ID?)"
        )
    # switch positions are idempotent: sent again until answered (DDS can drop the first
    # answers to a new client, hdrc3_base.ros_runtime.first_answer)
    request = SimSetRc.Request(mode=_MODE[mode], engine=_ENGINE[engine])
    response = process.first_answer(client, request, timeout_s)
    if response is None:
        raise ConfigError(f"/{agent}/rc/set did not answer within {timeout_s} s")
    result: SimResult = response.result
    return int(result.code), str(result.reason)


def hand_over(process: RosProcess, node: Node, agent: str, timeout_s: float = 60.0) -> None:
    """Act as the safety pilot: engine on, switch to autonomous, until the PFC takes over (§6.1.1).

    Returns once the control kernel reports autonomous ground idle: until then the DRC refuses a
    take-off ("RC switch manual") or the PFC rejects it (its Mode Switch is still leaving Start).

    Raises:
        ConfigError: world_sim refused the switches, or the PFC did not take over in time.
    """
    code, reason = set_rc(process, node, agent, Switch.AUTONOMOUS, Switch.ON, timeout_s=10.0)
    if code != SimResult.OK:
        raise ConfigError(f"the simulated RC of {agent} refused engine on + autonomous: {reason}")
    ready: list[bool] = []

    def on_pfc(msg: PfcState) -> None:
        ready.append(bool(msg.auto_flag) and msg.mode == PfcState.MODE_GROUND_IDLE)

    subscription = node.create_subscription(PfcState, f"/{agent}/pfc/state", on_pfc, 10)
    try:
        if not process.spin_until(lambda: bool(ready) and ready[-1], timeout_s):
            raise ConfigError(
                f"the control kernel of {agent} did not report autonomous ground idle "
                f"in {timeout_s:g} s"
            )
    finally:
        node.destroy_subscription(subscription)
