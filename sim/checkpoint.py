"""World checkpoints: the whole state of a running world in one file, so a restart resumes it.

What a checkpoint holds (:class:`WorldState`): the tick, every agent (flight model including
JSBSim's rigid body, rotor and drive-train states, the YACS and its YAS front end, the RC
transmitter, the sensor suite with its noise streams, schedules, faults, power switches and
payload mechanisms, the latest command), the wind (gusts and their stream), the dynamic objects
(a driving car's pose is a function of the tick and its drive's departure, which a resume delays
by the skipped ticks), and what the node adds (:class:`RunState`: run id, pause, lockstep set).

Why pickle and not a hand-written format: the state is spread over some twenty plain Python
classes (numpy generators, Gauss-Markov processes, schedules, filters); a codec per class would
repeat what pickle does and silently miss every state variable added later. Two things are not
pickled but re-attached when loading: the world (loaded again from its file and identified by a
digest of its content, :class:`WorldIdentity`) and JSBSim's C++ instance
(``FlightModel.__getstate__`` saves it as a ``RigidBodyState`` that ``__setstate__`` writes back
through ``ic/`` properties and ``run_ic()``).

File: ``MAGIC``, format version (4 bytes), SHA-256 of the payload, payload (pickle protocol 5).
It is written to a temporary file beside the target and renamed over it (atomic on POSIX): a
reader finds the previous or the new checkpoint, never part of one. No fsync: a checkpoint
survives the death of the process (the kernel's page cache holds it), not a machine crash. A
file is only ever read by a world_sim of the same launch; the restricted unpickler builds
classes of ``sim``, numpy and plain containers only, so a foreign file is refused, not run.
"""

from __future__ import annotations

import enum
import hashlib
import io
import os
import pickle
import struct
import tempfile
import uuid
from dataclasses import dataclass
from pathlib import Path
from types import MethodType
from typing import Any

from hdrc3_base.errors import ConfigError
from sim.payload import PayloadWorld
from sim.wind import Wind
from sim.world import DynamicObject
from sim.world_sim import TICK_NS, SimAgent, SimConfig, WorldSim

MAGIC = b"hdrc3 world checkpoint\n"
FORMAT = 3
"""Version of the file layout and of the pickled classes; another version is not resumed.
3: dynamic objects carry a car's ``drive`` and ``paint``."""
_HEADER = struct.Struct(f">{len(MAGIC)}sI32s")
_ALLOWED_MODULES = ("sim.", "numpy")
_ALLOWED_BUILTINS = frozenset({"complex", "frozenset", "set", "slice", "bytearray", "range"})


class LoadStatus(enum.Enum):
    """What reading a checkpoint found."""

    OK = "ok"
    MISSING = "missing"
    """No checkpoint at the path: no world_sim of this launch got as far as writing one."""
    CORRUPT = "corrupt"
    """Unreadable, truncated, not a checkpoint or a checksum mismatch."""
    INCOMPATIBLE = "incompatible"
    """A valid checkpoint of another world, agent list, seed or file format."""


@dataclass(frozen=True, slots=True)
class WorldIdentity:
    """What must be equal for a checkpoint to continue a world."""

    world: str
    """World name."""
    digest: str
    """SHA-256 of the world's content (terrain, buildings, pads, objects ...)."""
    agents: tuple[str, ...]
    seed: int
    payload: float
    """Payload per aircraft at start, kg."""

    @classmethod
    def of(cls, config: SimConfig) -> WorldIdentity:
        """Identity of a run configured by ``config``."""
        digest = hashlib.sha256(pickle.dumps(config.world, protocol=5)).hexdigest()
        return cls(config.world.name, digest, config.agents, config.seed, config.payload)

    def difference(self, other: WorldIdentity) -> str | None:
        """Readable difference between a checkpoint's identity (``other``) and this, or None."""
        if self.world != other.world or self.digest != other.digest:
            return (
                f"it is of world {other.world!r} ({other.digest[:12]}), "
                f"this is {self.world!r} ({self.digest[:12]})"
            )
        for name in ("agents", "seed", "payload"):
            mine, theirs = getattr(self, name), getattr(other, name)
            if mine != theirs:
                return f"its {name} are {theirs}, this run's are {mine}"
        return None


@dataclass(frozen=True, slots=True)
class RunState:
    """What the node adds to the world state."""

    run_id: str
    """Identifies one world from its start (or full reset) on; kept across resumes."""
    paused: bool = False
    lockstep: tuple[str, ...] = ()
    """Explicitly lockstepped agents (empty: automatic mode)."""


