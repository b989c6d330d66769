"""MuJoCo payload world: falling boxes, the hook picking up and dropping, faults, checkpoints."""

from __future__ import annotations

import math
import pickle
from dataclasses import replace

import pytest

from sim.hook import HookFault, HookParams, WinchState
from sim.payload import PayloadPose, PayloadWorld
from sim.payload_scene import WALL, carrier_slots
from sim.world import BoxContents, DynamicObject, ObjectKind
from sim.world_loader import load_world

WORLD = load_world("revinge")
DT = 0.005
BOX1 = next(o for o in WORLD.objects if o.id == "box1")
GROUND1 = WORLD.terrain.height(BOX1.east, BOX1.north)
ANCHOR = (BOX1.east, BOX1.north, GROUND1 + 3.0)
"""A winch hovering 3 m above box1."""


def _world(*extra: DynamicObject) -> PayloadWorld:
    return PayloadWorld(WORLD.terrain, [*WORLD.objects, *extra], {"uav0": ANCHOR})


def _run(world: PayloadWorld, seconds: float, anchor: tuple[float, float, float] = ANCHOR) -> None:
    for _ in range(round(seconds / DT)):
        world.step(DT, {"uav0": anchor})


@pytest.mark.parametrize(
    ("east", "north", "heading"),
    [(-100.0, 50.0, 0.3), (150.0, -120.0, 2.0), (-280.0, 180.0, 5.0)],
)
def test_a_box_dropped_from_10_m_comes_to_rest_on_the_terrain(
    east: float, north: float, heading: float
) -> None:
    box = DynamicObject(
        "drop", ObjectKind.BOX, east, north, heading, (0.4, 0.4, 0.3),
        contents=BoxContents.WATER, mass=5.0,
    )  # fmt: skip
    world = _world(box)
    world.place("drop", east, north, WORLD.terrain.height(east, north) + 10.0)
    _run(world, 0.5)
    assert world.pose("drop").speed > 3.0  # falling
    _run(world, 8.0)
    pose = world.pose("drop")
    assert pose.speed < 0.01
    # resting: its bottom centre on the terrain under where it ended up (it may have bounced)
    assert pose.up == pytest.approx(WORLD.terrain.height(pose.east, pose.north), abs=0.02)


def test_resting_objects_stay_where_the_world_file_puts_them() -> None:
    world = _world()
    _run(world, 2.0)
    for obj in WORLD.objects:
        if obj.kind in (ObjectKind.BOX, ObjectKind.CARRIER):
            pose = world.pose(obj.id)
            assert (pose.east, pose.north) == pytest.approx((obj.east, obj.north), abs=0.01)
            ground = WORLD.terrain.height(obj.east, obj.north)
            assert pose.up == pytest.approx(ground + (WALL if obj.on else 0.0), abs=0.02)


def _pick_up(world: PayloadWorld) -> None:
    world.command("uav0", 2.95, magnet=True)  # lower onto the box (0.3 m high, 3 m below)
    _run(world, 6.0)
    world.command("uav0", 0.5, magnet=True)  # raise
    _run(world, 6.0)


def test_the_hook_lowers_grips_and_lifts_a_box_with_its_weight_on_the_cable() -> None:
    world = _world()
    lowering = world.reading("uav0")
    assert lowering.tension == pytest.approx(0.0, abs=1e-9)  # nothing stepped yet
    _run(world, 1.0)
    assert world.reading("uav0").tension == pytest.approx(HookParams().hook_mass * 9.81, rel=0.05)
    _pick_up(world)
    reading = world.reading("uav0")
    assert reading.carrying and reading.object_id == "box1"
    pose = world.pose("box1")
    assert pose.held_by == "uav0"
    assert pose.up > GROUND1 + 2.0
    weight = (5.0 + HookParams().hook_mass) * 9.81
    assert reading.tension == pytest.approx(weight, rel=0.05)
    force = world.cable_force("uav0")
    assert force[2] == pytest.approx(-weight, rel=0.05)  # pulls the aircraft down


def test_releasing_in_flight_drops_the_box_which_falls_and_rests() -> None:
    world = _world()
    _pick_up(world)
    world.inject("uav0", HookFault.RELEASE)
    _run(world, 0.3)
    assert not world.reading("uav0").carrying
    assert world.pose("box1").held_by == ""
    _run(world, 6.0)
    pose = world.pose("box1")
    assert pose.speed < 0.01
    assert pose.up == pytest.approx(WORLD.terrain.height(pose.east, pose.north), abs=0.02)
    # the light cable goes back to carrying the hook only
    assert world.reading("uav0").tension == pytest.approx(HookParams().hook_mass * 9.81, rel=0.1)


