"""WorldObjects entries become renderable objects with the world file's properties."""

from __future__ import annotations

import math
from dataclasses import dataclass

from sim.render.objects import objects_from_message
from sim.world_loader import load_world


@dataclass
class Entry:
    id: str
    kind: str
    east: float
    north: float
    heading: float
    size: tuple[float, ...]


def test_known_objects_keep_their_temperature_and_spawned_ones_get_defaults() -> None:
    world = load_world("revinge")
    body = world.objects[0]
    entries = [
        Entry(body.id, body.kind.value, 1.0, 2.0, 0.5, body.size),
        Entry("crate", "box", 3.0, 4.0, 0.0, (0.4, 0.4, 0.3)),
        Entry("fox", "animal", 3.0, 4.0, 0.0, (0.8, 0.3, 0.5)),
        Entry("ufo", "saucer", 0.0, 0.0, 0.0, (1.0, 1.0, 1.0)),
        Entry("nan", "person", math.nan, 0.0, 0.0, (1.8, 0.5, 0.3)),
        Entry("flat", "person", 0.0, 0.0, 0.0, (1.8, 0.5)),
    ]
    objects = {o.id: o for o in objects_from_message(world, entries)}
    assert set(objects) == {body.id, "crate", "fox"}
    moved = objects[body.id]
    assert (moved.east, moved.north, moved.heading) == (1.0, 2.0, 0.5)
    assert moved.temperature == body.temperature
    assert objects["fox"].temperature is not None and objects["fox"].temperature > 290.0
    assert objects["crate"].temperature is None


def test_a_driving_car_keeps_its_paint_and_drive_where_it_is_now() -> None:
    world = load_world("revinge_chase")
    (chase,) = [o for o in world.objects if o.id == "chase1"]
    entries = [Entry("chase1", "car", 180.0, -100.0, 1.5, chase.size)]
    (moved,) = objects_from_message(world, entries)
    assert (moved.east, moved.north, moved.heading) == (180.0, -100.0, 1.5)
    assert moved.paint == chase.paint == (0.85, 0.05, 0.80)
    assert moved.drive == chase.drive and moved.temperature == chase.temperature
