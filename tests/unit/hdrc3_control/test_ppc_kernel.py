"""The PPC kernel: PPCL events in, device commands and completion events out."""

from __future__ import annotations

import math

import pytest

from hdrc3_control.event_codec import decode, encode
from hdrc3_control.ppc_kernel import ColorSeed, PpcKernel, model_path
from hdrc3_control.ppc_modes import ImageProcessing, PadVision, Pose, PtuMode
from hdrc3_control.visual_servoing import Sighting
from hdrc3_hcsm.event import WireEvent
from hdrc3_hcsm.loader import load_file
from hdrc3_hcsm.tables import compile_model
from hdrc3_hcsm.transport import LoopbackNetwork, LoopbackTransport

EVENTS = compile_model(load_file(model_path())).events
POSE = Pose((0.0, 0.0, 20.0), 0.0, 0.0, 0.0)
IP = ImageProcessing
ENGAGE = {
    IP.SALIENCY: ("PPCL-IP-Saliency-EV", ()),
    IP.STATE_ESTIMATION: ("PPCL-IP-State-Est-EV", ()),
    IP.COLOR_TRACKER: ("PPCL-IP-Tracker-EV", (320.0, 200.0)),
}
"""The PPCL event (and its numbers) that engages each image processing function."""


class Bench:
    """A PPC kernel with a simulated PTU (60 deg/s) and zoom motor, driven at 25 Hz."""

    def __init__(self, ptu_timeout: float = 10.0) -> None:
        net = LoopbackNetwork()
        self.drc: LoopbackTransport = net.endpoint("DRC")
        self.pfc: LoopbackTransport = net.endpoint("PFC")
        self.kernel = PpcKernel(net.endpoint("PPC"), ptu_timeout=ptu_timeout)
        self.t = 0.0
        self.pan = self.tilt = self.zoom = 0.0
        self.powered = True
        self.replies: list[tuple[str, int, str]] = []
        self.seeds: list[ColorSeed] = []
        self.functions: list[ImageProcessing] = []
        """The published image processing functions and colour tracker seeds, in order."""
        self.pad_vision: list[PadVision] = []
        """The published pad vision reports, in order."""

    def send(self, name: str, cid: int, *numbers: float) -> None:
        self.drc.send(WireEvent(EVENTS.id_of(name), name, encode(cid, numbers), "DRC", "PPC"))

    def from_pfc(self, name: str) -> None:
        """An event of the PFC's Pad Vision automaton (no payload)."""
        self.pfc.send(WireEvent(EVENTS.id_of(name), name, b"", "PFC", "PPC"))

    def run(self, seconds: float) -> None:
        for _ in range(round(seconds / 0.04)):
            self.t += 0.04
            self.kernel.ptu_reading(self.t, self.pan, self.tilt)
            out = self.kernel.step(self.t, POSE, (self.pan, self.tilt), {0: self.zoom, 1: 0.0})
            if out.ptu is not None and self.powered:
                step = math.radians(60.0) * 0.04
                self.pan += max(-step, min(step, out.ptu[0] - self.pan))
                self.tilt += max(-step, min(step, out.ptu[1] - self.tilt))
            if out.color_seed is not None:
                self.seeds.append(out.color_seed)
            if out.image_processing is not None:
                self.functions.append(out.image_processing)
            if out.pad_vision is not None:
                self.pad_vision.append(out.pad_vision)
            for cam in out.cameras:
                if cam.camera_id == 0:
                    self.zoom = cam.zoom
            for event in self.drc.receive():
                p = decode(event.data, 0, with_reason=True)
                self.replies.append((event.name, p.command_id, p.reason))

    def engage(self, function: ImageProcessing, cid: int) -> None:
        """Send the command that engages ``function`` and run one iteration."""
        name, numbers = ENGAGE[function]
        self.send(name, cid, *numbers)
        self.run(0.04)

    def sight(self, source: ImageProcessing, direction: tuple[float, float, float]) -> None:
        """An image of ``source`` taken now sees its object in ``direction`` (optical frame)."""
        self.kernel.see(source, Sighting(self.t, direction))

    def outcome(self, cid: int) -> str | None:
        return next((name for name, c, _ in self.replies if c == cid), None)


def test_turn_to_moves_the_ptu_and_finishes_on_target() -> None:
    b = Bench()
    b.send("PPCL-Turn-To-EV", 7, 0.0, math.radians(90.0))
    b.run(0.5)
    assert b.outcome(7) is None  # still slewing at 60 deg/s
    b.run(1.5)
    assert b.outcome(7) == "PPCL-Finished-EV"
    assert b.tilt == pytest.approx(math.radians(90.0))
    assert b.kernel.mode is PtuMode.TURN_TO


def test_look_at_points_down_at_the_spot_below() -> None:
    b = Bench()
    b.send("PPCL-Look-At-EV", 8, 0.0, 0.0, 0.0)
    b.run(3.0)
    assert b.outcome(8) == "PPCL-Finished-EV"
    assert b.tilt == pytest.approx(math.radians(88.7), abs=math.radians(1.5))


