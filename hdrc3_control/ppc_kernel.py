"""The PPC's kernel (perception_kernel): its HCSM interpreter and the payload control modes.

``automata_ppc/ppc.hcsm`` receives the PPCL events from the DRC and raises action flags; this
module is the flag consumer (RunControlFunctions of Algorithm 1) that engages the pan-tilt modes
(:mod:`hdrc3_control.ppc_modes`), the camera parameters, the laser configuration and the image
processing function (the saliency pipeline, the landing pad's pose or the colour tracker, each a
node of its own, runs while it is engaged; the colour tracker from the seed pixel of
``ppcl_ip_color_tracker(x, y)``), and the source of the conditions (on target, zoom reached,
timeouts). While the pad's pose or the colour tracker runs, the PTU keeps the pad or the tracked
object in the image's centre (:mod:`hdrc3_control.visual_servoing`) instead of following its
commanded mode. The PFC's landing engages the pad's pose itself (``Pad-Est-Engage-EV``, released
by ``Pad-Est-Release-EV``; the Ip automaton's ``Ip-Land-Est-ST``) when the PPC reports it
:attr:`PadVision.READY`; :attr:`PpcKernel.pad_vision` is that report, from the devices the node
sees (:meth:`PpcKernel.devices`) and the images the pad pipeline processed
(:meth:`PpcKernel.pad_image`). :meth:`PpcKernel.step` is one iteration, driven by the PTU angle
reports (25 Hz of sim time) in the node.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from importlib import resources
from pathlib import Path

from hdrc3_control.event_codec import Decoded, decode, encode
from hdrc3_control.ppc_hardware import PtuLimits
from hdrc3_control.ppc_modes import (
    ImageProcessing,
    PadVision,
    Pose,
    PtuController,
    PtuMode,
    on_target,
    pad_vision,
)
from hdrc3_control.visual_servoing import PtuServo, Sighting
from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.interpreter import Interpreter
from hdrc3_hcsm.loader import load_file
from hdrc3_hcsm.main_loop import MainLoop
from hdrc3_hcsm.memory import ActionFlags, MemoryBank
from hdrc3_hcsm.tables import compile_model
from hdrc3_hcsm.transport import Transport

ZOOM_TOLERANCE = 0.02
SERVOED = frozenset({ImageProcessing.STATE_ESTIMATION, ImageProcessing.COLOR_TRACKER})
"""Image processing functions whose sightings the PTU servoes on."""


@dataclass(frozen=True, slots=True)
class ColorSeed:
    """The colour tracker's seed: ``ppcl_ip_color_tracker(x, y)`` received at PPC ``time``."""

    x: float
    """Pixel column, from the left of the colour image."""
    y: float
    """Pixel row, from the top."""
    time: float


@dataclass(frozen=True, slots=True)
class CameraSetting:
    """What the PPC commands one camera to do (CameraCommand)."""

    camera_id: int
    zoom: float = 0.0
    auto_exposure: bool = True
    iris: float = 0.5
    shutter: float = 0.01


@dataclass(frozen=True, slots=True)
class LaserSetting:
    """What the PPC commands the laser range finder to do (LaserCommand)."""

    angular_resolution: float = 1.0
    distance_resolution: float = 0.01
    rotation_speed: float = 0.0
    hold_angle: bool = False
    rotation_angle: float = 0.0
    collect: bool = False


@dataclass
class PpcOutputs:
    """One iteration's commands to the devices; ``None``/empty when unchanged."""

    ptu: tuple[float, float] | None = None
    cameras: list[CameraSetting] = field(default_factory=list)
    laser: LaserSetting | None = None
    image_processing: ImageProcessing | None = None
    color_seed: ColorSeed | None = None
    """A new colour tracker seed (each ``ppcl_ip_color_tracker`` command, also the same pixel)."""
    pad_vision: PadVision | None = None
    """The PPC's changed :class:`PadVision` state."""


def model_path() -> Path:
    """Location of the PPC automata file."""
    return Path(str(resources.files("hdrc3_control.automata_ppc") / "ppc.hcsm"))


