"""The PPCL half of the command layer (chapter section 6.2.3).

Exclusive control: ``request``/``release`` per resource (PTU, camera, image processing, laser)
with an owner name; control of the PTU, camera and image processing is denied while a
vision-based landing runs (its control mode handles them). A mode or parameter command needs its
resource held (the service requests carry no caller identity, so any caller may use a held
resource; ownership keeps two executors from taking the same resource). An accepted command
answers ``PPCL_OK`` with an id; the PPC reports the mode reaching its target (finished) or failing;
a newer command for the same mode replaces an older one (cancelled). No queue, no busy: payload
modes replace each other as the chapter's pan-tilt modes do. The image processing commands
(``ppcl_ip_saliency``, ``ppcl_ip_state_estimation``, ``ppcl_ip_color_tracker(x, y)`` with the
seed pixel, ``ppcl_ip_abort``) finish when the PPC has engaged (or stopped) the function.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from hdrc3_control.event_codec import decode, encode
from hdrc3_control.ppc_hardware import CAMERAS, PtuLimits
from hdrc3_hcsm.event import WireEvent
from hdrc3_platform_server import limits as check
from hdrc3_platform_server.codes import EventKind, PpclCode, PpclCommand, PtuActivity, Resource
from hdrc3_platform_server.commands import PPCL
from hdrc3_platform_server.completion import CompletionEvent, EventSink
from hdrc3_platform_server.drc import DrcKernel
from hdrc3_platform_server.fcl_api import IdSource
from hdrc3_platform_server.geo_frame import WorldFrame

LANDING_CONTROLLED = frozenset({Resource.PTU, Resource.CAMERA, Resource.IMAGE_PROCESSING})
RESTARTED_PPC = "perception kernel (PPC) restarted: the command was lost"
"""Reason of the terminal event of a PPCL command the PPC forgot in a restart."""


@dataclass(frozen=True, slots=True)
class PpclAnswer:
    """Immediate answer of one PPCL call (PpclReturn)."""

    code: PpclCode
    reason: str = ""
    command_id: int = 0


@dataclass(frozen=True, slots=True)
class CameraInfo:
    """Intrinsics of one camera at its current zoom (ppcl_get_camera_info)."""

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float
    zoom: float
    hfov: float


class PayloadCommandLayer:
    """Validates, answers and forwards PPCL commands; turns PPC replies into PlatformEvents."""

    def __init__(
        self,
        kernel: DrcKernel,
        frame: WorldFrame,
        sink: EventSink,
        ids: IdSource,
        landing: Callable[[], bool],
        ptu: PtuLimits | None = None,
    ) -> None:
        self.kernel = kernel
        self.frame = frame
        self.sink = sink
        self.ids = ids
        self.landing = landing
        """True while a vision-based landing runs (fcl_land in progress)."""
        self.ptu = ptu or PtuLimits()
        self.owners: dict[Resource, str] = {}
        self.activity = PtuActivity.IDLE
        self.pending: dict[int, tuple[PpclCommand, str]] = {}
        """Accepted, not yet finished commands: id -> (command, mode key)."""
        kernel.listeners.append(self)

    def _emit(self, command_id: int, command: PpclCommand, kind: EventKind, reason: str) -> None:
        self.sink(CompletionEvent(command_id, command.label, kind, reason, self.kernel.status.now))

    # --- ownership ------------------------------------------------------------------------
    def control(self, resource: int, request: bool, owner: str) -> PpclAnswer:
        """ppcl_request_*_control / ppcl_release_*_control (synchronous: no events)."""
        try:
            res = Resource(resource)
        except ValueError:
            return PpclAnswer(PpclCode.NOT_ACCEPTED, f"unknown resource {resource} (0..3)")
        name = res.name.lower()
        holder = self.owners.get(res)
        bad = check.owner(owner, required=request)
        if bad:
            return PpclAnswer(PpclCode.NOT_ACCEPTED, bad)
        if request:
            if res in LANDING_CONTROLLED and self.landing():
                return PpclAnswer(
                    PpclCode.CONTROL_DENIED, f"vision-based landing in progress controls the {name}"
                )
            if holder is not None and holder != owner:
                return PpclAnswer(PpclCode.CONTROL_DENIED, f"{name} is controlled by {holder!r}")
            self.owners[res] = owner
            return PpclAnswer(PpclCode.OK)
        if holder is None:
            return PpclAnswer(PpclCode.OK, f"{name} was not controlled by anyone")
        if owner and holder != owner:
            return PpclAnswer(
                PpclCode.NOT_ACCEPTED, f"{name} is controlled by {holder!r}, not {owner!r}"
            )
        del self.owners[res]
        return PpclAnswer(PpclCode.OK)

    # --- queries --------------------------------------------------------------------------
    def camera_info(self, camera_id: int) -> tuple[PpclAnswer, CameraInfo | None]:
        """Intrinsics at the camera's current zoom (from the PPC's camera state)."""
        bad = check.camera(camera_id)
        if bad:
            return PpclAnswer(PpclCode.NOT_ACCEPTED, bad), None
        spec = CAMERAS[camera_id]
        sample = self.kernel.status.cameras.get(camera_id)
        zoom = sample.zoom if sample is not None else 0.0
        f = spec.focal(zoom)
        info = CameraInfo(
            spec.width,
            spec.height,
            f,
            f,
            spec.width / 2.0,
            spec.height / 2.0,
            zoom,
            spec.hfov(zoom),
        )
        return PpclAnswer(PpclCode.OK), info

    # --- mode and parameter commands ------------------------------------------------------
    def submit(self, command: PpclCommand, args: Sequence[float], now: float) -> PpclAnswer:
        """Answer one PPCL mode/parameter call at DRC time ``now``."""
        spec = PPCL[command]
        values, reason = check.arguments(command.label, spec.names, args)
        if reason is None:
            numbers, reason = self._arguments(command, values)
        if reason is not None:
            return PpclAnswer(PpclCode.NOT_ACCEPTED, reason)
        res = spec.resource
        name = res.name.lower()
        if res in LANDING_CONTROLLED and self.landing():
            return PpclAnswer(
                PpclCode.CONTROL_DENIED, f"vision-based landing in progress controls the {name}"
            )
        if res not in self.owners:
            return PpclAnswer(
                PpclCode.NOT_ACCEPTED,
                f"request control of the {name} first (ppcl_request_{name}_control)",
            )
        if not self.kernel.status.ppc_fresh():
            return PpclAnswer(
                PpclCode.NOT_ACCEPTED,
                "no data from the perception kernel (PPC): is perception_kernel running?",
            )
        cid = self.ids.next()
        key = spec.mode_key(values)
        for old, (old_command, old_key) in list(self.pending.items()):
            if old_key == key:
                del self.pending[old]
                self._emit(
                    old,
                    old_command,
                    EventKind.CANCELLED,
                    f"replaced by {command.label} (command {cid})",
                )
        self.pending[cid] = (command, key)
        if spec.activity is not None:
            self.activity = spec.activity
        self.kernel.post(spec.api_event, encode(cid, numbers))
        self.kernel.step(now)
        return PpclAnswer(PpclCode.OK, "", cid)

    def _arguments(
        self, command: PpclCommand, a: tuple[float, ...]
    ) -> tuple[tuple[float, ...], str | None]:
        """Command-specific checks of finite arguments; the numbers for the PPC."""
        c = PpclCommand
        if command is c.TURN_TO:
            pan, tilt = a
            return (pan, tilt), check.pan_tilt(self.ptu, pan, tilt)
        if command is c.LOOK_AT:
            lon, lat, has_alt, alt = a
            bad = (
                check.wgs84(lon, lat)
                or check.flag("has_altitude", has_alt)
                or check.altitude(self.frame, alt, "look-at altitude")
            )
            if bad:
                return (), bad
            e, n, _ = self.frame.to_enu(lon, lat, self.frame.altitude)
            if not self.frame.inside(e, n):
                return (
                    (),
                    f"look-at point ({e:.0f} m east, {n:.0f} m north) is far outside the world",
                )
            u = (alt - self.frame.altitude) if has_alt else self.frame.ground_up(e, n)
            return (e, n, u), None
        if command is c.ZOOM:
            camera, value = a
            return (camera, value), check.camera(camera) or check.unit_interval("zoom", value)
        if command is c.EXPOSURE:
            camera, auto = a
            return (camera, auto), check.camera(camera) or check.flag("auto_exposure", auto)
        if command in (c.IRIS, c.SHUTTER):
            camera, value = a
            bad = check.camera(camera) or (
                check.unit_interval("iris", value) if command is c.IRIS else check.shutter(value)
            )
            return (camera, value), bad
        if command is c.LASER_ANGULAR_RESOLUTION:
            return a, check.laser_angular(a[0])
        if command is c.LASER_DISTANCE_RESOLUTION:
            return a, check.laser_distance(a[0])
        if command is c.LASER_ROTATION_SPEED:
            return a, check.laser_speed(a[0])
        if command is c.LASER_ROTATION_ANGLE:
            bad = check.angle("rotation_angle", a[0])
            return ((a[0] % math.tau,) if not bad else ()), bad
        if command is c.IP_COLOR_TRACKER:
            x, y = a
            return (x, y), check.pixel(x, y)
        return (), None

    # --- replies from the PPC -------------------------------------------------------------
    def on_wire(self, event: WireEvent, now: float) -> None:
        """Finish or fail the pending command the PPC reports on."""
        if event.name not in ("PPCL-Finished-EV", "PPCL-Failed-EV"):
            return
        # a short payload decodes to id 0, which is never pending; an invalid UTF-8 reason is
        # still shown (replaced bytes)
        p = decode(event.data, 0, with_reason=True)
        entry = self.pending.pop(p.command_id, None)
        if entry is None:
            return
        command, _ = entry
        if event.name == "PPCL-Finished-EV":
            self._emit(p.command_id, command, EventKind.FINISHED, "")
        else:
            self._emit(p.command_id, command, EventKind.FAILED, p.reason or "failed in the PPC")

    def after_step(self, now: float) -> None:
        """Nothing to do: PPCL outcomes come with the events."""

    def on_world_reset(self, reason: str, now: float) -> None:
        """The simulated world started over: every pending command ends FAILED."""
        self._fail_pending(f"simulation reset: {reason}")

    def on_kernel_exit(self, reason: str, now: float) -> None:
        """The PPC process died (the launcher saw it): every pending command ends FAILED now."""
        self._fail_pending(reason)

    def _fail_pending(self, reason: str) -> None:
        """End every pending command FAILED once; the PTU is idle."""
        for cid, (command, _) in sorted(self.pending.items()):
            self._emit(cid, command, EventKind.FAILED, reason)
        self.pending.clear()
        self.activity = PtuActivity.IDLE

    def on_restart(self, computer: str, now: float) -> None:
        """A restarted PPC forgot its pending commands: each ends FAILED once, the PTU is idle.

        The new PPC announces itself (``PPC-Started-EV``) with its first step, before any reply,
        so the notice comes before the new PPC can finish a command sent to it.
        """
        if computer == "PPC":
            self._fail_pending(RESTARTED_PPC)
