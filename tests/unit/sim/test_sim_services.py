import math
from collections.abc import Callable, Sequence
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from sim.lockstep import LockstepBarrier
from sim.rc_transmitter import FlightModeSwitch
from sim.sensors.fault import FaultMode
from sim.sensors.power import PowerDevice
from sim.sim_services import RcRequest, SimCode, SimResult, SimServices
from sim.world_loader import load_world
from sim.world_sim import SimConfig, WorldSim
from sim.yacs import YacsCommand

WORLD = load_world("revinge")
BUILDING = WORLD.buildings[0]
INSIDE = (
    sum(p[0] for p in BUILDING.footprint) / len(BUILDING.footprint),
    sum(p[1] for p in BUILDING.footprint) / len(BUILDING.footprint),
)
NAN = math.nan


@pytest.fixture(scope="module")
def services() -> SimServices:
    sim = WorldSim(SimConfig(WORLD, ("uav0", "uav1")))
    barrier: LockstepBarrier[YacsCommand | None] = LockstepBarrier(sim.agents)
    return SimServices(sim, barrier)


@pytest.mark.parametrize(
    ("call", "code", "reason"),
    [
        (lambda s: s.reset("uav9"), SimCode.UNKNOWN_AGENT, "unknown agent 'uav9'"),
        (lambda s: s.reset("", ["uav0", "x"]), SimCode.UNKNOWN_AGENT, "'x'"),
        (lambda s: s.reset("uav0", ["uav0"]), SimCode.INVALID_ARGUMENT, "full reset only"),
        (
            lambda s: s.teleport("uav0", False, NAN, 0.0, 0.0, 0.0),
            SimCode.INVALID_ARGUMENT,
            "finite",
        ),
        (
            lambda s: s.teleport("uav0", False, 0.0, 0.0, -1.0, 0.0),
            SimCode.INVALID_ARGUMENT,
            "height",
        ),
        (
            lambda s: s.teleport("uav0", False, 5000.0, 0.0, 0.0, 0.0),
            SimCode.BLOCKED,
            "outside the world",
        ),
        (
            lambda s: s.teleport("uav0", False, *INSIDE, 0.0, 0.0),
            SimCode.BLOCKED,
            f"building {BUILDING.name}",
        ),
        (
            lambda s: s.teleport("uav0", True, 95.0, 0.0, 0.0, 0.0),
            SimCode.INVALID_ARGUMENT,
            "latitude",
        ),
        (
            lambda s: s.teleport("nobody", False, 0.0, 0.0, 0.0, 0.0),
            SimCode.UNKNOWN_AGENT,
            "nobody",
        ),
        (
            lambda s: s.inject_fault("uav0", "sonar", 1, []),
            SimCode.UNKNOWN_NAME,
            "unknown sensor 'sonar'",
        ),
        (lambda s: s.inject_fault("uav0", "gps", 9, []), SimCode.INVALID_ARGUMENT, "fault mode 9"),
        (lambda s: s.inject_fault("uav0", "gps", 3, [NAN]), SimCode.INVALID_ARGUMENT, "finite"),
        (
            lambda s: s.inject_fault("uav0", "gps", 3, [1.0, 2.0]),
            SimCode.INVALID_ARGUMENT,
            "1 or 6 values",
        ),
        (
            lambda s: s.inject_fault("uav0", "laser", 3, [1.0, 2.0]),
            SimCode.INVALID_ARGUMENT,
            "takes 1 values",
        ),
        (lambda s: s.inject_fault("uav0", "imu", 4, [-2.0]), SimCode.INVALID_ARGUMENT, "noise-up"),
        (
            lambda s: s.spawn_object("p1", "dragon", 0.0, 0.0, 0.0),
            SimCode.UNKNOWN_NAME,
            "unknown object kind",
        ),
        (
            lambda s: s.spawn_object("p1", "person", NAN, 0.0, 0.0),
            SimCode.INVALID_ARGUMENT,
            "finite",
        ),
        (lambda s: s.spawn_object("p1", "box", *INSIDE, 0.0), SimCode.BLOCKED, "inside building"),
        (lambda s: s.spawn_object("p1", "box", 1e5, 0.0, 0.0), SimCode.BLOCKED, "outside"),
        (
            lambda s: s.spawn_object(WORLD.objects[0].id, "box", 0.0, 0.0, 0.0),
            SimCode.DUPLICATE,
            "already exists",
        ),
        (lambda s: s.spawn_object(" ", "box", 0.0, 0.0, 0.0), SimCode.INVALID_ARGUMENT, "empty"),
        (lambda s: s.set_wind((NAN, 0.0, 0.0), 0.0), SimCode.INVALID_ARGUMENT, "finite"),
        (lambda s: s.set_wind((0.0, 0.0, 0.0), 99.0), SimCode.INVALID_ARGUMENT, "gust intensity"),
        (lambda s: s.set_power("uav0", 1 << 20, True), SimCode.UNKNOWN_NAME, "device bits"),
        (lambda s: s.set_power("uav0", 0, True), SimCode.UNKNOWN_NAME, "device bits"),
        (lambda s: s.set_rc("uav0", RcRequest(mode=3)), SimCode.INVALID_ARGUMENT, "rc mode"),
        (
            lambda s: s.set_rc("uav0", RcRequest(sticks=(2.0, 0, 0, 0))),
            SimCode.INVALID_ARGUMENT,
            "sticks",
        ),
        (
            lambda s: s.set_rc("uav0", RcRequest(sticks=(0, 0, 0, NAN))),
            SimCode.INVALID_ARGUMENT,
            "sticks",
        ),
        (
            lambda s: s.set_rc("uav0", RcRequest(sticks=(0, 0, 0, -0.5))),
            SimCode.INVALID_ARGUMENT,
            "throttle",
        ),
    ],
)
def test_bad_requests_answer_a_code_and_a_reason(
    services, call, code: SimCode, reason: str
) -> None:
    result = call(services)
    assert result.code is code
    assert reason in result.reason


