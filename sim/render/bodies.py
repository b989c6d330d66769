"""Meshes of the dynamic objects: people in lying and sitting poses, dummies, animals, cars, boxes.

People and dummies are articulated primitives (head, torso, upper and lower limbs, hands, feet);
the pose, clothing and skin colours are drawn from a stream seeded by the object id, so the same
world renders the same people in every run. The local frame of an object is x forward (towards
the head of a lying person, the nose of a car), y left, z up, origin on the ground at its
position; the world file's ``size`` scales the model.
"""

from __future__ import annotations

import enum
import math
import zlib

import numpy as np
from numpy.typing import NDArray

from sim.render.materials import ThermalEnvironment
from sim.render.meshes import MeshBuilder, rot_up
from sim.world import DynamicObject, ObjectKind

SHIRTS = (
    (0.62, 0.08, 0.08),
    (0.10, 0.22, 0.58),
    (0.85, 0.85, 0.82),
    (0.12, 0.32, 0.16),
    (0.86, 0.70, 0.12),
    (0.45, 0.45, 0.47),
    (0.08, 0.08, 0.09),
    (0.90, 0.42, 0.10),
)
TROUSERS = (
    (0.14, 0.20, 0.40),
    (0.07, 0.07, 0.08),
    (0.55, 0.48, 0.32),
    (0.35, 0.35, 0.36),
    (0.30, 0.20, 0.12),
)
SKINS = (
    (0.96, 0.80, 0.69),
    (0.90, 0.72, 0.58),
    (0.78, 0.57, 0.44),
    (0.62, 0.43, 0.30),
    (0.45, 0.30, 0.20),
    (0.30, 0.20, 0.14),
)
FURS = ((0.40, 0.26, 0.14), (0.85, 0.83, 0.78), (0.12, 0.10, 0.09), (0.55, 0.50, 0.45))
CAR_PAINTS = (
    (0.75, 0.05, 0.05),
    (0.85, 0.85, 0.87),
    (0.05, 0.05, 0.06),
    (0.15, 0.25, 0.60),
    (0.50, 0.52, 0.55),
)
DUMMY_SKIN = (0.85, 0.78, 0.70)

CLOTHING_BELOW_SKIN_K = 2.5
"""Clothing surface is cooler than exposed skin."""
ENGINE_HOOD_ABOVE_BODY_K = 15.0
"""Warm engine under the hood of a car that has been driven."""
DUMMY_ABOVE_AMBIENT_K = 4.0
"""A dummy has no body heat: its surface is the air temperature plus some sun."""
OBJECT_ABOVE_AMBIENT_K = 2.0
"""Boxes and carriers in the sun."""


class Pose(enum.Enum):
    """How a person (or dummy) lies or sits."""

    ON_BACK = "on_back"
    ON_SIDE = "on_side"
    SITTING = "sitting"


POSE_WEIGHTS = {Pose.ON_BACK: 0.5, Pose.ON_SIDE: 0.25, Pose.SITTING: 0.25}


def object_rng(ident: str) -> np.random.Generator:
    """The random stream of one object (seeded by its id, stable across runs)."""
    return np.random.default_rng(zlib.crc32(ident.encode("utf-8")))


def choose(
    rng: np.random.Generator, options: tuple[tuple[float, float, float], ...]
) -> NDArray[np.float64]:
    """One colour of a palette, slightly varied."""
    base = np.asarray(options[int(rng.integers(len(options)))])
    varied: NDArray[np.float64] = np.clip(base * rng.uniform(0.9, 1.1), 0.0, 1.0)
    return varied


class _Placer:
    """Writes local-frame primitives of one object into a mesh in world coordinates."""

    def __init__(self, mesh: MeshBuilder, obj: DynamicObject, ground: float, scale: float) -> None:
        self.mesh = mesh
        self.rotation = rot_up(obj.heading)
        self.origin = np.array([obj.east, obj.north, ground])
        self.scale = scale

    def world(self, local: tuple[float, float, float]) -> NDArray[np.float64]:
        point: NDArray[np.float64] = self.origin + self.rotation @ (np.asarray(local) * self.scale)
        return point

    def limb(
        self,
        a: tuple[float, float, float],
        b: tuple[float, float, float],
        width: float,
        albedo: NDArray[np.float64],
        temperature: float,
    ) -> None:
        s = self.scale
        self.mesh.segment(
            self.world(a), self.world(b), width * s, width * s * 0.8, albedo, temperature
        )

    def box(
        self,
        center: tuple[float, float, float],
        size: tuple[float, float, float],
        albedo: NDArray[np.float64],
        temperature: float,
    ) -> None:
        s = self.scale
        self.mesh.box(
            self.world(center),
            (size[0] * s, size[1] * s, size[2] * s),
            self.rotation,
            albedo,
            temperature,
        )

    def ball(
        self,
        center: tuple[float, float, float],
        radius: tuple[float, float, float],
        albedo: NDArray[np.float64],
        temperature: float,
    ) -> None:
        s = self.scale
        self.mesh.sphere(
            self.world(center),
            (radius[0] * s, radius[1] * s, radius[2] * s),
            self.rotation,
            albedo,
            temperature,
        )