@dataclass(frozen=True, slots=True)
class WorldState:
    """The content of one checkpoint (after its :class:`WorldIdentity`)."""

    tick: int
    period_ticks: int
    """Ticks between two checkpoints: no tick later than ``tick + period_ticks - 1`` can have
    been published by the process that wrote this one (it writes before it publishes)."""
    agents: dict[str, SimAgent]
    wind: Wind
    objects: dict[str, DynamicObject]
    run: RunState
    payload: PayloadWorld
    """Boxes, carriers and hooks (rigid bodies)."""


@dataclass(frozen=True, slots=True)
class LoadResult:
    """Outcome of :func:`read_checkpoint`: the state if OK, otherwise why not."""

    status: LoadStatus
    state: WorldState | None = None
    reason: str = ""


def _external(key: str) -> object:
    """Stands in the pickle for the external ``key``; :class:`_Unpickler` supplies its own."""
    raise pickle.UnpicklingError(f"external reference {key!r} outside a checkpoint")


class _Pickler(pickle.Pickler):
    """Refers to the world (and its terrain and geometry) instead of copying them.

    By ``reducer_override`` (a call to :func:`_external`), not ``persistent_id``: pickle asks
    ``persistent_id`` about every object, numbers and strings included (~3000 Python calls, a
    third of a checkpoint's 7 ms), ``reducer_override`` only about objects of other types.
    """

    def __init__(self, file: io.BytesIO, sim: WorldSim) -> None:
        super().__init__(file, protocol=5)
        external = _externals(sim)
        self._terrain_height = external.pop("terrain_height")
        self._ids = {id(value): key for key, value in external.items()}

    def reducer_override(self, obj: Any) -> Any:
        if type(obj) is MethodType:  # a bound method is a new object at every access
            if obj == self._terrain_height:
                return _external, ("terrain_height",)
            return NotImplemented
        key = self._ids.get(id(obj))
        return NotImplemented if key is None else (_external, (key,))


class _Unpickler(pickle.Unpickler):
    """Re-attaches the externals of this process; builds only simulator and numpy classes."""

    def __init__(self, file: io.BytesIO, sim: WorldSim) -> None:
        super().__init__(file)
        self._external = _externals(sim)

    def persistent_load(self, pid: Any) -> Any:
        if pid not in self._external:
            raise pickle.UnpicklingError(f"unknown external reference {pid!r}")
        return self._external[pid]

    def find_class(self, module: str, name: str) -> Any:
        if module == __name__ and name == _external.__name__:
            return self.persistent_load  # this process's world, terrain and geometry
        allowed = module.startswith(_ALLOWED_MODULES) or (
            module == "builtins" and name in _ALLOWED_BUILTINS
        )
        if not allowed:
            raise pickle.UnpicklingError(f"a checkpoint does not contain {module}.{name}")
        return super().find_class(module, name)


def _externals(sim: WorldSim) -> dict[str, object]:
    return {
        "world": sim.world,
        "terrain": sim.world.terrain,
        "terrain_height": sim.world.terrain.height,
        "geometry": sim.geometry,
    }


def encode(sim: WorldSim, run: RunState, period_ticks: int) -> bytes:
    """The checkpoint file's bytes for the current state of ``sim``."""
    state = WorldState(sim.tick, period_ticks, sim.agents, sim.wind, sim.objects, run, sim.payload)
    buffer = io.BytesIO()
    pickler = _Pickler(buffer, sim)
    pickler.dump(WorldIdentity.of(sim.config))  # first: checked before the state is rebuilt
    pickler.dump(state)
    payload = buffer.getvalue()
    return _HEADER.pack(MAGIC, FORMAT, hashlib.sha256(payload).digest()) + payload


