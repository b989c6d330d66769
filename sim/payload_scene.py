"""MuJoCo model (MJCF) of the payload world: boxes, carriers and one hook per aircraft.

MuJoCo's axes are the world's local ENU axes (x east, y north, z up), in metres. Every body's
origin is its *bottom centre* (the point world objects are placed by); a carrier is a tray (a
base plate and four low walls) so that boxes put on it stay on it when it is lifted.

Terrain: MuJoCo's height-field contacts with boxes jitter and, on a grid as coarse as a world
file's (100 m), let boxes sink through (measured while writing this module), so the terrain is
not a MuJoCo geom. Each body instead touches its own plane (in a mocap body: MuJoCo moves static
world geoms only at load), which :mod:`sim.payload` keeps tangent to the world's bilinear
terrain under the body every step: the contact sees exactly the
height :class:`sim.terrain.Terrain` gives, and box-on-plane contacts rest without jitter.
Buildings are not in this model (a box dropped on a roof falls to the ground).

Each aircraft is a heavy anchor on three slide joints, put at its winch every step; the hook is
a free sphere on a rope (a spatial tendon whose upper length limit is the winch's cable length). The
magnet's grip is a ``connect`` equality between the hook and an object, one per (hook, object)
pair, inactive until the hook grips; a wound-in hook is held in its cradle under the winch by
another one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from sim.hook import HookParams
from sim.world import DynamicObject, ObjectKind

PAYLOAD_KINDS = (ObjectKind.BOX, ObjectKind.CARRIER)
"""World objects simulated as rigid bodies."""
TIMESTEP = 0.005
"""s, MuJoCo step (one per 200 Hz flight-model step)."""
WALL = 0.03
"""m, thickness of a carrier's base and walls."""
WALL_HEIGHT = 0.06
"""m, height of a carrier's rim above its base."""
POST = 0.03
"""m, half width of a carrier's central lifting post."""
LIFT_PLATE = 0.02
"""m, thickness of the steel plate on the post's top that the magnet grips (0.16 m square)."""
HOOK_DAMPING = 0.3
"""N s/m (and N m s/rad) on the hook's motion: air drag of hook and cable, which keeps a
pendulum whose cable is wound in from spinning up like a yo-yo."""
ANCHOR_MASS = 1.0e4
"""kg of a winch anchor: the cable's pull moves it by nanometres within a step."""
FRICTION = 0.8
DEFAULT_MASS = {ObjectKind.BOX: 5.0, ObjectKind.CARRIER: 8.0}
"""kg, when the world file gives none."""


@dataclass(frozen=True, slots=True)
class BodyNames:
    """MJCF names of one payload object."""

    body: str
    plane: str
    pair_prefix: str


def body_names(object_id: str) -> BodyNames:
    """Names of an object's body and its terrain plane."""
    return BodyNames(f"obj:{object_id}", f"ground:{object_id}", f"pair:{object_id}")


def hook_names(agent: str) -> tuple[str, str, str, str]:
    """(anchor body, hook body, tendon, ground plane) names of one agent's hook."""
    return (f"anchor:{agent}", f"hook:{agent}", f"cable:{agent}", f"ground:hook:{agent}")


def cradle_name(agent: str) -> str:
    """Name of the equality that holds ``agent``'s wound-in hook in its cradle."""
    return f"cradle:{agent}"


def grip_name(agent: str, object_id: str) -> str:
    """Name of the equality that attaches ``object_id`` to ``agent``'s hook."""
    return f"grip:{agent}:{object_id}"


def _quat_heading(heading: float) -> str:
    """MJCF quaternion of a heading (rad clockwise from north) about +z."""
    yaw = math.pi / 2.0 - heading
    return f"{math.cos(yaw / 2.0):.9f} 0 0 {math.sin(yaw / 2.0):.9f}"


def _geoms(obj: DynamicObject) -> list[tuple[str, str, str]]:
    """(name, half sizes, position) of an object's box geoms, in its body frame."""
    length, width, height = obj.size
    hx, hy, hz = length / 2.0, width / 2.0, height / 2.0
    if obj.kind is ObjectKind.BOX:
        return [(f"{obj.id}", f"{hx} {hy} {hz}", f"0 0 {hz}")]
    w = WALL / 2.0
    wall_z = WALL + WALL_HEIGHT / 2.0
    wh = WALL_HEIGHT / 2.0
    post = (height - WALL - LIFT_PLATE) / 2.0
    return [
        (f"{obj.id}:post", f"{POST} {POST} {post}", f"0 0 {WALL + post}"),
        (
            f"{obj.id}:plate",
            f"{LIFT_PLATE * 4} {LIFT_PLATE * 4} {LIFT_PLATE / 2}",
            f"0 0 {height - LIFT_PLATE / 2}",
        ),
        (f"{obj.id}:base", f"{hx + WALL} {hy + WALL} {w}", f"0 0 {w}"),
        # the rim stands outside the footprint: the whole length x width holds boxes
        (f"{obj.id}:front", f"{w} {hy + WALL} {wh}", f"{hx + w} 0 {wall_z}"),
        (f"{obj.id}:back", f"{w} {hy + WALL} {wh}", f"{-hx - w} 0 {wall_z}"),
        (f"{obj.id}:left", f"{hx} {w} {wh}", f"0 {hy + w} {wall_z}"),
        (f"{obj.id}:right", f"{hx} {w} {wh}", f"0 {-hy - w} {wall_z}"),
    ]


