"""The colour tracker (§6.1, §6.2.3): seeds, following, LOST, re-acquisition, red wrap-around,
distractors; the pixel's direction and ground point; a car rendered by the simulator."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pytest
from numpy.typing import NDArray

from hdrc3_interfaces.msg import ColorTrack
from hdrc3_perception.camera import CameraPose, Intrinsics, NavPose
from hdrc3_perception.colour_tracking import (
    CameraView,
    ColourModel,
    ColourTracker,
    TrackStatus,
    locate,
)
from hdrc3_perception.geolocation import Ground
from sim.world import DynamicObject

H, W = 240, 320
RED = (200, 25, 25)
BLUE = (30, 50, 190)
DARK = (25, 25, 28)
CAR = (40, 20)
"""Width and height of a car, pixels."""


@dataclass
class Scene:
    """A textured grass field with a grey road (rows 100-150) and coloured rectangles on it."""

    seed: int = 1
    rng: np.random.Generator = field(init=False)

    def __post_init__(self) -> None:
        self.rng = np.random.default_rng(self.seed)

    def image(
        self, *cars: tuple[float, float, tuple[int, int, int]], size: tuple[int, int] = CAR
    ) -> NDArray[np.uint8]:
        img = np.empty((H, W, 3), np.float64)
        img[:] = (84, 116, 58)
        img += self.rng.normal(0.0, 12.0, (H, W, 1)) + self.rng.normal(0.0, 5.0, (H, W, 3))
        img[100:150] = 95.0 + self.rng.normal(0.0, 8.0, (50, W, 1))
        for cx, cy, colour in cars:
            x0, y0 = round(cx - size[0] / 2), round(cy - size[1] / 2)
            x1, y1 = max(0, x0), max(0, y0)
            img[y1 : max(0, y0 + size[1]), x1 : max(0, x0 + size[0])] = colour
        noisy = img + self.rng.normal(0.0, 4.0, img.shape)
        return np.clip(noisy, 0, 255).astype(np.uint8)


def test_statuses_are_the_message_s() -> None:
    assert TrackStatus.TRACKING == ColorTrack.STATUS_TRACKING
    assert TrackStatus.LOST == ColorTrack.STATUS_LOST
    assert TrackStatus.BAD_SEED == ColorTrack.STATUS_BAD_SEED


@pytest.mark.parametrize(
    ("seed", "status", "reason"),
    [
        ((60.0, 125.0), TrackStatus.TRACKING, "seeded"),  # the red car
        ((52.0, 118.0), TrackStatus.TRACKING, "seeded"),  # off its centre, still on it
        ((200.0, 125.0), TrackStatus.BAD_SEED, "grey"),  # the road
        ((200.0, 30.0), TrackStatus.BAD_SEED, "background"),  # the grass field
        ((250.0, 125.0), TrackStatus.BAD_SEED, "dark"),  # a black car
        ((-1.0, 10.0), TrackStatus.BAD_SEED, "outside"),
        ((float(W), 10.0), TrackStatus.BAD_SEED, "outside"),
        ((10.0, float(H)), TrackStatus.BAD_SEED, "outside"),
        ((math.nan, 10.0), TrackStatus.BAD_SEED, "outside"),
        ((math.inf, 10.0), TrackStatus.BAD_SEED, "outside"),
    ],
)
def test_a_seed_is_taken_or_refused_with_a_reason(
    seed: tuple[float, float], status: TrackStatus, reason: str
) -> None:
    image = Scene().image((60, 125, RED), (250, 125, DARK))
    tracker = ColourTracker()
    result = tracker.seed(*seed, image)
    assert result.status is status and reason in result.reason, result
    if status is TrackStatus.TRACKING:
        assert (result.x, result.y) == pytest.approx((60.0, 125.0), abs=1.0)
        assert result.area == pytest.approx(CAR[0] * CAR[1], rel=0.05)
        assert result.bbox[2:] == pytest.approx(CAR, abs=2)
    else:
        assert tracker.model is None
        assert math.isnan(result.x) and math.isnan(result.y)
        assert tracker.update(image) == result  # the refusal stands until the next seed


def test_a_speck_is_no_object() -> None:
    image = Scene().image((60, 125, RED), size=(2, 2))
    result = ColourTracker().seed(60, 125, image)
    assert result.status is TrackStatus.BAD_SEED, result


@pytest.mark.parametrize(
    "velocity",
    [(0.0, 0.0), (3.0, 0.5), (10.0, -1.0), (-12.0, 2.0), (25.0, 3.0), (4.0, 9.0)],
)
def test_the_target_is_followed_at_several_speeds(velocity: tuple[float, float]) -> None:
    scene, tracker = Scene(), ColourTracker()
    start = (160.0 - 4.0 * velocity[0], 125.0 - 4.0 * velocity[1])
    assert tracker.seed(*start, scene.image((*start, RED))).status is TrackStatus.TRACKING
    for i in range(1, 9):
        truth = (start[0] + i * velocity[0], start[1] + i * velocity[1])
        result = tracker.update(scene.image((*truth, RED)))
        assert result.status is TrackStatus.TRACKING, (i, result)
        assert (result.x, result.y) == pytest.approx(truth, abs=1.0)


def test_lost_when_the_target_leaves_the_image() -> None:
    scene, tracker = Scene(), ColourTracker()
    tracker.seed(200, 125, scene.image((200, 125, RED)))
    statuses = []
    for i in range(1, 12):
        statuses.append(tracker.update(scene.image((200 + 15 * i, 125, RED))).status)
    # the car's centre passes the border at i = 8; a 20-px sliver is still tracked at i = 9
    assert statuses[:8] == [TrackStatus.TRACKING] * 8
    assert statuses[-1] is TrackStatus.LOST
    result = tracker.update(scene.image())
    assert result.status is TrackStatus.LOST and "no region" in result.reason


@pytest.mark.parametrize("hidden", [1, 4, 8])
def test_reacquired_near_the_prediction_and_not_at_a_twin_far_away(hidden: int) -> None:
    """Hidden (e.g. under a tree) for some images, then where constant velocity puts it."""
    scene, tracker = Scene(), ColourTracker()
    twin = (280.0, 30.0, RED)  # the same colour, far from the target's path
    tracker.seed(40, 125, scene.image((40, 125, RED), twin))
    for i in range(1, 4):
        assert tracker.update(scene.image((40 + 8 * i, 125, RED), twin)).status is (
            TrackStatus.TRACKING
        )
    for _ in range(hidden):
        result = tracker.update(scene.image(twin))
        assert result.status is TrackStatus.LOST and "1 of its size elsewhere" in result.reason
    back = 40.0 + 8 * (4 + hidden)
    result = tracker.update(scene.image((back, 125, RED), twin))
    assert result.status is TrackStatus.TRACKING
    assert (result.x, result.y) == pytest.approx((back, 125.0), abs=1.0)


def test_a_twin_beside_the_gate_is_not_taken() -> None:
    """A car of the target's colour appearing where the target was not heading stays LOST."""
    scene, tracker = Scene(), ColourTracker()
    tracker.seed(100, 125, scene.image((100, 125, RED)))
    tracker.update(scene.image((105, 125, RED)))
    result = tracker.update(scene.image((180, 60, RED)))  # 90 px off the prediction
    assert result.status is TrackStatus.LOST


