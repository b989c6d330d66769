"""Rendered images against the geometry: projection, bodies, occlusion, thermal contrast."""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np
import pytest

from sim.geodesy import GeodeticOrigin
from sim.render.imaging import CENTI_KELVIN
from sim.render.materials import Material, ThermalEnvironment
from sim.render.projection import look_at
from sim.render.renderer import Renderer, digest
from sim.sensors.camera_model import CameraPose, Intrinsics, project
from sim.terrain import Terrain
from sim.world import Building, DynamicObject, ObjectKind, World
from sim.world_loader import DEFAULT_SIZES, load_world

C0 = 273.15
ENV = ThermalEnvironment()
ROOF_K = ENV.ambient + Material.ROOF.surface.warmth


def _obj(ident: str, kind: ObjectKind, east: float, north: float, temp_c: float | None,
         heading: float = 0.0) -> DynamicObject:  # fmt: skip
    temperature = None if temp_c is None else C0 + temp_c
    return DynamicObject(ident, kind, east, north, heading, DEFAULT_SIZES[kind], temperature)


WORLD = World(
    name="block",
    origin=GeodeticOrigin(55.7, 13.47, 95.0),
    terrain=Terrain.flat(-100.0, -100.0, 100.0, 100.0),
    buildings=(Building("B1", ((0.0, 0.0), (10.0, 0.0), (10.0, 8.0), (0.0, 8.0)), 10.0, 0.0),),
    objects=(
        _obj("person", ObjectKind.PERSON, -20.0, 4.0, 34.0),
        _obj("dummy", ObjectKind.DUMMY, -20.0, -6.0, None, 0.4),
        _obj("hidden", ObjectKind.PERSON, 16.0, 4.0, 34.0, 1.5),
        _obj("dog", ObjectKind.ANIMAL, -35.0, -20.0, 30.0),
        _obj("car", ObjectKind.CAR, 30.0, -30.0, 20.0, math.pi / 2),
    ),
)


@pytest.fixture(scope="module")
def renderer() -> Iterator[Renderer]:
    r = Renderer(WORLD)
    yield r
    r.release()


SMALL = Intrinsics.from_fov(160, 120, math.radians(50.0))
ODD = Intrinsics(200, 150, 150.0, 151.0, 90.3, 80.7)


def _obj_by_id(ident: str) -> DynamicObject:
    return next(o for o in WORLD.objects if o.id == ident)


def _at(image: np.ndarray, uv: tuple[float, float]) -> np.ndarray:
    value: np.ndarray = image[int(uv[1]), int(uv[0])]
    return value


@pytest.mark.parametrize("intrinsics", [SMALL, ODD])
@pytest.mark.parametrize(
    "pose",
    [look_at((5.0, 4.0, 60.0), (5.0, 4.0, 0.0)), look_at((-25.0, -30.0, 35.0), (5.0, 4.0, 5.0))],
)
def test_roof_corners_land_where_camera_model_projects_them(
    renderer: Renderer, pose: CameraPose, intrinsics: Intrinsics
) -> None:
    kelvin = renderer.render_temperature(pose, intrinsics)
    roof = WORLD.buildings[0]
    centre = project(pose, intrinsics, (5.0, 4.0, roof.top))
    assert centre is not None
    assert _at(kelvin, centre) == pytest.approx(ROOF_K, abs=0.5)
    for e, n in roof.footprint:
        corner = project(pose, intrinsics, (e, n, roof.top))
        assert corner is not None
        direction = np.subtract(centre, corner)
        direction /= np.linalg.norm(direction)
        inside = np.add(corner, 1.5 * direction)
        assert _at(kelvin, tuple(inside)) == pytest.approx(ROOF_K, abs=0.5), (e, n)
        # just outside the roof along the diagonal: ground or wall, never roof
        outside = np.subtract(corner, 1.5 * direction)
        assert abs(_at(kelvin, tuple(outside)) - ROOF_K) > 5.0, (e, n)


def _person_view(ident: str, height: float = 30.0) -> tuple[CameraPose, tuple[float, float]]:
    obj = _obj_by_id(ident)
    pose = look_at((obj.east - 8.0, obj.north - 8.0, height), (obj.east, obj.north, 0.0))
    uv = project(pose, SMALL, (obj.east, obj.north, 0.15))
    assert uv is not None
    return pose, uv


def _window(image: np.ndarray, uv: tuple[float, float], half: int = 3) -> np.ndarray:
    u, v = int(uv[0]), int(uv[1])
    return image[v - half : v + half + 1, u - half : u + half + 1]


