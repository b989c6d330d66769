"""Payload rigid bodies (chapter section 11.1.2): boxes, carriers and hooks in MuJoCo.

The chapter's simulator used the Open Dynamics Engine so that dropped boxes bounce and roll;
this one uses MuJoCo (``mujoco`` from PyPI). :class:`PayloadWorld` owns the model of
:mod:`sim.payload_scene` and, each flight-model step, moves every aircraft's winch anchor, steps
the rigid bodies, winds each winch (:class:`sim.hook.Hook`) under the measured pull of the
cable (the constraint force of rope and cradle on the winch, which the aircraft feels too),
lets magnets grip what they touch or let go, and returns the cable force on each aircraft, which
:mod:`sim.world_sim` feeds into JSBSim. Deterministic: no randomness, fixed step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from sim.hook import Hook, HookFault, HookParams, HookReading
from sim.payload_scene import (
    PAYLOAD_KINDS,
    TIMESTEP,
    body_names,
    cradle_name,
    grip_name,
    hook_names,
    object_mass,
    scene_xml,
)
from sim.terrain import Terrain
from sim.world import BoxContents, DynamicObject, ObjectKind

Vec3 = tuple[float, float, float]
SWAP_RADIUS = 25.0
"""m: a mis-stocked depot swaps the gripped box with one of other contents this close."""
_SLOPE_STEP = 0.5
"""m, finite-difference step of the terrain slope under a body."""
_FOLLOW = 0.01
"""m a body moves before its ground plane follows it."""


@dataclass(frozen=True, slots=True)
class PayloadPose:
    """Where a payload object is: bottom centre (ENU, m), heading and who holds it."""

    east: float
    north: float
    up: float
    heading: float
    held_by: str
    speed: float
    """m/s of the body's origin (0 at rest)."""