def add_person(
    mesh: MeshBuilder, obj: DynamicObject, ground: float, skin_k: float, dummy: bool
) -> Pose:
    """A person (or a dummy: pale plastic skin) in a seeded pose; returns the pose."""
    rng = object_rng(obj.id)
    poses = list(POSE_WEIGHTS)
    pose = poses[int(rng.choice(len(poses), p=list(POSE_WEIGHTS.values())))]
    shirt, trousers = choose(rng, SHIRTS), choose(rng, TROUSERS)
    skin = np.asarray(DUMMY_SKIN) if dummy else choose(rng, SKINS)
    cloth_k = skin_k if dummy else skin_k - CLOTHING_BELOW_SKIN_K
    p = _Placer(mesh, obj, ground, obj.size[0] / 1.8)
    arm = math.radians(float(rng.uniform(5.0, 80.0)))
    arm2 = math.radians(float(rng.uniform(5.0, 80.0)))
    spread = math.radians(float(rng.uniform(2.0, 20.0)))
    if pose is Pose.SITTING:
        p.box((-0.05, 0.0, 0.45), (0.22, 0.38, 0.6), shirt, cloth_k)
        p.ball((-0.03, 0.0, 0.88), (0.1, 0.09, 0.12), skin, skin_k)
        for side in (1.0, -1.0):
            p.limb((-0.05, 0.1 * side, 0.12), (0.4, 0.12 * side, 0.14), 0.15, trousers, cloth_k)
            p.limb((0.4, 0.12 * side, 0.14), (0.82, 0.16 * side, 0.06), 0.12, trousers, cloth_k)
            p.box((0.86, 0.16 * side, 0.1), (0.08, 0.09, 0.16), trousers * 0.5, cloth_k)
            p.limb((-0.05, 0.22 * side, 0.68), (0.05, 0.27 * side, 0.42), 0.09, shirt, cloth_k)
            p.limb((0.05, 0.27 * side, 0.42), (0.3, 0.22 * side, 0.3), 0.08, shirt, cloth_k)
            p.ball((0.34, 0.22 * side, 0.29), (0.06, 0.04, 0.04), skin, skin_k)
        return pose
    narrow = 0.55 if pose is Pose.ON_SIDE else 1.0
    z = 0.11 if pose is Pose.ON_BACK else 0.17
    p.box((0.22, 0.0, z), (0.62, 0.38 * narrow, 0.22 / narrow * 0.9), shirt, cloth_k)
    p.ball((0.66, 0.0, 0.1), (0.12, 0.09, 0.1), skin, skin_k)
    for side, angle in ((1.0, arm), (-1.0, arm2)):
        shoulder = (0.46, 0.21 * side * narrow, z)
        elbow = (0.46 - 0.3 * math.cos(angle), (0.21 * narrow + 0.3 * math.sin(angle)) * side, 0.07)
        bend = angle * 0.6 if pose is Pose.ON_BACK else angle + 0.8
        hand = (elbow[0] - 0.28 * math.cos(bend), elbow[1] + 0.28 * math.sin(bend) * side, 0.06)
        p.limb(shoulder, elbow, 0.09, shirt, cloth_k)
        p.limb(elbow, hand, 0.08, shirt, cloth_k)
        p.ball(hand, (0.07, 0.05, 0.03), skin, skin_k)
        hip = (-0.08, 0.1 * side * narrow, 0.09)
        knee_y = 0.1 * narrow + 0.45 * math.sin(spread)
        if pose is Pose.ON_SIDE:  # legs drawn up in front of the body
            knee = (-0.4, 0.25 * side + 0.25, 0.12)
            foot = (-0.8, 0.2 * side + 0.3, 0.08)
        else:
            knee = (-0.53, knee_y * side, 0.08)
            foot = (-0.53 - 0.42 * math.cos(spread), (knee_y + 0.1 * math.sin(spread)) * side, 0.07)
        p.limb(hip, knee, 0.15, trousers, cloth_k)
        p.limb(knee, foot, 0.12, trousers, cloth_k)
        p.box((foot[0] - 0.05, foot[1], 0.08), (0.1, 0.09, 0.16), trousers * 0.5, cloth_k)
    return pose