@pytest.mark.parametrize(
    ("target", "other"),
    [(RED, BLUE), (BLUE, RED), (RED, (200, 200, 30)), ((220, 130, 20), RED)],
)
def test_a_distractor_of_another_hue_is_ignored(
    target: tuple[int, int, int], other: tuple[int, int, int]
) -> None:
    """The other car passes right beside the target, then sits where the hidden target was due."""
    scene, tracker = Scene(), ColourTracker()
    assert tracker.seed(100, 125, scene.image((100, 125, target))).status is TrackStatus.TRACKING
    for i in range(1, 8):
        truth = (100.0 + 6 * i, 125.0 + 2 * i)
        result = tracker.update(scene.image((*truth, target), (110.0 + 6 * i, 95.0, other)))
        assert result.status is TrackStatus.TRACKING
        assert (result.x, result.y) == pytest.approx(truth, abs=1.0)
    due = (100.0 + 6 * 8, 125.0 + 2 * 8)
    assert tracker.update(scene.image((*due, other))).status is TrackStatus.LOST


def test_red_across_the_hue_wrap_is_one_target() -> None:
    """A car painted half crimson (hue ~350 deg), half scarlet (~8 deg): hue 0 lies inside it."""
    scene, tracker = Scene(), ColourTracker()

    def image(cx: float) -> NDArray[np.uint8]:
        img = scene.image((cx - 10, 125, (200, 20, 50)), size=(20, 20))
        right = scene.image((cx + 10, 125, (200, 50, 20)), size=(20, 20))
        img[:, int(cx) :] = right[:, int(cx) :]
        return img

    seeded = tracker.seed(100, 125, image(100))
    assert seeded.status is TrackStatus.TRACKING
    assert tracker.model is not None and len(tracker.model.intervals()) == 2
    assert seeded.area == pytest.approx(800, rel=0.05) and seeded.x == pytest.approx(100, abs=1)
    for i in range(1, 6):
        result = tracker.update(image(100 + 10 * i))
        assert result.status is TrackStatus.TRACKING
        assert result.x == pytest.approx(100 + 10 * i, abs=1.0)
        assert result.area == pytest.approx(800, rel=0.05)


