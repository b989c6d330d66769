"""The executors' platform port over ROS: one agent's Platform Server services and events.

Requests are built from the Platform Server's command registry (``FCL``/``PPCL``: service type
and argument fields), sent asynchronously, and the handle follows the immediate answer and then
the platform events of its command id (a completion may overtake the answer: events are kept by
id until the answer names it). PPCL commands first take control of their payload resource as
``tst_manager``. Stopping an FCL command is ``fcl_cancel`` (the DRC brakes and hovers);
stopping a PTU mode is ``ppcl_ptu_abort``.

Every request carries a fresh ``request_key`` and is sent again every ``RESEND_S`` of wall time
until answered (DDS can lose the first answers to a new client; the server answers a known key
with its first answer, see ``hdrc3_base.answer_memory``). A command still unanswered
after :data:`ANSWER_TIMEOUT_S` fails with that reason.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from geometry_msgs.msg import PointStamped
from rclpy.client import Client
from rclpy.clock import Clock
from rclpy.clock_type import ClockType
from rclpy.node import Node

from hdrc3_base.answer_memory import RESEND_S, new_request_key
from hdrc3_base.ros_runtime import SERVICE_QOS
from hdrc3_base.stamps import stamp_s
from hdrc3_interfaces.msg import (
    FclReturn,
    HelicopterState,
    PlatformEvent,
    PpclReturn,
    RadiationDose,
)
from hdrc3_interfaces.srv import PpclControl, PpclHook
from hdrc3_platform_server.client import event_from_msg
from hdrc3_platform_server.codes import EventKind, FclCommand, PpclCommand, Resource
from hdrc3_platform_server.commands import FCL, PPCL
from hdrc3_platform_server.completion import TERMINAL, CompletionEvent
from hdrc3_platform_server.geo_frame import WorldFrame
from hdrc3_platform_server.hook_api import HookAction
from hdrc3_platform_server.node import EVENT_QOS, STATE_QOS
from hdrc3_tst.platform_port import (
    AnyCommand,
    Command,
    CommandState,
    DoseSample,
    PlatformState,
    Sighting,
)

OWNER = "tst_manager"
EARLY_IDS = 256
"""Command ids whose events are kept until an answer names them (the newest ones)."""
ANSWER_TIMEOUT_S = 30.0
"""Wall time after which an unanswered request ends its command FAILED."""
_FCL_CODES = {FclReturn.FCL_BUSY: "BUSY", FclReturn.FCL_NOT_ACCEPTED: "NOT_ACCEPTED"}
_PPCL_CODES = {
    PpclReturn.PPCL_CONTROL_DENIED: "CONTROL_DENIED",
    PpclReturn.PPCL_NOT_ACCEPTED: "NOT_ACCEPTED",
    PpclReturn.PPCL_BUSY: "BUSY",
}


@dataclass
class _Call:
    """One keyed request on its way: sent again until answered or given up."""

    client: Client
    request: Any
    on_answer: Callable[[Any], None]
    on_silence: Callable[[str], None]
    """Called with the reason when no answer came within :data:`ANSWER_TIMEOUT_S`."""
    first_sent: float
    sent: float
    future: Any  # rclpy's Future is untyped


class RosPlatform:
    """:class:`~hdrc3_tst.platform_port.PlatformPort` of ``agent`` for a node's executor."""

    def __init__(
        self, node: Node, agent: str, frame: WorldFrame, on_change: Callable[[], None]
    ) -> None:
        """Subscribe to the agent's platform events and Data Interface.

        Args:
            node: The node whose executor runs the callbacks.
            agent: Whose Platform Server to use.
            frame: The world's frame (WGS84 <-> local ENU).
            on_change: Called after a command's state changed (the manager ticks at once).
        """
        self._node, self._agent, self._frame, self._on_change = node, agent, frame, on_change
        self._clients: dict[str, Client] = {}
        self._by_id: dict[int, Command] = {}
        self._early: dict[int, list[CompletionEvent]] = {}
        self._stop_on_accept: dict[int, str] = {}
        self._owned: set[Resource] = set()
        self._state: PlatformState | None = None
        self._calls: list[_Call] = []
        node.create_timer(RESEND_S / 4, self._resend, clock=Clock(clock_type=ClockType.STEADY_TIME))
        node.create_subscription(
            PlatformEvent, f"/{agent}/platform_events", self._on_event, EVENT_QOS
        )
        node.create_subscription(
            HelicopterState, f"/{agent}/helicopter_state", self._on_state, STATE_QOS
        )
        self._seen: dict[str, Sighting] = {}
        self._dose: DoseSample | None = None
        node.create_subscription(
            RadiationDose, f"/{agent}/sensors/radiation", self._on_dose, STATE_QOS
        )
        node.create_subscription(
            PointStamped, f"/{agent}/sensors/hook_camera", self._on_seen, STATE_QOS
        )

    # --- PlatformPort ---------------------------------------------------------------------
    def send(self, command: FclCommand | PpclCommand, **args: float) -> Command:
        """Build the request from the registry and call the service."""
        handle = Command(command, dict(args))
        spec = FCL[command] if isinstance(command, FclCommand) else PPCL[command]
        request = spec.service_type().Request()
        for argument in spec.arguments:
            argument.write(request, args[argument.name])
        if isinstance(command, PpclCommand) and PPCL[command].resource not in self._owned:
            self._take_control(PPCL[command].resource, handle, request)
        else:
            self._call(handle, request)
        return handle

    def hook(self, action: HookAction, length: float = 0.0, object_id: str = "") -> Command:
        """Call ``ppcl/hook``; the handle follows its answer and final event."""
        handle = Command(action, {"length": length}, tag=object_id)
        request = PpclHook.Request(action=int(action), length=float(length), object_id=object_id)
        self._call(handle, request)
        return handle

    def stop(self, command: Command, reason: str) -> None:
        """End a command: cancel (FCL) or abort the PTU mode (PPCL); late answers stop too.

        A hook command is only given up: the winch and magnet stay as they are.
        """
        if command.state is CommandState.SENT:
            self._stop_on_accept[id(command)] = reason
            return
        if command.state.ended:
            return
        if isinstance(command.command, HookAction):
            pass
        elif isinstance(command.command, FclCommand):
            self._fire(FclCommand.CANCEL)
        elif PPCL[command.command].resource is Resource.PTU:
            self._fire(PpclCommand.PTU_ABORT)
        command.end(CommandState.FAILED, f"stopped: {reason}")

    def state(self) -> PlatformState | None:
        """The latest Data Interface sample in the local frame."""
        return self._state

    def seen(self, tag: str) -> Sighting | None:
        """The hook camera's latest sighting of ``tag``."""
        return self._seen.get(tag)

    def dose(self) -> DoseSample | None:
        """The radiation detector's latest sample."""
        return self._dose

    def _on_dose(self, msg: Any) -> None:
        if not (math.isfinite(msg.dose_rate) and math.isfinite(msg.integration_time)):
            return
        self._dose = DoseSample(
            msg.dose_rate, int(msg.counts), msg.integration_time, stamp_s(msg.header.stamp)
        )

    def _on_seen(self, msg: Any) -> None:
        p = msg.point
        if not all(math.isfinite(v) for v in (p.x, p.y, p.z)):
            return
        self._seen[str(msg.header.frame_id)] = Sighting((p.x, p.y, p.z), stamp_s(msg.header.stamp))

    # --- calls ----------------------------------------------------------------------------
    def _client(self, srv_type: Any, name: str) -> Client:
        if name not in self._clients:
            self._clients[name] = self._node.create_client(
                srv_type, f"/{self._agent}/{name}", qos_profile=SERVICE_QOS
            )
        return self._clients[name]

    def _service_name(self, command: AnyCommand) -> tuple[Any, str]:
        if isinstance(command, HookAction):
            return PpclHook, "ppcl/hook"
        if isinstance(command, FclCommand):
            return FCL[command].service_type(), f"fcl/{command.value}"
        return PPCL[command].service_type(), f"ppcl/{command.value}"

    def _call(self, handle: Command, request: Any) -> None:
        srv_type, name = self._service_name(handle.command)
        client = self._client(srv_type, name)
        if not client.service_is_ready():
            handle.end(CommandState.FAILED, f"no service /{self._agent}/{name}")
            return
        self._send(
            client, request, lambda answer: self._answered(handle, answer), self._silent(handle)
        )

    def _silent(self, handle: Command) -> Callable[[str], None]:
        def give_up(reason: str) -> None:
            handle.end(CommandState.FAILED, reason)
            self._on_change()

        return give_up

    def _fire(self, command: FclCommand | PpclCommand) -> None:
        """Send a command nobody waits for (cancel, ptu_abort); it is still sent until answered."""
        srv_type, name = self._service_name(command)
        client = self._client(srv_type, name)
        if client.service_is_ready():
            self._send(client, srv_type.Request(), lambda _: None, lambda _: None)

    def _send(
        self,
        client: Client,
        request: Any,
        on_answer: Callable[[Any], None],
        on_silence: Callable[[str], None],
    ) -> None:
        """Send ``request`` with a fresh key; ``_resend`` sends it again until it is answered."""
        request.request_key = new_request_key()
        now = time.monotonic()
        call = _Call(client, request, on_answer, on_silence, now, now, client.call_async(request))
        self._calls.append(call)
        self._watch(call)

    def _watch(self, call: _Call) -> None:
        def answered(future: Any) -> None:
            if call.future is future and call in self._calls:
                self._calls.remove(call)
                call.on_answer(future.result())

        call.future.add_done_callback(answered)

    def _resend(self) -> None:
        now = time.monotonic()
        for call in [c for c in self._calls if now - c.sent >= RESEND_S]:
            call.client.remove_pending_request(call.future)
            if now - call.first_sent >= ANSWER_TIMEOUT_S:
                self._calls.remove(call)
                call.on_silence(f"no answer from {call.client.srv_name} in {ANSWER_TIMEOUT_S:g} s")
                continue
            call.sent, call.future = now, call.client.call_async(call.request)
            self._watch(call)

    def _take_control(self, resource: Resource, handle: Command, request: Any) -> None:
        client = self._client(PpclControl, "ppcl/control")
        if not client.service_is_ready():
            handle.end(CommandState.FAILED, f"no service /{self._agent}/ppcl/control")
            return
        ask = PpclControl.Request(resource=int(resource), request=True, owner=OWNER)

        def granted(answer: Any) -> None:
            result = answer.result
            if result.code != PpclReturn.PPCL_OK:
                handle.end(CommandState.FAILED, f"control of {resource.name}: {result.reason}")
                self._on_change()
                return
            self._owned.add(resource)
            self._call(handle, request)

        self._send(client, ask, granted, self._silent(handle))

    def _answered(self, handle: Command, response: Any) -> None:
        result = response.result
        ok = FclReturn.FCL_OK if isinstance(handle.command, FclCommand) else PpclReturn.PPCL_OK
        if result.code != ok:
            names = _FCL_CODES if isinstance(handle.command, FclCommand) else _PPCL_CODES
            handle.busy = names.get(result.code) == "BUSY"
            handle.end(
                CommandState.FAILED,
                f"refused ({names.get(result.code, result.code)}): {result.reason}",
            )
            self._on_change()
            return
        handle.command_id = int(result.command_id)
        handle.state = CommandState.RUNNING
        self._by_id[handle.command_id] = handle
        for event in self._early.pop(handle.command_id, []):
            self._apply(handle, event)
        reason = self._stop_on_accept.pop(id(handle), None)
        if reason is not None:
            self.stop(handle, reason)
        self._on_change()

    # --- inputs ---------------------------------------------------------------------------
    def _on_event(self, msg: Any) -> None:
        try:
            event = event_from_msg(msg)
        except ValueError:  # an event kind of a newer server: not ours to interpret
            return
        handle = self._by_id.get(event.command_id)
        if handle is None:
            # other clients' commands too: keep only the newest ids (dicts keep insertion order)
            self._early.setdefault(event.command_id, []).append(event)
            while len(self._early) > EARLY_IDS:
                del self._early[next(iter(self._early))]
            return
        self._apply(handle, event)
        self._on_change()

    @staticmethod
    def _apply(handle: Command, event: CompletionEvent) -> None:
        if event.kind is EventKind.SEGMENT_REQUEST:
            handle.segment_requested = True
        elif event.kind in TERMINAL:
            state = (
                CommandState.FINISHED if event.kind is EventKind.FINISHED else CommandState.FAILED
            )
            handle.end(state, f"{event.kind.name} {event.reason}".strip())

    def _on_state(self, msg: Any) -> None:
        position = self._frame.state_enu(msg)
        if position is None:
            return
        east, north, up = position
        self._state = PlatformState(
            east,
            north,
            up,
            bool(msg.on_ground_flag),
            bool(msg.auto_flag),
            str(msg.failsafe_reason),
        )