def add_animal(mesh: MeshBuilder, obj: DynamicObject, ground: float, fur_k: float) -> None:
    """A standing four-legged animal (dog, sheep, deer): body, neck, head, legs."""
    rng = object_rng(obj.id)
    fur = choose(rng, FURS)
    length, width, height = obj.size
    p = _Placer(mesh, obj, ground, 1.0)
    leg = 0.55 * height
    body_z = leg + 0.2 * height
    p.ball((0.0, 0.0, body_z), (0.45 * length, 0.5 * width, 0.22 * height), fur, fur_k)
    p.limb(
        (0.38 * length, 0.0, body_z), (0.5 * length, 0.0, 0.95 * height), 0.12 * length, fur, fur_k
    )
    p.ball(
        (0.55 * length, 0.0, 0.95 * height), (0.1 * length, 0.2 * width, 0.08 * height), fur, fur_k
    )
    for dx in (0.3, -0.3):
        for side in (1.0, -1.0):
            top = (dx * length, 0.3 * width * side, body_z)
            p.limb(top, (dx * length, 0.3 * width * side, 0.0), 0.06 * length, fur, fur_k)


def add_car(mesh: MeshBuilder, obj: DynamicObject, ground: float, body_k: float) -> None:
    """A car: lower body, cabin, four wheels and a warm engine hood at the front.

    The body has the object's ``paint`` if it has one (a colour a tracker is told), else a
    colour of ``CAR_PAINTS`` drawn by its id.
    """
    rng = object_rng(obj.id)
    paint = choose(rng, CAR_PAINTS) if obj.paint is None else np.asarray(obj.paint)
    length, width, height = obj.size
    p = _Placer(mesh, obj, ground, 1.0)
    lower = 0.5 * height
    p.box((0.0, 0.0, 0.15 * height + lower / 2), (length, width, lower), paint, body_k)
    p.box(
        (0.32 * length, 0.0, 0.15 * height + lower + 0.01),
        (0.3 * length, 0.9 * width, 0.02),
        paint,
        body_k + ENGINE_HOOD_ABOVE_BODY_K,
    )
    p.box(
        (-0.1 * length, 0.0, 0.15 * height + lower + 0.35 * height / 2),
        (0.5 * length, 0.86 * width, 0.35 * height),
        paint * 0.35 + 0.1,
        body_k,
    )
    tyre = np.array([0.05, 0.05, 0.05])
    for dx in (0.32, -0.32):
        for side in (1.0, -1.0):
            p.box(
                (dx * length, 0.45 * width * side, 0.17 * height),
                (0.34 * height * 1.3, 0.12 * width, 0.34 * height),
                tyre,
                body_k,
            )


def add_object(
    mesh: MeshBuilder, obj: DynamicObject, ground: float, env: ThermalEnvironment
) -> None:
    """Add the mesh of any dynamic object."""
    match obj.kind:
        case ObjectKind.PERSON:
            add_person(mesh, obj, ground, obj.temperature or env.ambient + 18.0, dummy=False)
        case ObjectKind.DUMMY:
            warm = obj.temperature or env.ambient + DUMMY_ABOVE_AMBIENT_K
            add_person(mesh, obj, ground, warm, dummy=True)
        case ObjectKind.ANIMAL:
            add_animal(mesh, obj, ground, obj.temperature or env.ambient + 15.0)
        case ObjectKind.CAR:
            add_car(mesh, obj, ground, obj.temperature or env.ambient + 5.0)
        case ObjectKind.BOX | ObjectKind.CARRIER:
            rng = object_rng(obj.id)
            colour = (0.55, 0.40, 0.22) if obj.kind is ObjectKind.BOX else (0.4, 0.42, 0.45)
            colour_arr = np.asarray(colour) * rng.uniform(0.9, 1.1)
            length, width, height = obj.size
            mesh.box(
                (obj.east, obj.north, ground + height / 2),
                (length, width, height),
                rot_up(obj.heading),
                colour_arr,
                env.ambient + OBJECT_ABOVE_AMBIENT_K,
            )