@pytest.mark.parametrize(
    ("hue", "tol", "intervals"),
    [
        (90, 10, [(80, 100)]),
        (3, 8, [(0, 11), (175, 179)]),
        (176, 8, [(168, 179), (0, 4)]),
        (0, 6, [(0, 6), (174, 179)]),
    ],
)
def test_hue_intervals_wrap(hue: int, tol: int, intervals: list[tuple[int, int]]) -> None:
    assert ColourModel(hue, tol, 60, 40).intervals() == intervals


def test_timed_images_predict_across_a_dropped_image() -> None:
    scene, tracker = Scene(), ColourTracker()
    speed = 400.0  # px/s: 16 px per image at 25 Hz
    times = [0.0, 0.04, 0.08, 0.20, 0.24]  # two images dropped before 0.20: 48 px in one go
    tracker.seed(60, 125, scene.image((60, 125, RED)), times[0])
    for t in times[1:]:
        truth = 60.0 + speed * t
        result = tracker.update(scene.image((truth, 125, RED)), t)
        assert result.status is TrackStatus.TRACKING and result.x == pytest.approx(truth, abs=1)


@pytest.mark.parametrize(
    "bad",
    [
        np.zeros((H, W), np.uint8),
        np.zeros((H, W, 4), np.uint8),
        np.zeros((H, W, 3), np.float32),
        np.zeros((0, W, 3), np.uint8),
        [[1, 2, 3]],
    ],
)
def test_bad_images_get_a_status_not_an_exception(bad: object) -> None:
    tracker = ColourTracker()
    seeded = tracker.seed(5, 5, bad)  # type: ignore[arg-type]
    assert seeded.status is TrackStatus.BAD_SEED and "bad image" in seeded.reason
    scene = Scene()
    tracker.seed(60, 125, scene.image((60, 125, RED)))
    result = tracker.update(bad)  # type: ignore[arg-type]
    assert result.status is TrackStatus.LOST and "bad image" in result.reason
    assert tracker.update(scene.image((62, 125, RED))).status is TrackStatus.TRACKING


def test_no_seed_and_reset() -> None:
    scene, tracker = Scene(), ColourTracker()
    image = scene.image((60, 125, RED))
    assert tracker.update(image).status is TrackStatus.LOST
    assert "no seed" in tracker.update(image).reason
    tracker.seed(60, 125, image)
    assert tracker.update(image, math.nan).status is TrackStatus.LOST
    tracker.reset()
    assert tracker.model is None and "no seed" in tracker.update(image).reason