class PayloadWorld:
    """Boxes, carriers and one hook per agent, stepped with the flight models."""

    def __init__(
        self,
        terrain: Terrain,
        objects: list[DynamicObject],
        anchors: dict[str, Vec3],
        params: HookParams | None = None,
    ) -> None:
        """Build the model with every box and carrier of ``objects`` at rest on the terrain.

        Args:
            terrain: The world's terrain.
            objects: World objects; those of kind box or carrier become rigid bodies.
            anchors: Winch anchor of each agent, ENU m (the hook hangs stowed below it).
            params: Hook ratings (same for every agent).

        """
        self.terrain = terrain
        self.params = params or HookParams()
        self.objects = {o.id: o for o in objects if o.kind in PAYLOAD_KINDS}
        placed = [(o, terrain.height(o.east, o.north)) for o in self.objects.values()]
        self.xml = scene_xml(placed, sorted(anchors.items()), self.params)
        self.hooks = {agent: Hook(self.params) for agent in sorted(anchors)}
        self._last_anchor = dict(anchors)
        self._build()

    def _build(self) -> None:
        m = self.model = mujoco.MjModel.from_xml_string(self.xml)
        self.data = mujoco.MjData(m)

        def ident(kind: mujoco.mjtObj, name: str) -> int:
            return int(mujoco.mj_name2id(m, kind, name))

        body, geom = mujoco.mjtObj.mjOBJ_BODY, mujoco.mjtObj.mjOBJ_GEOM
        self._body = {oid: ident(body, body_names(oid).body) for oid in self.objects}
        self._owner = {int(g): oid for oid, b in self._body.items() for g in _geoms_of(m, b)}
        planes = [_mocap(m, ident(body, body_names(oid).plane)) for oid in self.objects]
        bodies = [self._body[oid] for oid in self.objects]
        self._anchor: dict[str, tuple[int, int]] = {}
        """(qpos, dof) address of each agent's winch anchor's first slide joint."""
        self._hook_body: dict[str, int] = {}
        self._hook_geom: dict[str, int] = {}
        self._tendon: dict[str, int] = {}
        self._grip: dict[tuple[str, str], int] = {}
        self._cradle: dict[str, int] = {}
        for agent in self.hooks:
            anchor, hook, cable, plane = hook_names(agent)
            joint = int(m.body_jntadr[ident(body, anchor)])
            self._anchor[agent] = (int(m.jnt_qposadr[joint]), int(m.jnt_dofadr[joint]))
            self._put_anchor(agent, self._last_anchor[agent], (0.0, 0.0, 0.0))
            self._hook_body[agent] = ident(body, hook)
            self._hook_geom[agent] = ident(geom, hook)
            self._tendon[agent] = ident(mujoco.mjtObj.mjOBJ_TENDON, cable)
            # hook and winch never sleep: the aircraft moves them without a contact to wake them
            self._cradle[agent] = ident(mujoco.mjtObj.mjOBJ_EQUALITY, cradle_name(agent))
            m.eq_data[self._cradle[agent], 3:6] = 0.0  # the hook's centre (compiled elsewhere)
            for b in (self._hook_body[agent], ident(body, anchor)):
                m.tree_sleep_policy[int(m.body_treeid[b])] = mujoco.mjtSleepPolicy.mjSLEEP_NEVER
            planes.append(_mocap(m, ident(body, plane)))
            bodies.append(self._hook_body[agent])
            for oid in self.objects:
                self._grip[(agent, oid)] = ident(
                    mujoco.mjtObj.mjOBJ_EQUALITY, grip_name(agent, oid)
                )
        self._planes = np.array(planes, dtype=np.int64)
        """Mocap index of the ground plane of each body in ``_plane_bodies``."""
        self._plane_bodies = np.array(bodies, dtype=np.int64)
        self._plane_xy = np.full((len(planes), 2), np.inf)
        self._forces: dict[str, Vec3] = {agent: (0.0, 0.0, 0.0) for agent in self.hooks}
        self._follow_terrain()
        mujoco.mj_forward(m, self.data)

    # ------------------------------------------------------------- pickling
    def __getstate__(self) -> dict[str, Any]:
        """Checkpoint: the MJCF and the simulation state, not MuJoCo's C objects."""
        d, m = self.data, self.model
        state = {k: v for k, v in self.__dict__.items() if not k.startswith("_") and k != "data"}
        del state["model"]
        state["_arrays"] = {
            "qpos": d.qpos.copy(),
            "qvel": d.qvel.copy(),
            "qacc_warmstart": d.qacc_warmstart.copy(),
            "eq_active": d.eq_active.copy(),
            "eq_data": m.eq_data.copy(),
            "tendon_range": m.tendon_range.copy(),
            "time": np.array([d.time]),
        }
        state["_forces"] = self._forces
        state["_last_anchor"] = self._last_anchor
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        """Restore: rebuild the model and put the state back."""
        arrays = state.pop("_arrays")
        forces = state.pop("_forces")
        self._last_anchor = state.pop("_last_anchor")
        self.__dict__.update(state)
        self._build()
        d, m = self.data, self.model
        d.qpos[:] = arrays["qpos"]
        d.qvel[:] = arrays["qvel"]
        d.qacc_warmstart[:] = arrays["qacc_warmstart"]
        d.eq_active[:] = arrays["eq_active"]
        m.eq_data[:] = arrays["eq_data"]
        m.tendon_range[:] = arrays["tendon_range"]
        d.time = float(arrays["time"][0])
        mujoco.mj_forward(m, d)
        self._forces = forces

    # ------------------------------------------------------------------ step
    def step(self, dt: float, anchors: dict[str, Vec3]) -> None:
        """Advance by ``dt`` (a multiple of the MuJoCo step) with the winches at ``anchors``."""
        m, d = self.model, self.data
        for agent, pos in anchors.items():
            last = self._last_anchor[agent]
            velocity = ((pos[0] - last[0]) / dt, (pos[1] - last[1]) / dt, (pos[2] - last[2]) / dt)
            self._put_anchor(agent, pos, velocity)
            self._last_anchor[agent] = pos
        for agent, hook in self.hooks.items():
            m.tendon_range[self._tendon[agent], 1] = hook.length
            stowed = hook.length <= self.params.stowed_cable + 1e-9 and hook.target <= hook.length
            d.eq_active[self._cradle[agent]] = 1 if stowed else 0
        for _ in range(max(1, round(dt / TIMESTEP))):
            self._follow_terrain()
            mujoco.mj_step(m, d)
        for agent, hook in self.hooks.items():
            pull = self._pull(agent)
            hook.step(dt, math.sqrt(pull[0] ** 2 + pull[1] ** 2 + pull[2] ** 2))
            self._forces[agent] = pull
            if hook.must_let_go():
                self._let_go(agent)
            elif hook.may_grip():
                touched = self._touching(agent)
                if touched is not None:
                    self._grip_object(agent, touched)

    def _put_anchor(self, agent: str, pos: Vec3, velocity: Vec3) -> None:
        """Winch anchor of ``agent`` at ``pos`` (ENU m) moving at ``velocity`` (m/s)."""
        q, v = self._anchor[agent]
        self.data.qpos[q : q + 3] = pos
        self.data.qvel[v : v + 3] = velocity

    def _pull(self, agent: str) -> Vec3:
        """Force of cable and cradle on ``agent``'s winch, N ENU (the constraint force on it)."""
        _, v = self._anchor[agent]
        f = self.data.qfrc_constraint[v : v + 3]
        return (float(f[0]), float(f[1]), float(f[2]))

    def _follow_terrain(self) -> None:
        """Move the ground plane of every body that moved under it, tangent to the terrain."""
        d = self.data
        xy = d.xpos[self._plane_bodies, :2]
        moved = np.nonzero(np.abs(xy - self._plane_xy).max(axis=1) > _FOLLOW)[0]
        if moved.size == 0:
            return
        height = self.terrain.height
        s = _SLOPE_STEP
        for i in moved.tolist():
            e, n = float(xy[i, 0]), float(xy[i, 1])
            gx = (height(e + s, n) - height(e - s, n)) / (2.0 * s)
            gy = (height(e, n + s) - height(e, n - s)) / (2.0 * s)
            plane = int(self._planes[i])
            d.mocap_pos[plane] = (e, n, height(e, n))
            d.mocap_quat[plane] = _tilt_quat(gx, gy)
            self._plane_xy[i] = (e, n)

    # ------------------------------------------------------------- gripping
    def _touching(self, agent: str) -> str | None:
        """The payload object the hook's magnet touches (the first contact), or None."""
        d = self.data
        hook_geom = self._hook_geom[agent]
        for i in range(d.ncon):
            c = d.contact[i]
            other = c.geom2 if c.geom1 == hook_geom else c.geom1 if c.geom2 == hook_geom else -1
            owner = self._owner.get(int(other))
            if owner is not None and self.held_by(owner) == "":
                return owner
        return None

    def _grip_object(self, agent: str, touched: str) -> None:
        hook = self.hooks[agent]
        target = touched
        if hook.wrong_box:
            other = self._swap_partner(touched)
            if other is not None:
                self._swap(touched, other)
                target = other
        d, m = self.data, self.model
        eq = self._grip[(agent, target)]
        body = self._body[target]
        obj = self.objects[target]
        if obj.kind is ObjectKind.CARRIER:
            # the lifting plate's eye centres the carrier under the hook: lifted off centre, it
            # would tip onto one edge and shed its boxes
            local = np.array([0.0, 0.0, obj.size[2]])
        else:
            point = d.xpos[self._hook_body[agent]] - np.array([0.0, 0.0, self.params.hook_radius])
            local = d.xmat[body].reshape(3, 3).T @ (point - d.xpos[body])
        m.eq_data[eq, 0:3] = (0.0, 0.0, -self.params.hook_radius)
        m.eq_data[eq, 3:6] = local
        d.eq_active[eq] = 1
        hook.gripped(target)

    def _let_go(self, agent: str) -> None:
        hook = self.hooks[agent]
        if hook.held is not None:
            self.data.eq_active[self._grip[(agent, hook.held)]] = 0
        hook.let_go()

    def _swap_partner(self, touched: str) -> str | None:
        """Nearest free box of other contents within SWAP_RADIUS of ``touched``, or None."""
        obj = self.objects[touched]
        if obj.kind is not ObjectKind.BOX:
            return None
        here = self.data.xpos[self._body[touched]]
        best: tuple[float, str] | None = None
        for oid, other in self.objects.items():
            if other.kind is not ObjectKind.BOX or _contents(other) == _contents(obj):
                continue
            if self.held_by(oid):
                continue
            dist = float(np.linalg.norm(self.data.xpos[self._body[oid]] - here))
            if dist <= SWAP_RADIUS and (best is None or dist < best[0]):
                best = (dist, oid)
        return None if best is None else best[1]

    def _swap(self, a: str, b: str) -> None:
        """Exchange two resting objects' poses (a mis-stocked depot)."""
        m, d = self.model, self.data
        qa = int(m.jnt_qposadr[m.body_jntadr[self._body[a]]])
        qb = int(m.jnt_qposadr[m.body_jntadr[self._body[b]]])
        pa, pb = d.qpos[qa : qa + 7].copy(), d.qpos[qb : qb + 7].copy()
        d.qpos[qa : qa + 7], d.qpos[qb : qb + 7] = pb, pa
        for q in (qa, qb):
            va = int(m.jnt_dofadr[m.body_jntadr[self._body[a if q == qa else b]]])
            d.qvel[va : va + 6] = 0.0
        self._plane_xy[:] = np.inf
        mujoco.mj_forward(m, d)

    # ---------------------------------------------------------------- inputs
    def command(self, agent: str, cable_length: float, magnet: bool) -> None:
        """Winch and magnet set-point of ``agent``'s hook."""
        self.hooks[agent].command(cable_length, magnet)

    def inject(self, agent: str, fault: HookFault) -> None:
        """Hook fault of ``agent`` (see :class:`sim.hook.Hook`)."""
        self.hooks[agent].inject(fault)

    def place(self, object_id: str, east: float, north: float, up: float) -> None:
        """Put a free object with its bottom centre at a point, level, released from rest."""
        m, d = self.model, self.data
        joint = m.body_jntadr[self._body[object_id]]
        q, v = int(m.jnt_qposadr[joint]), int(m.jnt_dofadr[joint])
        d.qpos[q : q + 3] = (east, north, up)
        d.qvel[v : v + 6] = 0.0
        d.qvel[v + 2] = -1e-3  # a sleeping body wakes up when it has a velocity
        self._plane_xy[:] = np.inf
        mujoco.mj_forward(m, d)

    def reset_hook(self, agent: str, anchor: Vec3) -> None:
        """Drop what the hook holds, wind it in and hang it still under ``anchor``."""
        self._let_go(agent)
        self.hooks[agent] = Hook(self.params)
        m, d = self.model, self.data
        self._put_anchor(agent, anchor, (0.0, 0.0, 0.0))
        self._last_anchor[agent] = anchor
        body = self._hook_body[agent]
        q = int(m.jnt_qposadr[m.body_jntadr[body]])
        v = int(m.jnt_dofadr[m.body_jntadr[body]])
        d.qpos[q : q + 3] = (anchor[0], anchor[1], anchor[2] - self.params.stowed_cable)
        d.qpos[q + 3 : q + 7] = (1.0, 0.0, 0.0, 0.0)
        d.qvel[v : v + 6] = 0.0
        self._forces[agent] = (0.0, 0.0, 0.0)
        self._plane_xy[:] = np.inf
        mujoco.mj_forward(m, d)

    # ---------------------------------------------------------------- output
    def cable_force(self, agent: str) -> Vec3:
        """Force of ``agent``'s cable on its aircraft after the last step, N ENU."""
        return self._forces[agent]

    def reading(self, agent: str) -> HookReading:
        """``agent``'s carrying sensor sample."""
        return self.hooks[agent].reading()

    def held_by(self, object_id: str) -> str:
        """Agent whose hook holds ``object_id`` ("" when none)."""
        for agent, hook in self.hooks.items():
            if hook.held == object_id:
                return agent
        return ""

    def mass(self, object_id: str) -> float:
        """Mass of an object, kg."""
        return object_mass(self.objects[object_id])

    def hook_position(self, agent: str) -> Vec3:
        """Centre of ``agent``'s hook, ENU m."""
        p = self.data.xpos[self._hook_body[agent]]
        return (float(p[0]), float(p[1]), float(p[2]))

    def pose(self, object_id: str) -> PayloadPose:
        """Pose of one object now."""
        d = self.data
        b = self._body[object_id]
        p = d.xpos[b]
        r = d.xmat[b]
        heading = (math.pi / 2.0 - math.atan2(float(r[3]), float(r[0]))) % (2.0 * math.pi)
        v = d.cvel[b]  # rotation-translation at the body's centre of mass (world orientation)
        speed = float(np.linalg.norm(v[3:6]))
        return PayloadPose(
            float(p[0]), float(p[1]), float(p[2]), heading, self.held_by(object_id), speed
        )

    def poses(self) -> dict[str, PayloadPose]:
        """Poses of every payload object, by id."""
        return {oid: self.pose(oid) for oid in self.objects}


def _mocap(model: Any, body: int) -> int:
    return int(model.body_mocapid[body])


def _geoms_of(model: Any, body: int) -> range:
    start = int(model.body_geomadr[body])
    return range(start, start + int(model.body_geomnum[body]))


def _contents(obj: DynamicObject) -> BoxContents | None:
    return obj.contents


def _tilt_quat(gx: float, gy: float) -> tuple[float, float, float, float]:
    """Quaternion (w, x, y, z) turning +z onto the terrain normal (-gx, -gy, 1)/|.|."""
    k = 1.0 / math.sqrt(gx * gx + gy * gy + 1.0)
    nx, ny, nz = -gx * k, -gy * k, k
    # half-way quaternion between z and n: (1 + n_z, z x n) normalised
    w, x, y = 1.0 + nz, -ny, nx
    q = 1.0 / math.sqrt(w * w + x * x + y * y)
    return (w * q, x * q, y * q, 0.0)