def test_valid_requests_change_the_simulation(services: SimServices) -> None:
    sim = services.sim
    assert services.set_rc("uav1", RcRequest(mode=2, engine=1)).ok
    rc = sim.agents["uav1"].aircraft.rc.state
    assert rc.mode is FlightModeSwitch.AUTONOMOUS and rc.engine_on
    assert services.set_rc("uav1", RcRequest(link=2, sticks=(0.5, 0.0, 0.0, 0.3))).ok
    assert not sim.agents["uav1"].aircraft.rc.state.link_ok
    assert services.inject_fault("uav0", "gps", 3, [1.0, 2.0, 3.0, 0.0, 0.0, 0.0]).ok
    assert sim.agents["uav0"].sensors.gps.fault.mode is FaultMode.BIAS
    assert services.spawn_object("extra_box", "box", 0.0, 0.0, 0.5).ok
    assert sim.objects["extra_box"].contents is not None
    assert services.spawn_object("extra_fox", "animal", 2.0, 0.0, 0.5).ok
    assert services.spawn_object("extra_dummy", "dummy", 4.0, 0.0, 0.5).ok
    assert (sim.objects["extra_fox"].temperature or 0.0) > 300.0
    assert services.set_wind((3.0, 0.0, 0.0), 1.0).ok
    assert sim.wind.mean == (3.0, 0.0, 0.0)
    assert services.set_power("uav0", int(PowerDevice.LASER), True).ok
    assert sim.agents["uav0"].sensors.power.is_on(PowerDevice.LASER)
    pad = WORLD.pad("H2")
    assert services.teleport("uav0", False, pad.east + 20.0, pad.north, 2.0, 0.0).ok
    lat_lon = sim.agents["uav0"].sensors.gps  # any object with the origin will do
    origin = lat_lon.origin
    assert services.teleport("uav0", True, origin.latitude, origin.longitude, 0.0, 0.0).ok
    assert sim.truth("uav0").position_enu[:2] == pytest.approx((0.0, 0.0), abs=0.01)
    assert services.pause(True).ok and services.paused
    # a full reset undoes all of it and fixes the lockstep set
    assert services.reset("", ["uav0"]).ok
    assert "extra_box" not in sim.objects
    assert sim.wind.mean == (0.0, 0.0, 0.0)
    assert sim.agents["uav0"].sensors.gps.fault.mode is FaultMode.NONE
    assert not sim.agents["uav1"].aircraft.rc.state.engine_on
    assert services.barrier.required == {"uav0"}
    assert services.reset("uav1").ok


@pytest.mark.parametrize(
    ("call", "code", "reason"),
    [
        (lambda s: s.ptu_command("uav0", NAN, 0.0), SimCode.INVALID_ARGUMENT, "finite"),
        (lambda s: s.ptu_command("uavX", 0.0, 0.0), SimCode.UNKNOWN_AGENT, "uavX"),
        (lambda s: s.camera_command("uav0", 7, 0.5), SimCode.UNKNOWN_NAME, "camera id 7"),
        (lambda s: s.camera_command("uav0", 0, NAN), SimCode.INVALID_ARGUMENT, "finite"),
        (
            lambda s: s.laser_command("uav0", 0.3, 0.01, 0.0, False, 0.0),
            SimCode.INVALID_ARGUMENT,
            "0.25, 0.5 or 1.0",
        ),
        (
            lambda s: s.laser_command("uav0", 1.0, 0.1, 0.0, False, 0.0),
            SimCode.INVALID_ARGUMENT,
            "distance resolution",
        ),
        (
            lambda s: s.laser_command("uav0", 1.0, 0.01, NAN, False, 0.0),
            SimCode.INVALID_ARGUMENT,
            "finite",
        ),
    ],
)
def test_bad_payload_commands(services, call, code: SimCode, reason: str) -> None:
    result = call(services)
    assert result.code is code
    assert reason in result.reason