def test_hook_failure_grips_nothing_until_cleared() -> None:
    world = _world()
    world.inject("uav0", HookFault.HOOK_FAIL)
    _pick_up(world)
    assert not world.reading("uav0").carrying
    assert world.pose("box1").up == pytest.approx(GROUND1, abs=0.02)
    world.inject("uav0", HookFault.NONE)
    _pick_up(world)
    assert world.reading("uav0").object_id == "box1"


def test_a_mis_stocked_depot_hands_the_hook_a_box_of_other_contents() -> None:
    world = _world()
    world.inject("uav0", HookFault.WRONG_BOX)
    _pick_up(world)
    held = world.reading("uav0").object_id
    by_id = {o.id: o for o in WORLD.objects}
    assert held not in ("", "box1")
    assert by_id[held].contents is not by_id["box1"].contents
    # box1 took the gripped box's place in the depot
    assert world.pose("box1").up == pytest.approx(
        WORLD.terrain.height(by_id[held].east, by_id[held].north), abs=0.02
    )


def test_a_pickled_payload_world_continues_identically() -> None:
    world = _world()
    world.command("uav0", 2.95, magnet=True)
    _run(world, 4.0)
    copy = pickle.loads(pickle.dumps(world))
    world.command("uav0", 0.5, magnet=True)
    copy.command("uav0", 0.5, magnet=True)
    _run(world, 3.0)
    _run(copy, 3.0)
    assert copy.pose("box1") == world.pose("box1")
    assert copy.reading("uav0") == world.reading("uav0")


def test_a_carrier_holds_boxes_put_on_it_when_lifted() -> None:
    carrier = next(o for o in WORLD.objects if o.id == "carrier1")
    ground = WORLD.terrain.height(carrier.east, carrier.north)
    box = replace(BOX1, id="load", east=carrier.east, north=carrier.north)
    anchor = (carrier.east, carrier.north, ground + 3.0)
    world = PayloadWorld(WORLD.terrain, [carrier, box], {"uav0": anchor})
    east, north = carrier_slots(carrier, 0.4)[0]
    world.place("load", east, north, ground + 0.5)  # dropped onto its place
    _run(world, 2.0, anchor)
    on_ground = _distance(world.pose("load"), world.pose("carrier1"))
    # lower onto the lifting plate at the carrier's centre (its top is the carrier's height)
    world.command("uav0", 3.0 - carrier.size[2] + 0.05, magnet=True)
    _run(world, 6.0, anchor)
    assert world.reading("uav0").object_id == "carrier1"
    world.command("uav0", 1.0, magnet=True)
    _run(world, 5.0, anchor)
    load, lifted = world.pose("load"), world.pose("carrier1")
    assert lifted.up > ground + 1.0
    # the box rides on its place although the carrier swings and tilts under its load
    assert _distance(load, lifted) == pytest.approx(on_ground, abs=0.03)


def _distance(a: PayloadPose, b: PayloadPose) -> float:
    return math.dist((a.east, a.north, a.up), (b.east, b.north, b.up))


@pytest.mark.parametrize(("aboard", "lifts"), [(4, False), (2, True)])
def test_a_loaded_carrier_lifts_only_below_the_winch_rating(aboard: int, lifts: bool) -> None:
    carrier = next(o for o in WORLD.objects if o.id == "carrier3")
    loaded = [o for o in WORLD.objects if o.on == "carrier3"]
    boxes = loaded if aboard == 4 else [loaded[0], loaded[3]]  # two at opposite corners
    ground = WORLD.terrain.height(carrier.east, carrier.north)
    # the magnet lands off the plate's centre; its eye centres the carrier under the hook
    anchor = (carrier.east + 0.07, carrier.north + 0.05, ground + 3.0)
    world = PayloadWorld(WORLD.terrain, [carrier, *boxes], {"uav0": anchor})
    _run(world, 1.0, anchor)
    world.command("uav0", 3.0 - carrier.size[2] + 0.05, magnet=True)  # onto the lifting plate
    _run(world, 6.0, anchor)
    assert world.reading("uav0").object_id == "carrier3"
    world.command("uav0", 1.0, magnet=True)
    _run(world, 6.0, anchor)
    load = (8.0 + 5.0 * aboard + HookParams().hook_mass) * 9.81
    reading = world.reading("uav0")
    if lifts:  # the boxes ride on their places
        assert world.pose("carrier3").up > ground + 1.0
        assert all(world.pose(box.id).up > ground + 1.0 for box in boxes)
        assert reading.tension == pytest.approx(load, rel=0.08)
    else:  # the drum stops: the carrier stays on the ground
        assert reading.winch is WinchState.STALLED
        assert world.pose("carrier3").up < ground + 0.1  # not even one edge rises
        assert all(world.pose(box.id).up < ground + 0.1 for box in boxes)
        assert reading.tension > HookParams().stall_tension
