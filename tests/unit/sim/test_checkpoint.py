import hashlib
import math
import os
import pickle
import struct
from dataclasses import replace
from pathlib import Path

import pytest

from sim import checkpoint as ck
from sim.checkpoint import Checkpoints, LoadStatus, RunKind, RunState
from sim.rc_transmitter import FlightModeSwitch
from sim.sensors.fault import FaultMode
from sim.sensors.power import PowerDevice
from sim.wind import WindSettings
from sim.world import DynamicObject, ObjectKind
from sim.world_loader import load_world
from sim.world_sim import TICK_NS, SimConfig, WorldSim
from sim.yacs import YacsCommand

WORLD = load_world("revinge")
CONFIG = SimConfig(WORLD, ("uav0", "uav1"), seed=3)
RUN = RunState("run-a", paused=True, lockstep=("uav0",))


def _command(k: int) -> YacsCommand:
    return YacsCommand(pitch=-0.1 if k > 750 else 0.0, vertical=1.5, yaw_rate=0.05)


def _advance(sim: WorldSim, ticks: int, first: int) -> list[tuple[float, ...]]:
    """Fly uav0 with a fixed command sequence; the GPS fixes of uav0 published on the way."""
    fixes: list[tuple[float, ...]] = []
    for k in range(first, first + ticks):
        sim.command("uav0", _command(k))
        sim.advance()
        for readings in sim.take_readings()["uav0"]:
            if readings.gps is not None:
                fixes.append((readings.gps.time, *readings.gps.position_enu))
    return fixes


@pytest.fixture(scope="module")
def flying() -> tuple[WorldSim, bytes]:
    """uav0 airborne at t = 16 s (rotor spun up in 10 s) with a fault, object and wind."""
    sim = WorldSim(CONFIG)
    rc = sim.agents["uav0"].aircraft.rc
    rc.set_engine(True)
    rc.set_mode(FlightModeSwitch.AUTONOMOUS)
    sim.set_wind(WindSettings((2.0, 1.0, 0.0), 1.0))
    sim.agents["uav1"].sensors.barometer.fault.set(FaultMode.BIAS, 3.0)
    sim.agents["uav1"].sensors.power.switch(PowerDevice.PTU, False)
    sim.spawn(DynamicObject("crate", ObjectKind.BOX, 10.0, 5.0, 0.0, (1.0, 1.0, 1.0)))
    _advance(sim, 800, 0)
    return sim, ck.encode(sim, RUN, 10)


def _restored(data: bytes, skip: int = 0) -> tuple[WorldSim, ck.WorldState]:
    sim = WorldSim(CONFIG)
    found = ck.decode(data, sim)
    assert found.status is LoadStatus.OK, found.reason
    assert found.state is not None
    state = found.state
    sim.resume(state.tick, state.agents, state.wind, state.objects, skip, payload=state.payload)
    return sim, state


def test_a_resumed_world_continues_where_the_checkpoint_was(
    flying: tuple[WorldSim, bytes],
) -> None:
    original, data = flying
    copy, state = _restored(data)
    assert (state.tick, state.period_ticks, state.run) == (800, 10, RUN)
    before, after = original.truth("uav0"), copy.truth("uav0")
    assert not before.on_ground and before.position_enu[2] > 5.0
    assert math.dist(before.position_enu, after.position_enu) < 1e-6
    assert math.dist(before.velocity_enu, after.velocity_enu) < 1e-9
    assert copy.objects["crate"] == original.objects["crate"]
    assert copy.wind.gust == original.wind.gust
    uav1 = copy.agents["uav1"].sensors
    assert uav1.barometer.fault.mode is FaultMode.BIAS and not uav1.power.is_on(PowerDevice.PTU)
    # same commands: the same flight, the same noisy GPS fixes (noise streams restored)
    fixes = _advance(original, 100, 800), _advance(copy, 100, 800)
    assert len(fixes[0]) == len(fixes[1]) == 20
    for a, b in zip(*fixes, strict=True):
        assert a[0] == b[0] and math.dist(a[1:], b[1:]) < 1e-3
    assert math.dist(original.truth("uav0").position_enu, copy.truth("uav0").position_enu) < 1e-3


def test_a_skip_moves_every_clock_and_nothing_else(flying: tuple[WorldSim, bytes]) -> None:
    _, data = flying
    plain, _ = _restored(data)
    skipped, _ = _restored(data, skip=25)
    assert skipped.time_ns == plain.time_ns + 25 * TICK_NS
    assert skipped.truth("uav0").time == pytest.approx(plain.truth("uav0").time + 0.5)
    fixes = _advance(plain, 50, 800), _advance(skipped, 50, 800)
    for a, b in zip(*fixes, strict=True):
        assert b[0] == pytest.approx(a[0] + 0.5) and math.dist(a[1:], b[1:]) < 1e-9


def _with_payload(payload: bytes, version: int = ck.FORMAT) -> bytes:
    digest = hashlib.sha256(payload).digest()
    return struct.pack(f">{len(ck.MAGIC)}sI32s", ck.MAGIC, version, digest) + payload


class _Exploit:
    def __reduce__(self) -> tuple[object, tuple[str]]:
        return (os.system, ("echo never",))