def test_payload_commands_drive_ptu_zoom_and_laser(services: SimServices) -> None:
    sensors = services.sim.agents["uav1"].sensors
    assert services.ptu_command("uav1", 0.5, 4.0).ok  # tilt clamped to the limit
    assert sensors.ptu.pan_target == 0.5 and sensors.ptu.tilt_target < 4.0
    assert services.camera_command("uav1", 1, 0.7).ok
    assert sensors.thermal_camera.zoom_target == 0.7
    assert services.laser_command("uav1", 0.25, 0.001, 1.0, False, 0.0).ok
    laser = sensors.laser
    assert (laser.config.fov_deg, laser.config.resolution_deg) == (100.0, 0.25)
    assert laser.rotation_speed == 1.0 and laser.rate_hz == pytest.approx(1 / 0.053)
    assert services.laser_command("uav1", 1.0, 0.01, 1.0, True, -1.0).ok
    assert laser.rotation_speed == 0.0 and laser.rotation_angle == pytest.approx(2 * math.pi - 1.0)
    assert not sensors.power.is_on(PowerDevice.LASER)  # off at start, a command leaves it off
    for collect in (True, False):  # the PPC's data collection flag switches the unit
        assert services.laser_command("uav1", 1.0, 0.01, 1.0, False, 0.0, power=collect).ok
        assert sensors.power.is_on(PowerDevice.LASER) is collect
    sensors.power.switch(PowerDevice.PTU, False)
    assert services.ptu_command("uav1", 0.0, 0.0).code is SimCode.WRONG_STATE


# ---------------------------------------------------------------- property test: extreme values
ABSURD = 1e17
"""Any number at least this large is outside every field's range (angles, m, m/s, factors)."""
_PAD = WORLD.pad("H2")
Call = Callable[[SimServices, Sequence[Any]], SimResult]
SERVICES: dict[str, tuple[Call, tuple[Any, ...]]] = {
    "reset": (lambda s, a: s.reset(a[0], a[1]), ("", ["uav0", "uav1"])),
    "pause": (lambda s, a: s.pause(a[0]), (False,)),
    "teleport": (
        lambda s, a: s.teleport(*a),
        ("uav1", False, _PAD.east + 20.0, _PAD.north, 2.0, 0.5),
    ),
    "inject_fault": (lambda s, a: s.inject_fault(*a), ("uav0", "gps", 3, [1.0])),
    "clear_fault": (lambda s, a: s.inject_fault(*a), ("uav0", "imu", 0, [])),
    "spawn_object": (lambda s, a: s.spawn_object(*a), ("p1", "person", 10.0, 5.0, 0.3)),
    "set_wind": (lambda s, a: s.set_wind((a[0], a[1], a[2]), a[3]), (1.0, 0.0, 0.0, 0.5)),
    "set_power": (lambda s, a: s.set_power(*a), ("uav0", 128, True)),
    "set_rc": (
        lambda s, a: s.set_rc(a[0], RcRequest(a[1], a[2], a[3], (a[4], a[5], a[6], a[7]))),
        ("uav1", 2, 1, 1, 0.1, 0.1, 0.1, 0.5),
    ),
    "ptu_command": (lambda s, a: s.ptu_command(*a), ("uav0", 0.2, -0.3)),
    "camera_command": (lambda s, a: s.camera_command(*a), ("uav0", 1, 0.5)),
    "laser_command": (lambda s, a: s.laser_command(*a), ("uav0", 1.0, 0.01, 1.0, True, 0.5)),
}
"""Every request of SimServices as (call with flat arguments, valid arguments)."""

_numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([1e308, -1e308, 1e17, -1e17, 2 * math.pi + 1e-6, -0.0, 4.0]),
)


class FloatList(list[float]):
    """Strategy key of a list of numbers (fault magnitudes)."""


class StrList(list[str]):
    """Strategy key of a list of names (lockstep agents)."""


_extreme: dict[type, st.SearchStrategy[Any]] = {
    float: _numbers,
    bool: st.booleans(),
    int: st.one_of(st.integers(-(2**64), 2**64), st.sampled_from([0, 3, 255, 2**32 - 1])),
    str: st.one_of(st.text(max_size=8), st.just("u" * 100_000), st.just("\x00\n")),
    FloatList: st.one_of(st.lists(_numbers, max_size=20), st.just([1.0] * 100_000)),
    StrList: st.lists(st.sampled_from(["uav0", "uav1", "", "u" * 100_000]), max_size=40),
}