def test_abort_stops_the_mode_and_is_acknowledged() -> None:
    b = Bench()
    b.send("PPCL-Turn-To-EV", 1, 1.0, 1.0)
    b.run(0.2)
    b.send("PPCL-Ptu-Abort-EV", 2)
    b.run(0.1)
    assert b.outcome(2) == "PPCL-Finished-EV" and b.outcome(1) is None
    assert b.kernel.mode is PtuMode.IDLE


def test_unpowered_ptu_times_out_with_a_reason() -> None:
    b = Bench(ptu_timeout=1.0)
    b.powered = False
    b.send("PPCL-Turn-To-EV", 3, 0.5, 0.5)
    b.run(1.5)
    failed = [r for r in b.replies if r[1] == 3]
    assert failed and failed[0][0] == "PPCL-Failed-EV" and "did not reach" in failed[0][2]


def test_zoom_and_camera_parameters() -> None:
    b = Bench()
    b.send("PPCL-Zoom-EV", 4, 0.0, 0.6)
    b.send("PPCL-Iris-EV", 5, 1.0, 0.25)
    b.send("PPCL-Exposure-EV", 6, 0.0, 0.0)
    b.run(0.2)
    assert [b.outcome(c) for c in (4, 5, 6)] == ["PPCL-Finished-EV"] * 3
    assert b.kernel.cameras[0].zoom == 0.6 and not b.kernel.cameras[0].auto_exposure
    assert b.kernel.cameras[1].iris == 0.25


@pytest.mark.parametrize(
    ("name", "value", "field", "expected"),
    [
        ("PPCL-Laser-Angular-EV", 0.25, "angular_resolution", 0.25),
        ("PPCL-Laser-Distance-EV", 0.001, "distance_resolution", 0.001),
        ("PPCL-Laser-Speed-EV", -2.0, "rotation_speed", -2.0),
        ("PPCL-Laser-Angle-EV", 1.0, "hold_angle", True),
    ],
)
def test_laser_parameters(name: str, value: float, field: str, expected: object) -> None:
    b = Bench()
    b.send(name, 9, value)
    b.run(0.08)
    assert getattr(b.kernel.laser, field) == expected and b.outcome(9) == "PPCL-Finished-EV"


def test_laser_collection_start_stop() -> None:
    b = Bench()
    b.send("PPCL-Laser-Start-EV", 10)
    b.run(0.08)
    assert b.kernel.laser.collect
    b.send("PPCL-Laser-Stop-EV", 11)
    b.run(0.08)
    assert not b.kernel.laser.collect
    assert b.outcome(10) == b.outcome(11) == "PPCL-Finished-EV"


@pytest.mark.parametrize(
    ("engaged", "source", "servoed"),
    [
        (IP.STATE_ESTIMATION, IP.STATE_ESTIMATION, True),
        (IP.STATE_ESTIMATION, IP.COLOR_TRACKER, False),
        (IP.COLOR_TRACKER, IP.COLOR_TRACKER, True),
        (IP.COLOR_TRACKER, IP.STATE_ESTIMATION, False),
        (IP.SALIENCY, IP.COLOR_TRACKER, False),
        (IP.SALIENCY, IP.STATE_ESTIMATION, False),
        (IP.IDLE, IP.STATE_ESTIMATION, False),
    ],
)
def test_the_ptu_servoes_on_the_engaged_functions_sightings_only(
    engaged: ImageProcessing, source: ImageProcessing, servoed: bool
) -> None:
    b = Bench()
    if engaged is not IP.IDLE:
        b.engage(engaged, 3)
        assert b.outcome(3) == "PPCL-Finished-EV"
    assert b.kernel.image_processing is engaged
    b.sight(source, (0.0, 1.0, 5.0))
    b.run(1.0)
    assert b.kernel.tracking is servoed
    if servoed:
        assert b.tilt == pytest.approx(math.atan2(1.0, 5.0), abs=1e-6)
    b.send("PPCL-IP-Abort-EV", 4)
    b.run(0.08)
    assert not b.kernel.tracking and b.kernel.image_processing is IP.IDLE
    assert b.outcome(4) == "PPCL-Finished-EV"


def test_colour_tracking_publishes_each_seed_and_stops_on_abort() -> None:
    b = Bench()
    b.send("PPCL-IP-Tracker-EV", 5, 100.0, 200.0)
    b.run(0.04)
    first = b.t
    b.run(0.2)
    b.send("PPCL-IP-Tracker-EV", 6, 100.0, 200.0)  # the same pixel again: a new seed
    b.run(0.04)
    assert b.seeds == [ColorSeed(100.0, 200.0, first), ColorSeed(100.0, 200.0, b.t)]
    assert b.functions == [IP.COLOR_TRACKER]  # engaged once, restarted by the seed
    assert b.kernel.color_seed == b.seeds[-1]
    assert b.outcome(5) == b.outcome(6) == "PPCL-Finished-EV"
    b.send("PPCL-IP-Abort-EV", 7)
    b.run(0.04)
    assert b.functions == [IP.COLOR_TRACKER, IP.IDLE] and b.kernel.color_seed is None
    assert b.outcome(7) == "PPCL-Finished-EV"