@pytest.mark.parametrize(
    ("damage", "status", "words"),
    [
        (lambda d: d[:10], LoadStatus.CORRUPT, "too short"),
        (lambda d: d[:-100], LoadStatus.CORRUPT, "checksum"),
        (lambda d: d[:-1] + bytes([d[-1] ^ 1]), LoadStatus.CORRUPT, "checksum"),
        (lambda d: b"PK" + d[2:], LoadStatus.CORRUPT, "not a world checkpoint"),
        (
            lambda d: _with_payload(d[len(ck.MAGIC) + 36 :], 99),
            LoadStatus.INCOMPATIBLE,
            "format 99",
        ),
        (lambda d: _with_payload(pickle.dumps(_Exploit())), LoadStatus.CORRUPT, "does not contain"),
        (lambda d: _with_payload(b"not a pickle"), LoadStatus.CORRUPT, "cannot rebuild"),
        (lambda d: _with_payload(pickle.dumps(3)), LoadStatus.CORRUPT, "no world identity"),
    ],
)
def test_damaged_files_are_refused_with_a_reason(
    flying: tuple[WorldSim, bytes], damage, status: LoadStatus, words: str
) -> None:
    found = ck.decode(damage(flying[1]), WorldSim(CONFIG))
    assert (found.status, found.state) == (status, None)
    assert words in found.reason


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ({"agents": ("uav0",)}, "agents"),
        ({"seed": 4}, "seed"),
        ({"world": replace(WORLD, name="elsewhere")}, "world 'revinge'"),
        ({"world": replace(WORLD, objects=())}, "this is 'revinge'"),
    ],
)
def test_a_checkpoint_of_another_world_is_incompatible(
    flying: tuple[WorldSim, bytes], change: dict[str, object], words: str
) -> None:
    other = WorldSim(replace(CONFIG, **change))  # type: ignore[arg-type]
    found = ck.decode(flying[1], other)
    assert found.status is LoadStatus.INCOMPATIBLE and words in found.reason


def test_checkpoints_resume_with_a_monotonic_clock(
    tmp_path: Path, flying: tuple[WorldSim, bytes]
) -> None:
    path = tmp_path / "world.checkpoint"
    first = Checkpoints(path, 10)
    sim = WorldSim(CONFIG)
    assert first.start(sim).kind is RunKind.STARTED  # no file yet
    assert first.due(0)
    assert first.write(sim, RunState("run-b")) is None
    assert [first.due(t) for t in (5, 9, 10)] == [False, False, True]
    path.write_bytes(flying[1])
    restarted = WorldSim(CONFIG)
    event = Checkpoints(path, 10).start(restarted)
    assert event.kind is RunKind.RESUMED and event.run == RUN
    # the dead process published at most tick 809: the world goes on from tick 810
    assert (event.checkpoint_ns, event.stamp_ns) == (800 * TICK_NS, 810 * TICK_NS)
    assert restarted.time_ns == 810 * TICK_NS and "t = 16.00 s at t = 16.20 s" in event.reason
    assert [p.name for p in tmp_path.iterdir()] == ["world.checkpoint"]  # no temporary left


def test_an_unusable_checkpoint_starts_the_world_over(tmp_path: Path) -> None:
    path = tmp_path / "world.checkpoint"
    path.write_bytes(b"garbage")
    sim = WorldSim(CONFIG)
    event = Checkpoints(path, 10).start(sim)
    assert event.kind is RunKind.RESET and sim.time_ns == event.stamp_ns == 0
    assert "could not resume" in event.reason and "too short" in event.reason
    assert event.run.run_id and event.run.run_id != RUN.run_id


def test_a_failed_write_is_a_reason_not_an_exception(tmp_path: Path) -> None:
    checkpoints = Checkpoints(tmp_path / "gone" / "world.checkpoint", 10)
    problem = checkpoints.write(WorldSim(CONFIG), RUN)
    assert problem is not None and "cannot write checkpoint" in problem
    assert not checkpoints.due(5)  # retried a period later, not every tick


def test_a_driving_car_resumes_where_it_was_and_stands_still_in_the_skipped_time() -> None:
    config = SimConfig(load_world("revinge_chase"), ("uav0",))
    sim = WorldSim(config)
    for _ in range(100):
        sim.advance()
    before = sim.object_poses()["chase1"]
    assert before.speed == pytest.approx(4.0)
    copy = WorldSim(config)
    found = ck.decode(ck.encode(sim, RUN, 10), copy)
    assert found.state is not None, found.reason
    state = found.state
    copy.resume(state.tick, state.agents, state.wind, state.objects, 25, payload=state.payload)
    assert copy.time == pytest.approx(sim.time + 0.5)
    after = copy.object_poses()["chase1"]
    assert (after.east, after.north, after.speed) == pytest.approx((before.east, before.north, 4.0))
    sim.advance()
    copy.advance()
    moved, resumed = sim.object_poses()["chase1"], copy.object_poses()["chase1"]
    assert (resumed.east, resumed.north, resumed.speed) == pytest.approx(
        (moved.east, moved.north, moved.speed)
    )
    assert moved.east > before.east