def test_a_new_seed_restarts_on_the_new_target() -> None:
    scene, tracker = Scene(), ColourTracker()
    image = scene.image((60, 125, RED), (250, 50, BLUE))
    tracker.seed(60, 125, image)
    assert tracker.seed(250, 50, image).x == pytest.approx(250, abs=1)
    result = tracker.update(scene.image((60, 125, RED), (255, 50, BLUE)))
    assert result.status is TrackStatus.TRACKING and result.x == pytest.approx(255, abs=1)


# --- direction and ground point -------------------------------------------------------------

K = Intrinsics.from_fov(W, H, math.radians(48.0))
NAV = NavPose((10.0, -20.0, 32.0), 0.02, -0.03, 0.7)
PTU = (0.3, 1.2)


def test_direction_is_the_optical_ray() -> None:
    d = K.direction(K.cx, K.cy)
    assert d == pytest.approx([0.0, 0.0, 1.0])
    d = K.direction(K.cx + K.fx, K.cy - K.fy)  # 45 deg right and up
    assert d == pytest.approx(np.array([1.0, -1.0, 1.0]) / math.sqrt(3.0))


@pytest.mark.parametrize("ground", [Ground(flat_up=2.0), Ground(height=lambda e, n: 0.05 * e)])
def test_a_tracked_pixel_is_located_on_the_ground(ground: Ground) -> None:
    pose = CameraPose.of(NAV, *PTU)
    truth = np.array([18.0, -12.0, 0.0])
    truth[2] = ground.up(truth[0], truth[1])
    u, v = pose.project(K, truth)[0]
    fix = locate(K, u, v, CameraView.at(K, NAV, PTU), ground)
    assert fix.position is not None and fix.position == pytest.approx(truth, abs=0.05)
    assert fix.direction == pytest.approx(K.direction(u, v))
    to_truth = truth - pose.position
    assert pose.rotation @ fix.direction == pytest.approx(to_truth / np.linalg.norm(to_truth))


@pytest.mark.parametrize(
    ("nav", "ptu", "reason"),
    [
        (None, PTU, "helicopter_state"),
        (NavPose((math.nan, 0.0, 30.0), 0.0, 0.0, 0.0), PTU, "helicopter_state"),
        (NAV, None, "PTU"),
        (NAV, (0.0, math.nan), "PTU"),
        (NAV, (0.0, -0.5), "no ground"),  # looking up
    ],
)
def test_not_located_says_why(
    nav: NavPose | None, ptu: tuple[float, float] | None, reason: str
) -> None:
    fix = locate(K, K.cx, K.cy, CameraView.at(K, nav, ptu), Ground())
    assert fix.position is None and reason in fix.reason
    assert np.linalg.norm(fix.direction) == pytest.approx(1.0)


# --- the simulator's renderer ---------------------------------------------------------------


def _saturated(car: DynamicObject) -> bool:
    """Whether the renderer paints this car in a colour (not white, grey or black)."""
    from sim.render.bodies import CAR_PAINTS, choose, object_rng

    paint = getattr(car, "paint", None)  # a world file's paint, else one drawn by the id
    rgb = np.asarray(paint if paint is not None else choose(object_rng(car.id), CAR_PAINTS))
    return bool(rgb.max() - rgb.min() > 0.5 * rgb.max())


def test_a_rendered_car_of_revinge_is_tracked_as_the_camera_passes() -> None:
    from sim.render.projection import look_at
    from sim.render.renderer import Renderer
    from sim.sensors.camera_model import Intrinsics as SimIntrinsics
    from sim.sensors.camera_model import project
    from sim.world import ObjectKind
    from sim.world_loader import load_world

    world = load_world("revinge")
    cars = world.objects_of(ObjectKind.CAR)
    coloured = [c for c in cars if _saturated(c)]
    plain = [c for c in cars if not _saturated(c)]
    assert coloured and plain  # revinge: a red car1; a white and two black ones
    car = coloured[0]
    ground = world.terrain.height(car.east, car.north)
    k = SimIntrinsics.from_fov(360, 288, math.radians(48.0))
    renderer = Renderer(world)
    tracker = ColourTracker()
    try:
        for i in range(8):
            east = car.east - 10.0 + 2.5 * i  # the car drifts across the image, 25 px a frame
            pose = look_at((east, car.north - 15.0, ground + 30.0), (east, car.north, ground))
            image = renderer.render_color(pose, k, stamp_ns=40_000_000 * i)
            uv = project(pose, k, (car.east, car.north, ground + 0.8))
            assert uv is not None
            result = tracker.seed(*uv, image) if i == 0 else tracker.update(image)
            assert result.status is TrackStatus.TRACKING, (i, result)
            assert (result.x, result.y) == pytest.approx(uv, abs=3.0)
        # cars without a colour give no seed
        for other in plain:
            up = world.terrain.height(other.east, other.north)
            pose = look_at(
                (other.east, other.north - 15.0, up + 30.0), (other.east, other.north, up)
            )
            uv = project(pose, k, (other.east, other.north, up + 0.8))
            assert uv is not None
            result = tracker.seed(*uv, renderer.render_color(pose, k))
            assert result.status is TrackStatus.BAD_SEED, (other.id, result)
    finally:
        renderer.release()