def _kind(value: object) -> type:
    """The strategy key of a field: its type, a list by the type of its items."""
    if isinstance(value, list):
        return StrList if value and isinstance(value[0], str) else FloatList
    return type(value)


@st.composite
def _requests(draw: st.DrawFn) -> tuple[str, tuple[Any, ...], frozenset[int]]:
    """A valid request of one service with one to three fields replaced by extreme values."""
    name = draw(st.sampled_from(sorted(SERVICES)))
    args = list(SERVICES[name][1])
    changed = frozenset(draw(st.lists(st.integers(0, len(args) - 1), min_size=1, max_size=3)))
    for i in changed:
        args[i] = draw(_extreme[_kind(args[i])])
    return name, tuple(args), changed


@pytest.fixture(scope="module")
def fuzzed() -> SimServices:
    sim = WorldSim(SimConfig(WORLD, ("uav0", "uav1")))
    return SimServices(sim, LockstepBarrier(sim.agents))


@pytest.mark.parametrize("name", sorted(SERVICES))
def test_the_fuzzed_requests_start_from_valid_ones(fuzzed: SimServices, name: str) -> None:
    call, args = SERVICES[name]
    assert call(fuzzed, args).ok


_EXTREMES = (math.nan, math.inf, -math.inf, 1e308, -1e308, 1e17, -1e17)
_FLOAT_FIELDS = [
    (name, i, value)
    for name, (_, args) in sorted(SERVICES.items())
    for i, arg in enumerate(args)
    if isinstance(arg, float)
    for value in _EXTREMES
]


@pytest.mark.parametrize(("name", "index", "value"), _FLOAT_FIELDS)
def test_every_number_field_refuses_extreme_values(
    fuzzed: SimServices, name: str, index: int, value: float
) -> None:
    call, args = SERVICES[name]
    result = call(fuzzed, (*args[:index], value, *args[index + 1 :]))
    assert result.code is not SimCode.OK and 0 < len(result.reason) <= 300


@given(st.lists(_requests(), min_size=1, max_size=4))
def test_extreme_values_get_a_defined_answer(
    fuzzed: SimServices, requests: list[tuple[str, tuple[Any, ...], frozenset[int]]]
) -> None:
    """NaN, +-inf, +-1e308 and 100,000-character strings: a code, a short reason, a live core."""
    for name, args, changed in requests:
        result = SERVICES[name][0](fuzzed, args)
        assert result.code in SimCode
        assert result.ok or 0 < len(result.reason) <= 300
        absurd = [
            args[i]
            for i in changed
            if isinstance(args[i], float) and not (math.isfinite(args[i]) and abs(args[i]) < ABSURD)
        ]
        if absurd:
            assert not result.ok, (name, args)
    fuzzed.sim.advance()
    assert all(math.isfinite(v) for v in fuzzed.sim.truth("uav0").position_enu)


@pytest.mark.parametrize(
    ("call", "code", "reason"),
    [
        (lambda s: s.inject_fault("uav0", "hook", 3, []), SimCode.INVALID_ARGUMENT,
         "not a hook fault"),
        (lambda s: s.inject_fault("uav0", "gps", 6, []), SimCode.INVALID_ARGUMENT,
         "a fault of the 'hook'"),
        (lambda s: s.inject_fault("uav0", "hook", 5, []), SimCode.WRONG_STATE, "holds nothing"),
        (lambda s: s.hook_command("uav0", NAN, True), SimCode.INVALID_ARGUMENT, "cable length"),
        (lambda s: s.hook_command("uav0", 25.0, True), SimCode.INVALID_ARGUMENT, "[0, 20] m"),
        (lambda s: s.hook_command("uav9", 1.0, True), SimCode.UNKNOWN_AGENT, "uav9"),
    ],
)  # fmt: skip
def test_bad_hook_requests(
    services: SimServices, call: Callable[[SimServices], SimResult], code: SimCode, reason: str
) -> None:
    result = call(services)
    assert result.code is code and reason in result.reason


def test_hook_faults_and_commands_reach_the_hook() -> None:
    sim = WorldSim(SimConfig(WORLD, ("uav0",)))
    s = SimServices(sim, LockstepBarrier(sim.agents))
    assert s.inject_fault("uav0", "hook", 6, []).ok  # hook failure
    assert sim.payload.hooks["uav0"].failed
    assert s.inject_fault("uav0", "hook", 0, []).ok
    assert not sim.payload.hooks["uav0"].failed
    assert s.inject_fault("uav0", "hook", 7, []).ok  # wrong box at the next grip
    assert sim.payload.hooks["uav0"].wrong_box
    assert s.hook_command("uav0", 2.0, True).ok
    assert (sim.payload.hooks["uav0"].target, sim.carrying("uav0").magnet) == (2.0, True)