@pytest.mark.parametrize(
    ("before", "function"),
    [
        (IP.IDLE, IP.COLOR_TRACKER),
        (IP.SALIENCY, IP.COLOR_TRACKER),
        (IP.STATE_ESTIMATION, IP.COLOR_TRACKER),
        (IP.COLOR_TRACKER, IP.STATE_ESTIMATION),
        (IP.COLOR_TRACKER, IP.SALIENCY),
    ],
)
def test_one_image_processing_function_replaces_another(
    before: ImageProcessing, function: ImageProcessing
) -> None:
    b = Bench()
    if before is not IP.IDLE:
        b.engage(before, 1)
    b.engage(function, 2)
    assert b.kernel.image_processing is function and b.outcome(2) == "PPCL-Finished-EV"
    assert b.functions[-1] is function
    assert (b.kernel.color_seed is not None) is (function is IP.COLOR_TRACKER)


def test_a_new_seed_holds_the_pointing_until_its_object_is_seen() -> None:
    b = Bench()
    b.send("PPCL-Turn-To-EV", 1, 0.0, 0.0)  # the commanded mode: straight ahead
    b.engage(IP.COLOR_TRACKER, 2)
    seed = b.t
    b.sight(IP.COLOR_TRACKER, (0.0, 1.0, 1.0))  # 45 deg down
    b.run(1.0)
    assert b.tilt == pytest.approx(math.pi / 4, abs=1e-6)
    b.send("PPCL-IP-Tracker-EV", 3, 10.0, 10.0)
    b.run(0.04)
    b.kernel.see(IP.COLOR_TRACKER, Sighting(seed, (1.0, 0.0, 1.0)))  # the old seed's image
    b.run(1.9)  # within the hold (2 s): still, not back to the commanded mode
    assert b.kernel.tracking and b.tilt == pytest.approx(math.pi / 4, abs=1e-6)
    assert b.pan == pytest.approx(0.0, abs=1e-9)
    b.run(0.2)  # not seen within the hold: back to the commanded turn-to
    assert not b.kernel.tracking
    b.run(1.0)
    assert b.tilt == pytest.approx(0.0, abs=1e-9)


def test_pad_vision_follows_the_devices_the_function_and_the_images() -> None:
    """NONE without camera and pipeline; READY when both are up; ENGAGED once state estimation
    is; RUNNING while the pipeline reports images, ENGAGED again 2 s after the last one."""
    b = Bench()
    b.run(0.2)
    assert b.kernel.pad_vision is PadVision.NONE and b.pad_vision == []
    b.kernel.devices(camera=True, pipeline=True)
    b.run(0.04)
    b.engage(IP.STATE_ESTIMATION, 1)
    for _ in range(10):
        b.kernel.pad_image(b.t)
        b.run(0.2)
    b.run(2.2)
    b.kernel.devices(camera=False, pipeline=True)
    b.run(0.04)
    assert b.pad_vision == [
        PadVision.READY,
        PadVision.ENGAGED,
        PadVision.RUNNING,
        PadVision.ENGAGED,
        PadVision.NONE,
    ]


@pytest.mark.parametrize(
    ("before", "ppcl_between", "engaged", "after"),
    [
        # idle: the landing engages the pad's pose and releases it, no PPCL reply
        (IP.IDLE, None, IP.STATE_ESTIMATION, IP.IDLE),
        # another function runs (engaged by PPCL): the landing changes nothing
        (IP.SALIENCY, None, IP.SALIENCY, IP.SALIENCY),
        (IP.STATE_ESTIMATION, None, IP.STATE_ESTIMATION, IP.STATE_ESTIMATION),
        # the operator takes the pad's pose over during the landing: it stays after it
        (IP.IDLE, IP.STATE_ESTIMATION, IP.STATE_ESTIMATION, IP.STATE_ESTIMATION),
        # or switches to another function: the release does not stop that one
        (IP.IDLE, IP.COLOR_TRACKER, IP.COLOR_TRACKER, IP.COLOR_TRACKER),
    ],
)
def test_the_landing_engages_the_pads_pose_from_idle_and_releases_only_its_own(
    before: ImageProcessing,
    ppcl_between: ImageProcessing | None,
    engaged: ImageProcessing,
    after: ImageProcessing,
) -> None:
    b = Bench()
    b.kernel.devices(camera=True, pipeline=True)
    b.run(0.04)  # the first step announces the PPC (PPC-Started-EV)
    if before is not IP.IDLE:
        b.engage(before, 1)
    replies = len(b.replies)
    b.from_pfc("Pad-Est-Engage-EV")
    b.run(0.04)
    if ppcl_between is not None:
        b.engage(ppcl_between, 2)
        assert b.outcome(2) == "PPCL-Finished-EV"
    assert b.kernel.image_processing is engaged
    b.from_pfc("Pad-Est-Release-EV")
    b.run(0.04)
    assert b.kernel.image_processing is after
    assert len(b.replies) == replies + (ppcl_between is not None)  # the landing's: no reply