@pytest.mark.parametrize(("with_view", "tracked"), [(True, True), (False, False)])
def test_the_camera_s_own_motion_is_not_taken_for_the_target_s(
    with_view: bool, tracked: bool
) -> None:
    """A parked car while the PTU swings left and right by 0.2 rad per image (60 px here).

    With each image's :class:`CameraView` the prediction is the car's world direction seen by
    the new camera; from image motion alone the swing looks like a fast car that reverses.
    """
    from hdrc3_perception.colour_tracking import CameraView

    intrinsics = Intrinsics.from_fov(W, H, math.radians(60.0))
    nav = NavPose((0.0, 0.0, 30.0), 0.0, 0.0, 0.0)
    car = np.array([0.0, 60.0, 0.0])

    def view_and_pixel(pan: float) -> tuple[CameraView, tuple[float, float]]:
        pose = CameraPose.of(nav, pan, math.atan2(30.0, 60.0))
        pixel = pose.project(intrinsics, car[None, :])[0]
        return CameraView.of(intrinsics, pose), (float(pixel[0]), float(pixel[1]))

    scene, tracker = Scene(), ColourTracker()
    view, (u, v) = view_and_pixel(0.0)
    seeded = tracker.seed(u, v, scene.image((u, v, RED)), 0.0, view if with_view else None)
    assert seeded.status is TrackStatus.TRACKING
    statuses = []
    for i, pan in enumerate([0.2, 0.4, 0.2, 0.0, -0.2, 0.0, 0.2], start=1):
        view, (u, v) = view_and_pixel(pan)
        result = tracker.update(scene.image((u, v, RED)), 0.04 * i, view if with_view else None)
        statuses.append(result.status is TrackStatus.TRACKING)
    assert all(statuses) is tracked, statuses


def test_a_camera_view_projects_the_directions_it_gives() -> None:
    from hdrc3_perception.colour_tracking import CameraView

    intrinsics = Intrinsics.from_fov(W, H, math.radians(60.0))
    pose = CameraPose.of(NavPose((5.0, -3.0, 40.0), 0.05, -0.02, 1.0), 0.3, 0.6)
    view = CameraView.of(intrinsics, pose)
    for u, v in [(0.0, 0.0), (160.0, 120.0), (300.5, 17.25)]:
        assert view.pixel(view.direction(u, v)) == pytest.approx((u, v), abs=1e-6)
    assert view.pixel(-view.direction(160.0, 120.0)) is None  # behind the camera


def test_a_target_far_from_both_predictions_is_searched_for_in_the_whole_image() -> None:
    """The camera swung back (no view given): LOST at first, then taken wherever it is."""
    scene, tracker = Scene(), ColourTracker()
    tracker.seed(40, 125, scene.image((40, 125, RED)))
    for x in (70, 100):
        assert tracker.update(scene.image((x, 125, RED))).status is TrackStatus.TRACKING
    statuses = [tracker.update(scene.image((40, 125, RED))).status for _ in range(13)]
    search = tracker.config.search_images
    assert statuses[:search] == [TrackStatus.LOST] * search
    assert statuses[search] is TrackStatus.TRACKING
