"""People, dummies, animals and cars: seeded poses and colours, sizes, surface temperatures."""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import replace

import numpy as np
import pytest

from sim.render.bodies import (
    CAR_PAINTS,
    CLOTHING_BELOW_SKIN_K,
    ENGINE_HOOD_ABOVE_BODY_K,
    Pose,
    add_object,
    add_person,
)
from sim.render.materials import ThermalEnvironment
from sim.render.meshes import MeshBuilder
from sim.world import DynamicObject, ObjectKind
from sim.world_loader import DEFAULT_SIZES

ENV = ThermalEnvironment()


def _obj(
    ident: str, kind: ObjectKind, temperature: float | None = 307.0, heading: float = 0.0
) -> DynamicObject:
    return DynamicObject(ident, kind, 10.0, -5.0, heading, DEFAULT_SIZES[kind], temperature)


def _mesh(obj: DynamicObject) -> np.ndarray:
    mesh = MeshBuilder()
    add_object(mesh, obj, 2.0, ENV)
    return mesh.array()


def test_poses_and_colours_vary_between_people_and_repeat_per_id() -> None:
    poses = Counter(
        add_person(MeshBuilder(), _obj(f"p{i}", ObjectKind.PERSON), 0.0, 307.0, dummy=False)
        for i in range(60)
    )
    assert set(poses) == set(Pose)
    assert np.array_equal(
        _mesh(_obj("p1", ObjectKind.PERSON)), _mesh(_obj("p1", ObjectKind.PERSON))
    )
    colours = {
        tuple(np.round(_mesh(_obj(f"p{i}", ObjectKind.PERSON))[0, 6:9], 2)) for i in range(20)
    }
    assert len(colours) > 5


@pytest.mark.parametrize("heading", [0.0, 1.0, 4.0])
@pytest.mark.parametrize(
    "kind", [ObjectKind.PERSON, ObjectKind.DUMMY, ObjectKind.ANIMAL, ObjectKind.CAR, ObjectKind.BOX]
)
def test_objects_stand_on_the_ground_within_their_size(kind: ObjectKind, heading: float) -> None:
    obj = _obj("x", kind, heading=heading)
    v = _mesh(obj)
    length, width, height = obj.size
    reach = math.hypot(length, width) / 2.0 + 0.3
    assert np.hypot(v[:, 0] - obj.east, v[:, 1] - obj.north).max() < reach
    assert v[:, 2].min() == pytest.approx(2.0, abs=0.1)  # on the ground at 2 m
    limit = 1.0 if kind in (ObjectKind.PERSON, ObjectKind.DUMMY) else height + 0.05
    assert v[:, 2].max() - 2.0 < limit


def test_person_skin_is_the_world_temperature_and_clothing_cooler() -> None:
    temps = set(np.round(_mesh(_obj("p", ObjectKind.PERSON, 307.0))[:, 9], 3))
    assert temps == {307.0, round(307.0 - CLOTHING_BELOW_SKIN_K, 3)}


def test_dummy_without_temperature_is_near_the_air_and_car_hood_is_hot() -> None:
    dummy = _mesh(_obj("d", ObjectKind.DUMMY, None))
    assert ENV.ambient < dummy[:, 9].max() < ENV.ambient + 6.0
    car = _mesh(_obj("c", ObjectKind.CAR, 290.0))
    assert set(np.round(car[:, 9], 3)) == {290.0, 290.0 + ENGINE_HOOD_ABOVE_BODY_K}


@pytest.mark.parametrize("ident", ["c", "car1", "chase1"])
def test_a_painted_car_has_its_paint_and_others_one_of_the_palette(ident: str) -> None:
    paint = (0.85, 0.05, 0.80)
    painted = _mesh(replace(_obj(ident, ObjectKind.CAR), paint=paint))
    colours = {tuple(np.round(c, 4)) for c in painted[:, 6:9]}
    assert tuple(np.round(np.asarray(paint, dtype=np.float32), 4)) in colours
    plain = _mesh(_obj(ident, ObjectKind.CAR))
    body = plain[0, 6:9]  # the lower body: a palette colour varied by at most 10 %
    ratios = [body / np.asarray(p) for p in CAR_PAINTS]
    assert any(np.all((r > 0.89) & (r < 1.11)) for r in ratios)
    assert not np.allclose(body, paint, atol=0.1)