def test_person_is_hot_in_thermal_and_seen_in_colour(renderer: Renderer) -> None:
    pose, uv = _person_view("person")
    thermal = renderer.render_thermal(pose, SMALL, stamp_ns=5)
    assert thermal.dtype == np.uint16
    assert _window(thermal, uv).max() / CENTI_KELVIN > C0 + 30.0
    assert np.median(thermal) / CENTI_KELVIN == pytest.approx(ENV.ambient, abs=3.0)
    try:
        renderer.set_objects([_obj_by_id("person")])
        with_people = renderer.render_color(pose, SMALL, stamp_ns=5).astype(int)
        renderer.set_objects([])
        empty = renderer.render_color(pose, SMALL, stamp_ns=5).astype(int)
    finally:
        renderer.set_objects(WORLD.objects)
    changed = np.abs(with_people - empty).sum(axis=2) > 0
    assert _window(changed, uv, 1).any()  # the person covers its projected centre
    rows, cols = np.nonzero(changed)
    assert len(rows) >= 15  # a 1.8 m person is about 10 px long here
    # nothing else changed (same noise for the same stamp): every changed pixel is the person's
    assert np.hypot(cols + 0.5 - uv[0], rows + 0.5 - uv[1]).max() < 8.0


def test_building_occludes_the_person_behind_it(renderer: Renderer) -> None:
    hidden = _obj_by_id("hidden")
    # low camera west of the building, looking east across it at the person behind
    pose = look_at((-30.0, 4.0, 6.0), (hidden.east, hidden.north, 0.1))
    uv = project(pose, SMALL, (hidden.east, hidden.north, 0.15))
    assert uv is not None
    kelvin = renderer.render_temperature(pose, SMALL)
    assert _window(kelvin, uv, 2).max() < C0 + 25.0  # the wall, not the person
    without = World(name="open", origin=WORLD.origin, terrain=WORLD.terrain, objects=WORLD.objects)
    open_view = Renderer(without)
    try:
        kelvin = open_view.render_temperature(pose, SMALL)
    finally:
        open_view.release()
    assert _window(kelvin, uv, 2).max() > C0 + 30.0


def test_dummy_is_cooler_than_a_person_and_warmer_than_grass(renderer: Renderer) -> None:
    person_pose, person_uv = _person_view("person")
    dummy_pose, dummy_uv = _person_view("dummy")
    person = _window(renderer.render_temperature(person_pose, SMALL), person_uv).max()
    dummy = _window(renderer.render_temperature(dummy_pose, SMALL), dummy_uv).max()
    assert person > dummy + 10.0
    assert dummy > ENV.ambient + Material.GRASS.surface.warmth + 1.0


def test_distractors_are_warm(renderer: Renderer) -> None:
    dog_pose, dog_uv = _person_view("dog")
    assert _window(renderer.render_temperature(dog_pose, SMALL), dog_uv).max() > C0 + 28.0
    car = _obj_by_id("car")
    pose = look_at((car.east, car.north, 30.0), (car.east, car.north, 0.0))
    # heading east: the hood is 1.4 m east of the centre
    hood = project(pose, SMALL, (car.east + 1.4, car.north, 1.0))
    assert hood is not None
    kelvin = renderer.render_temperature(pose, SMALL)
    assert _window(kelvin, hood, 1).max() > C0 + 20.0 + 10.0


def test_frames_are_deterministic_per_stamp(renderer: Renderer) -> None:
    pose, _ = _person_view("person")
    a = renderer.render_color(pose, SMALL, stamp_ns=40_000_000)
    b = renderer.render_color(pose, SMALL, stamp_ns=40_000_000)
    c = renderer.render_color(pose, SMALL, stamp_ns=80_000_000)
    assert digest(a) == digest(b) != digest(c)
    t1 = renderer.render_thermal(pose, SMALL, stamp_ns=40_000_000)
    t2 = renderer.render_thermal(pose, SMALL, stamp_ns=40_000_000)
    assert digest(t1) == digest(t2)


def test_revinge_bodies_are_hot_where_they_lie() -> None:
    world = load_world("revinge")
    renderer = Renderer(world)
    try:
        for body in world.objects_of(ObjectKind.PERSON)[:3]:
            ground = world.terrain.height(body.east, body.north)
            pose = look_at((body.east, body.north - 10.0, ground + 40.0),
                           (body.east, body.north, ground))  # fmt: skip
            uv = project(pose, SMALL, (body.east, body.north, ground + 0.15))
            assert uv is not None
            kelvin = renderer.render_temperature(pose, SMALL)
            assert body.temperature is not None
            assert _window(kelvin, uv).max() == pytest.approx(body.temperature, abs=0.5)
    finally:
        renderer.release()