def write_checkpoint(path: Path, data: bytes) -> None:
    """Replace the checkpoint at ``path`` by ``data`` atomically (OSError if impossible)."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as out:
            out.write(data)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def decode(data: bytes, sim: WorldSim) -> LoadResult:
    """The state in checkpoint bytes, checked against the world ``sim`` runs."""
    if len(data) < _HEADER.size:
        return LoadResult(LoadStatus.CORRUPT, reason=f"{len(data)} bytes: too short")
    magic, version, digest = _HEADER.unpack_from(data)
    if magic != MAGIC:
        return LoadResult(LoadStatus.CORRUPT, reason="not a world checkpoint")
    if version != FORMAT:
        return LoadResult(
            LoadStatus.INCOMPATIBLE, reason=f"format {version}, this world_sim reads {FORMAT}"
        )
    payload = data[_HEADER.size :]
    if hashlib.sha256(payload).digest() != digest:
        return LoadResult(LoadStatus.CORRUPT, reason="checksum mismatch (truncated or damaged)")
    unpickler = _Unpickler(io.BytesIO(payload), sim)
    try:
        identity = unpickler.load()
        if not isinstance(identity, WorldIdentity):
            return LoadResult(LoadStatus.CORRUPT, reason="no world identity")
        different = WorldIdentity.of(sim.config).difference(identity)
        if different is not None:
            return LoadResult(LoadStatus.INCOMPATIBLE, reason=different)
        state = unpickler.load()
    except Exception as exc:  # any failure to rebuild the state means "cannot resume"
        return LoadResult(LoadStatus.CORRUPT, reason=f"cannot rebuild the state: {exc}")
    if not isinstance(state, WorldState):
        return LoadResult(LoadStatus.CORRUPT, reason="no world state")
    return LoadResult(LoadStatus.OK, state)


def read_checkpoint(path: Path, sim: WorldSim) -> LoadResult:
    """Load the checkpoint at ``path`` for the world ``sim`` runs; never raises on bad files."""
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        return LoadResult(LoadStatus.MISSING, reason=f"no checkpoint at {path}")
    except OSError as exc:
        return LoadResult(LoadStatus.CORRUPT, reason=f"cannot read {path}: {exc.strerror}")
    return decode(data, sim)


class RunKind(enum.IntEnum):
    """How a world began or went on (values of SimRun.msg)."""

    STARTED = 0
    RESUMED = 1
    RESET = 2


@dataclass(frozen=True, slots=True)
class RunEvent:
    """One announcement on /world_sim/run."""

    kind: RunKind
    run: RunState
    stamp_ns: int
    """Sim time the world starts or goes on from."""
    checkpoint_ns: int = 0
    """RESUMED: sim time of the resumed state."""
    reason: str = ""


def new_run_id() -> str:
    """A fresh random run id."""
    return uuid.uuid4().hex[:16]


class Checkpoints:
    """One world_sim's checkpoint file: resumed at start, rewritten every ``period_ticks``.

    A checkpoint is written before the tick it holds is published, and again at least every
    ``period_ticks``: no published tick is ever ``period_ticks`` or more beyond the file's, so
    resuming ``period_ticks`` after it keeps the clock monotonic.
    """

    def __init__(self, path: Path | None, period_ticks: int) -> None:
        """Checkpoints at ``path`` (None: none) every ``period_ticks`` >= 1 ticks."""
        if period_ticks < 1:
            raise ConfigError(f"checkpoint period must be at least one tick, got {period_ticks}")
        self.path = path
        self.period_ticks = period_ticks
        self._written: int | None = None

    def start(self, sim: WorldSim) -> RunEvent:
        """Resume the checkpoint into ``sim`` if there is a usable one; say what happened."""
        if self.path is None:
            return RunEvent(RunKind.STARTED, RunState(new_run_id()), sim.time_ns, reason="")
        found = read_checkpoint(self.path, sim)
        if found.status is LoadStatus.MISSING:
            return RunEvent(RunKind.STARTED, RunState(new_run_id()), sim.time_ns, reason="")
        state = found.state
        if state is None:
            reason = (
                f"world_sim restarted and could not resume checkpoint {self.path}: "
                f"{found.reason}; the world starts over"
            )
            return RunEvent(RunKind.RESET, RunState(new_run_id()), sim.time_ns, reason=reason)
        sim.resume(
            state.tick,
            state.agents,
            state.wind,
            state.objects,
            state.period_ticks,
            payload=state.payload,
        )
        saved = state.tick * TICK_NS
        reason = (
            f"world_sim restarted and resumed the world of t = {saved / 1e9:.2f} s "
            f"at t = {sim.time_ns / 1e9:.2f} s"
        )
        return RunEvent(RunKind.RESUMED, state.run, sim.time_ns, saved, reason)

    def due(self, tick: int) -> bool:
        """True when the state of ``tick`` must be written before it is published."""
        if self.path is None:
            return False
        last = self._written
        return last is None or tick < last or tick >= last + self.period_ticks

    def write(self, sim: WorldSim, run: RunState) -> str | None:
        """Write the current state; the reason if that failed (the run goes on regardless)."""
        if self.path is None:
            return None
        self._written = sim.tick  # a failed write is retried one period later, not every tick
        try:
            write_checkpoint(self.path, encode(sim, run, self.period_ticks))
        except OSError as exc:
            return f"cannot write checkpoint {self.path}: {exc.strerror or exc}"
        return None