def _plane(name: str, east: float, north: float, up: float) -> str:
    """A ground plane in its own mocap body (MuJoCo moves static world geoms only at load)."""
    return (
        f'<body name="{name}" mocap="true" pos="{east} {north} {up}">'
        f'<geom name="{name}" type="plane" size="0 0 1" contype="0" conaffinity="0"/></body>'
    )


def carrier_slots(carrier: DynamicObject, box_length: float) -> list[tuple[float, float]]:
    """Box places on a carrier (ENU m): up to two boxes across on each side of the post.

    ``capacity`` places alternating between the two halves along the carrier's length; the
    boxes' centres sit ``box_length`` apart across the carrier's width.
    """
    capacity = carrier.capacity or 0
    length, _, _ = carrier.size
    along = (length / 2.0 + POST + LIFT_PLATE * 4) / 2.0
    across = box_length / 2.0
    s, c = math.sin(carrier.heading), math.cos(carrier.heading)  # length axis (east, north)
    out = []
    for i in range(capacity):
        a = along if i % 2 == 0 else -along
        b = across if (i // 2) % 2 == 0 else -across
        # across axis: heading + 90 deg
        out.append((carrier.east + a * s + b * c, carrier.north + a * c - b * s))
    return out


def object_mass(obj: DynamicObject) -> float:
    """Mass of a payload object, kg."""
    return obj.mass if obj.mass is not None else DEFAULT_MASS[obj.kind]


def scene_xml(
    objects: list[tuple[DynamicObject, float]],
    agents: list[tuple[str, tuple[float, float, float]]],
    hook: HookParams,
) -> str:
    """MJCF of the payload world.

    Args:
        objects: Boxes and carriers with the terrain height under each (a box ``on`` a
            carrier starts on the carrier's base).
        agents: Agent names with their winch anchor position (ENU, m).
        hook: Winch and magnet ratings.

    """
    world: list[str] = []
    contacts: list[str] = []
    equalities: list[str] = []
    tendons: list[str] = []
    for obj, ground in objects:
        names = body_names(obj.id)
        world.append(_plane(names.plane, obj.east, obj.north, ground))
        mass = object_mass(obj)
        geoms = _geoms(obj)
        share = mass / len(geoms)
        rest = ground + (WALL if obj.on else 0.0)  # a loaded box stands on its carrier's base
        body = [
            f'<body name="{names.body}" pos="{obj.east} {obj.north} {rest + 0.002}" '
            f'quat="{_quat_heading(obj.heading)}"><freejoint/>'
        ]
        for name, half, pos in geoms:
            body.append(
                f'<geom name="{name}" type="box" size="{half}" pos="{pos}" mass="{share}" '
                f'friction="{FRICTION} 0.005 0.0001"/>'
            )
            contacts.append(f'<pair geom1="{names.plane}" geom2="{name}"/>')
        body.append("</body>")
        world.append("".join(body))
    r = hook.hook_radius
    for agent, (e, n, u) in agents:
        anchor, hook_body, cable, plane = hook_names(agent)
        # the winch: moved with the aircraft through three slide joints (position and velocity
        # set every step), so the rope's constraint sees the true relative velocity of its ends
        # (a mocap anchor has no velocity: the constraint's damping then acts on the hook's
        # absolute velocity and throws it about at cruise speed); heavy, weightless, not colliding
        slides = "".join(
            f'<joint name="{anchor}:{axis}" type="slide" axis="{vec}" damping="0"/>'
            for axis, vec in (("e", "1 0 0"), ("n", "0 1 0"), ("u", "0 0 1"))
        )
        world.append(
            f'<body name="{anchor}" pos="0 0 0" gravcomp="1">{slides}'
            f'<geom type="sphere" size="0.05" mass="{ANCHOR_MASS}" contype="0" conaffinity="0"/>'
            f'<site name="{anchor}"/></body>'
        )
        world.append(_plane(plane, e, n, u - 1.0))
        world.append(
            f'<body name="{hook_body}" pos="{e} {n} {u - hook.stowed_cable}">'
            f'<joint type="free" damping="{HOOK_DAMPING}"/>'
            f'<geom name="{hook_body}" type="sphere" size="{r}" mass="{hook.hook_mass}"/>'
            f'<site name="{hook_body}"/></body>'
        )
        contacts.append(f'<pair geom1="{plane}" geom2="{hook_body}"/>')
        equalities.append(
            f'<connect name="{cradle_name(agent)}" body1="{anchor}" body2="{hook_body}" '
            f'anchor="0 0 {-hook.stowed_cable}" active="false"/>'
        )
        tendons.append(
            f'<spatial name="{cable}" limited="true" range="0 {hook.stowed_cable}" width="0.01">'
            f'<site site="{anchor}"/><site site="{hook_body}"/></spatial>'
        )
        for obj, _ in objects:
            equalities.append(
                f'<connect name="{grip_name(agent, obj.id)}" body1="{hook_body}" '
                f'body2="{body_names(obj.id).body}" anchor="0 0 {-r}" active="false"/>'
            )
    return (
        '<mujoco model="payload">'
        f'<option timestep="{TIMESTEP}" cone="elliptic" impratio="10">'
        '<flag sleep="enable"/></option>'
        f"<worldbody>{''.join(world)}</worldbody>"
        f"<contact>{''.join(contacts)}</contact>"
        f"<tendon>{''.join(tendons)}</tendon>"
        f"<equality>{''.join(equalities)}</equality>"
        "</mujoco>"
    )