class PpcKernel:
    """HCSM interpreter + payload modes of the perception kernel."""

    def __init__(
        self,
        transport: Transport | None,
        limits: PtuLimits | None = None,
        *,
        ptu_timeout: float = 10.0,
        zoom_timeout: float = 10.0,
        image_timeout: float = 2.0,
    ) -> None:
        self.ptu = PtuController(limits)
        self.servo = PtuServo(limits)
        """Keeps the pad (state estimation, §5.4) or the colour tracker's object centred (§6.1)."""
        self._sightings: list[tuple[ImageProcessing, Sighting]] = []
        self._servoed: tuple[ImageProcessing, ColorSeed | None] | None = None
        """The object the servo follows (function, seed); a change restarts it."""
        self.ptu_timeout = ptu_timeout
        self.zoom_timeout = zoom_timeout
        self.now = 0.0
        self.pose: Pose | None = None
        self.measured: tuple[float, float] | None = None
        self.zooms: dict[int, float] = {}
        self.cameras = {cam: CameraSetting(cam) for cam in (0, 1)}
        self.laser = LaserSetting()
        self.image_processing = ImageProcessing.IDLE
        self.color_seed: ColorSeed | None = None
        """The colour tracker's seed while colour tracking is engaged."""
        self.image_timeout = image_timeout
        """Pad images processed within this count as running state estimation, s."""
        self.camera = False
        self.pipeline = False
        self._pad_image_at = -math.inf
        self.pad_vision = PadVision.NONE
        """What the PPC can do for a vision landing (:func:`pad_vision`)."""
        self._ptu_since = 0.0
        self._zoom_since = 0.0
        self._zoom_camera = 0
        self._outputs = PpcOutputs()
        conditions = {
            "Ptu-On-Target-CO": self._on_target,
            "Ptu-Timeout-CO": lambda: self.now - self._ptu_since > self.ptu_timeout,
            "Zoom-Reached-CO": self._zoom_reached,
            "Zoom-Timeout-CO": lambda: self.now - self._zoom_since > self.zoom_timeout,
        }
        model = compile_model(load_file(model_path()))
        self.interpreter = Interpreter(model, conditions)
        self.transport = transport
        self.loop = MainLoop(self.interpreter, (self,), None)
        self._started: WireEvent | None = WireEvent(
            model.events.id_of("PPC-Started-EV"), "PPC-Started-EV", b"", "PPC", "DRC"
        )
        """Sent with the first step: the DRC hears a restarted PPC's incarnation before any
        reply and ends the commands the old PPC had pending (docs/realtime_events.md)."""

    # --- conditions -----------------------------------------------------------------------
    def _on_target(self) -> bool:
        sp = self.ptu.update(self.pose)
        return sp is not None and self.measured is not None and on_target(self.measured, sp)

    def _zoom_reached(self) -> bool:
        zoom = self.zooms.get(self._zoom_camera)
        target = self.cameras[self._zoom_camera].zoom
        return zoom is not None and abs(zoom - target) <= ZOOM_TOLERANCE

    # --- flag consumer (RunControlFunctions) ----------------------------------------------
    def run(self, flags: ActionFlags, memory: MemoryBank, now: float) -> None:
        """Engage what this iteration's flags ask for."""
        out = self._outputs

        def read(slot: str, count: int) -> Decoded | None:
            decoded = decode(memory.read(slot), count)
            return decoded if decoded.ok else None

        if flags.is_set("Ptu-Stop-AC"):
            self.ptu.reset()
        if flags.is_set("Ptu-Turn-AC") and (p := read("Ptu-Cmd-DO", 2)):
            self.ptu.turn_to(*p.values)
            self._ptu_started(memory, p.command_id, now)
        if flags.is_set("Ptu-Look-AC") and (p := read("Ptu-Cmd-DO", 3)):
            x, y, z = p.values
            self.ptu.look_at((x, y, z))
            self._ptu_started(memory, p.command_id, now)
        if flags.is_set("Zoom-AC") and (p := read("Zoom-DO", 2)):
            cam = int(p.values[0])
            self._set_camera(cam, zoom=p.values[1])
            self._zoom_camera, self._zoom_since = cam, now
            reason = f"camera {cam} did not reach zoom {p.values[1]:g} in {self.zoom_timeout:g} s"
            memory.write("Zoom-Fail-DO", encode(p.command_id, (), reason))
        for flag, name in (
            ("Cam-Exposure-AC", "auto_exposure"),
            ("Cam-Iris-AC", "iris"),
            ("Cam-Shutter-AC", "shutter"),
        ):
            if flags.is_set(flag) and (p := read("Cam-DO", 2)):
                value: float | bool = p.values[1] if name != "auto_exposure" else p.values[1] > 0.5
                self._set_camera(int(p.values[0]), **{name: value})
        laser = self.laser
        if flags.is_set("Laser-Angular-AC") and (p := read("Laser-DO", 1)):
            laser = replace(laser, angular_resolution=p.values[0])
        if flags.is_set("Laser-Distance-AC") and (p := read("Laser-DO", 1)):
            laser = replace(laser, distance_resolution=p.values[0])
        if flags.is_set("Laser-Speed-AC") and (p := read("Laser-DO", 1)):
            laser = replace(laser, rotation_speed=p.values[0], hold_angle=False)
        if flags.is_set("Laser-Angle-AC") and (p := read("Laser-DO", 1)):
            laser = replace(laser, rotation_angle=p.values[0], rotation_speed=0.0, hold_angle=True)
        if flags.is_set("Laser-Start-AC"):
            laser = replace(laser, collect=True)
        if flags.is_set("Laser-Stop-AC"):
            laser = replace(laser, collect=False)
        if laser != self.laser:
            self.laser = laser
            out.laser = laser
        ip = self.image_processing
        if flags.is_set("Ip-Saliency-AC"):
            ip = ImageProcessing.SALIENCY
        if flags.is_set("Ip-State-Est-AC"):
            ip = ImageProcessing.STATE_ESTIMATION
        # the DRC checked the pixel; a malformed payload (never sent) engages nothing
        if flags.is_set("Ip-Tracker-AC") and (p := read("Ip-DO", 2)):
            ip = ImageProcessing.COLOR_TRACKER
            self.color_seed = out.color_seed = ColorSeed(p.values[0], p.values[1], now)
        if flags.is_set("Ip-Stop-AC"):
            ip = ImageProcessing.IDLE
        if ip is not ImageProcessing.COLOR_TRACKER:
            self.color_seed = None
        if ip is not self.image_processing:
            self.image_processing = out.image_processing = ip
            self._pad_image_at = -math.inf  # only images of this engagement count

    def _ptu_started(self, memory: MemoryBank, command_id: int, now: float) -> None:
        self._ptu_since = now
        reason = f"the PTU did not reach its set-point within {self.ptu_timeout:g} s"
        memory.write("Ptu-Fail-DO", encode(command_id, (), reason))

    def _set_camera(self, camera_id: int, **changes: float | bool) -> None:
        if camera_id not in self.cameras:
            return
        setting = replace(self.cameras[camera_id], **changes)  # type: ignore[arg-type]
        self.cameras[camera_id] = setting
        self._outputs.cameras.append(setting)

    # --- iteration ------------------------------------------------------------------------
    def see(self, source: ImageProcessing, sighting: Sighting) -> None:
        """Where one image of ``source`` saw its object (taken in the next iteration).

        Only the engaged function's sightings count; the colour tracker's only from images
        taken since its seed (older ones show the previous object).
        """
        self._sightings.append((source, sighting))

    def devices(self, camera: bool, pipeline: bool) -> None:
        """Whether a colour camera publishes images and the pad pose pipeline is up."""
        self.camera, self.pipeline = camera, pipeline

    def pad_image(self, time: float) -> None:
        """The pad pose pipeline processed an image (its result arrived at PPC ``time``)."""
        if math.isfinite(time):
            self._pad_image_at = max(self._pad_image_at, time)

    def ptu_reading(self, time: float, pan: float, tilt: float) -> None:
        """A PTU read-out with its sensor time (the servo aims from the image's angles)."""
        self.servo.reading(time, pan, tilt)

    def step(
        self,
        now: float,
        pose: Pose | None = None,
        measured: tuple[float, float] | None = None,
        zooms: dict[int, float] | None = None,
    ) -> PpcOutputs:
        """One iteration at PPC time ``now`` with the latest pose, PTU angles and zooms."""
        self.now = now
        if pose is not None:
            self.pose = pose
        if measured is not None and all(math.isfinite(a) for a in measured):
            self.measured = measured
        if zooms:
            self.zooms.update(zooms)
        self._outputs = PpcOutputs()
        self._send()
        received = self.transport.receive() if self.transport is not None else []
        # One macro step per received command: parameter commands share a memory slot, so two
        # of them in one step would leave the consumer only the last payload.
        for event in received:
            self.interpreter.post_wire(event)
            self.interpreter.execute(now)
            self.loop.run_control_functions(now)
        if not received:
            self.interpreter.execute(now)
            self.loop.run_control_functions(now)
        out = self._outputs
        out.ptu = self.ptu.update(self.pose)
        tracking = self._track(now)
        if tracking is not None:
            out.ptu = tracking
        age = now - self._pad_image_at
        state = pad_vision(
            self.camera, self.pipeline, self.image_processing, age, self.image_timeout
        )
        if state is not self.pad_vision:
            self.pad_vision = out.pad_vision = state
        self._send()  # replies leave in this iteration, not the next
        return out

    def _track(self, now: float) -> tuple[float, float] | None:
        """The servo's set-point while the pad's pose or the colour tracker runs (else None)."""
        sightings, self._sightings = self._sightings, []
        ip, seed = self.image_processing, self.color_seed
        if ip not in SERVOED:
            self.servo.reset()
            self._servoed = None
            return None
        if self._servoed is not None and self._servoed != (ip, seed):
            self.servo.restart(now)  # another object: hold still until it is seen
        self._servoed = (ip, seed)
        for source, sighting in sightings:
            if source is ip and (seed is None or sighting.time >= seed.time):
                self.servo.see(sighting)
        return self.servo.update(now)

    @property
    def tracking(self) -> bool:
        """True while the PTU follows the pad or the tracked object, not its commanded mode."""
        return self.servo.setpoint is not None

    def _send(self) -> None:
        outgoing = self.interpreter.take_outbox()
        if self._started is not None:
            outgoing.insert(0, self._started)
            self._started = None
        if self.transport is not None:
            for event in outgoing:
                self.transport.send(event)

    @property
    def mode(self) -> PtuMode:
        """Active pan-tilt mode."""
        return self.ptu.mode
