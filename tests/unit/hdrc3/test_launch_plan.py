import math
import socket
from dataclasses import replace
from pathlib import Path

import pytest

from hdrc3 import launch_plan
from hdrc3.launch_plan import (
    LaunchOptions,
    NodeKind,
    Scope,
    build_plan,
    check_domain_id,
    check_live_port,
    check_record_path,
    check_topic_pattern,
    check_world,
    parse_nodes,
    parse_speed,
)
from hdrc3_base.errors import ConfigError

CATALOG = (
    NodeKind("system_monitor", "hdrc3-system-monitor", Scope.GLOBAL, ""),
    NodeKind("world_sim", "hdrc3-world-sim", Scope.GLOBAL, "", world_params=True),
    NodeKind("platform_server", "hdrc3-platform-server", Scope.AGENT, ""),
    NodeKind("dyknow", "hdrc3-dyknow", Scope.AGENT, "", default=False),
)


def test_parse_nodes_keeps_catalog_order_and_always_started_nodes() -> None:
    assert parse_nodes("platform_server", CATALOG) == ("system_monitor", "platform_server")
    assert parse_nodes(None, CATALOG) == ("system_monitor", "world_sim", "platform_server")
    assert parse_nodes("dyknow", CATALOG) == ("system_monitor", "dyknow")


def test_unknown_node_lists_known_ones() -> None:
    with pytest.raises(ConfigError, match="unknown node 'pilot'; known nodes: system_monitor"):
        parse_nodes("pilot", CATALOG)


@pytest.mark.parametrize(("text", "speed"), [("1", 1.0), ("2.5", 2.5), ("max", math.inf)])
def test_parse_speed(text: str, speed: float) -> None:
    assert parse_speed(text) == speed


@pytest.mark.parametrize("text", ["0", "-1", "fast", "nan", "inf"])
def test_bad_speed(text: str) -> None:
    with pytest.raises(ConfigError, match="invalid --speed"):
        parse_speed(text)


@pytest.mark.parametrize("domain", [-1, 102, 232])
def test_bad_domain(domain: int) -> None:
    with pytest.raises(ConfigError, match="invalid --domain-id"):
        check_domain_id(domain)


@pytest.mark.parametrize(
    ("name", "message"),
    [("run.bag", "must end in .mcap"), ("nodir/run.mcap", "does not exist")],
)
def test_bad_record_path(tmp_path: Path, name: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        check_record_path(str(tmp_path / name))


@pytest.mark.parametrize(("pattern", "result"), [(None, ""), ("image_raw$", "image_raw$")])
def test_a_record_exclusion_is_a_regular_expression(pattern: str | None, result: str) -> None:
    assert check_topic_pattern(pattern) == result


def test_a_bad_record_exclusion_is_refused() -> None:
    with pytest.raises(ConfigError, match="not a regular expression"):
        check_topic_pattern("image_raw[")


def test_the_recorder_leaves_out_the_excluded_topics() -> None:
    options = LaunchOptions(
        agents=("uav0",),
        nodes=("world_sim",),
        world="revinge",
        speed=1.0,
        record=Path("run.mcap"),
        domain_id=None,
        record_exclude="image_raw$",
    )
    recorder = build_plan(options, launch_plan.CATALOG)[-1]
    assert recorder.argv[-2:] == ("--exclude", "image_raw$")


def test_plan_namespaces_agent_nodes_and_passes_world_params(tmp_path: Path) -> None:
    options = LaunchOptions(
        agents=("uav0", "uav1"),
        nodes=("system_monitor", "world_sim", "platform_server"),
        world="revinge",
        speed=math.inf,
        record=tmp_path / "run.mcap",
        domain_id=None,
    )
    specs = build_plan(options, CATALOG)
    assert [s.name for s in specs] == [
        "system_monitor",
        "world_sim",
        "uav0/platform_server",
        "uav1/platform_server",
        "recorder",
    ]
    assert [s.node_name for s in specs] == [
        "/system_monitor",
        "/world_sim",
        "/uav0/platform_server",
        "/uav1/platform_server",
        "/hdrc3_recorder",
    ]
    world_args = specs[1].argv[1:]
    assert "agents:=['uav0','uav1']" in world_args
    assert "world:=revinge" in world_args
    assert "speed:=0.0" in world_args
    assert specs[3].argv[-2:] == ("-r", "__ns:=/uav1")
    assert specs[4].argv[1:] == ("record", str(tmp_path / "run.mcap"), "--all")


@pytest.mark.parametrize(
    ("sim_world", "simulated", "model"),
    [(None, "revinge", "revinge"), ("revinge_changed", "revinge_changed", "revinge")],
)
def test_a_sim_world_goes_to_the_simulator_only(
    sim_world: str | None, simulated: str, model: str
) -> None:
    options = LaunchOptions(
        agents=("uav0",),
        nodes=("world_sim", "world_render", "path_planner", "laser_mapper"),
        world="revinge",
        speed=1.0,
        record=None,
        domain_id=None,
        sim_world=sim_world,
    )
    worlds = {
        s.name: next(a for a in s.argv if a.startswith("world:="))
        for s in build_plan(options, launch_plan.CATALOG)
    }
    assert worlds == {
        "world_sim": f"world:={simulated}",
        "world_render": f"world:={simulated}",
        "uav0/path_planner": f"world:={model}",
        "uav0/laser_mapper": f"world:={model}",
    }


@pytest.mark.parametrize(("port", "args"), [(None, []), (9123, ["port:=9123"])])
def test_the_live_view_is_global_and_gets_its_port(port: int | None, args: list[str]) -> None:
    options = LaunchOptions(
        agents=("uav0", "uav1"),
        nodes=("world_sim", "live_view"),
        world="revinge",
        speed=1.0,
        record=None,
        domain_id=None,
        live_port=port,
    )
    (_, live, recorder) = build_plan(replace(options, record=Path("run.mcap")), launch_plan.CATALOG)
    assert (live.name, live.node_name) == ("live_view", "/live_view")
    assert recorder.argv[-3:] == ("--live-channels", "--world", "revinge")
    assert "world:=revinge" in live.argv
    assert [a for a in live.argv if a.startswith("port:=")] == args


def test_live_port_in_use_or_out_of_range_is_refused() -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        port = taken.getsockname()[1]
        with pytest.raises(ConfigError, match=f"--live-port {port}: 127.0.0.1:{port} is not free"):
            check_live_port(port)
    for bad in (0, 65536):
        with pytest.raises(ConfigError, match="invalid --live-port"):
            check_live_port(bad)
    assert check_live_port(None) is None


@pytest.mark.parametrize("run_dir", [None, "run"])
def test_world_sim_and_each_control_kernel_get_their_own_checkpoint_in_the_run_directory(
    tmp_path: Path, run_dir: str | None
) -> None:
    options = LaunchOptions(
        agents=("uav0", "uav1"),
        nodes=("world_sim", "control_kernel", "platform_server"),
        world="revinge",
        speed=1.0,
        record=None,
        domain_id=None,
        run_dir=None if run_dir is None else tmp_path / run_dir,
    )
    checkpoints = {
        spec.name: [a for a in spec.argv if a.startswith("checkpoint:=")]
        for spec in build_plan(options, launch_plan.CATALOG)
    }
    files = {
        "world_sim": "world_sim.checkpoint",
        "uav0/control_kernel": "uav0.control_kernel.checkpoint",
        "uav1/control_kernel": "uav1.control_kernel.checkpoint",
        "uav0/platform_server": "uav0.platform_server.checkpoint",
        "uav1/platform_server": "uav1.platform_server.checkpoint",
    }
    assert checkpoints == {
        name: []
        if run_dir is None or file is None
        else [f"checkpoint:={tmp_path / run_dir}/{file}"]
        for name, file in files.items()
    }


def test_world_sim_is_in_the_catalogue_with_world_parameters() -> None:
    kinds = {kind.name: kind for kind in launch_plan.CATALOG}
    assert kinds["world_sim"].executable == "hdrc3-world-sim"
    assert kinds["world_sim"].scope is Scope.GLOBAL
    assert kinds["world_sim"].world_params


def test_check_world_accepts_shipped_names_and_world_files(tmp_path: Path) -> None:
    assert check_world("revinge") == "revinge"
    path = tmp_path / "mine.toml"
    path.write_text("[world]\nname = 'mine'\n")
    assert check_world(str(path)) == str(path.resolve())


@pytest.mark.parametrize("world", ["atlantis", "missing.toml", "revinge.json"])
def test_unknown_world_names_the_shipped_ones(world: str) -> None:
    with pytest.raises(ConfigError, match=f"unknown world '{world}'.*shipped worlds: revinge"):
        check_world(world)


@pytest.mark.parametrize(
    ("name", "executable"),
    [("path_planner", "hdrc3-path-planner"), ("tst_manager", "hdrc3-tst-manager")],
)
def test_planner_and_tst_manager_run_per_agent_when_named(name: str, executable: str) -> None:
    kind = {k.name: k for k in launch_plan.CATALOG}[name]
    assert (kind.executable, kind.scope, kind.default, kind.world_params) == (
        executable,
        Scope.AGENT,
        False,
        True,
    )
    assert name not in parse_nodes(None)
    assert name in parse_nodes(name)


@pytest.mark.parametrize("seed", [0, 7])
def test_only_the_simulator_gets_the_seed(seed: int) -> None:
    options = LaunchOptions(
        agents=("uav0",),
        nodes=("world_sim", "control_kernel"),
        world="revinge",
        speed=1.0,
        record=None,
        domain_id=None,
        seed=launch_plan.check_seed(seed),
    )
    seeds = {
        spec.name: [a for a in spec.argv if a.startswith("seed:=")]
        for spec in build_plan(options, launch_plan.CATALOG)
    }
    assert seeds == {"world_sim": [f"seed:={seed}"], "uav0/control_kernel": []}


def test_a_negative_seed_is_refused() -> None:
    with pytest.raises(ConfigError, match="seed must be an integer >= 0, got -1"):
        launch_plan.check_seed(-1)


def test_cameras_add_the_renderer_with_world_parameters_and_seed() -> None:
    assert "world_render" not in parse_nodes(None)
    assert "world_render" in parse_nodes(None, extra=("world_render",))
    assert parse_nodes("world_sim", extra=("world_render",)) == (
        "system_monitor",
        "world_sim",
        "world_render",
    )
    options = LaunchOptions(
        agents=("uav0", "uav1"),
        nodes=parse_nodes("world_sim", extra=("world_render",)),
        world="revinge",
        speed=1.0,
        record=None,
        domain_id=None,
        seed=3,
    )
    spec = next(s for s in build_plan(options, launch_plan.CATALOG) if s.name == "world_render")
    assert spec.argv[0].endswith("hdrc3-world-render")
    assert "agents:=['uav0','uav1']" in spec.argv and "seed:=3" in spec.argv
    assert "world:=revinge" in spec.argv


@pytest.mark.parametrize("given", [False, True])
def test_each_agents_execution_monitor_gets_the_monitor_spec(tmp_path: Path, given: bool) -> None:
    spec = tmp_path / "limits.monitors"
    spec.write_text("monitor a: always true;")
    options = LaunchOptions(
        agents=("uav0", "uav1"),
        nodes=parse_nodes("platform_server,execution_monitor"),
        world="revinge",
        speed=1.0,
        record=None,
        domain_id=None,
        monitor_spec=launch_plan.check_monitor_spec(str(spec) if given else None),
    )
    argv = {spec.name: spec.argv for spec in build_plan(options, launch_plan.CATALOG)}
    for agent in ("uav0", "uav1"):
        monitor = argv[f"{agent}/execution_monitor"]
        assert monitor[0].endswith("hdrc3-execution-monitor")
        assert (f"monitor_spec:={spec.resolve()}" in monitor) is given
        assert f"__ns:=/{agent}" in monitor
        assert not any(a.startswith("monitor_spec") for a in argv[f"{agent}/platform_server"])
    assert "execution_monitor" not in parse_nodes(None)


def test_a_missing_monitor_spec_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="is not a file"):
        launch_plan.check_monitor_spec(str(tmp_path / "none.monitors"))


def test_each_agents_gateway_gets_the_keystore_its_capabilities_and_the_acl_domain(
    tmp_path: Path,
) -> None:
    keystore = tmp_path / "keys.toml"
    keystore.write_text("[keys]\n")
    agents = ("uav0", "uav1")
    options = LaunchOptions(
        agents=agents,
        nodes=parse_nodes("platform_server,gateway"),
        world="revinge",
        speed=1.0,
        record=None,
        domain_id=None,
        keystore=launch_plan.check_keystore(str(keystore)),
        capabilities=launch_plan.parse_capabilities(["uav1=flight+hook"], agents),
        acl_domain=7,
        acl_discovery=launch_plan.check_discovery("subnet"),
    )
    argv = {spec.name: spec.argv for spec in build_plan(options, launch_plan.CATALOG)}
    for agent in agents:
        gateway = argv[f"{agent}/gateway"]
        assert gateway[0].endswith("hdrc3-gateway") and f"__ns:=/{agent}" in gateway
        assert f"keystore:={keystore.resolve()}" in gateway
        assert "acl_domain:=7" in gateway and "acl_discovery:=SUBNET" in gateway
    assert "capabilities:=['flight','hook']" in argv["uav1/gateway"]
    assert not any(a.startswith("capabilities") for a in argv["uav0/gateway"])
    assert "gateway" not in parse_nodes(None)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda p: launch_plan.check_keystore(str(p / "none.toml")), "is not a file"),
        (lambda p: launch_plan.parse_capabilities(["uav1=flight"], ("uav0",)), "AGENT=cap"),
        (lambda p: launch_plan.parse_capabilities(["uav0"], ("uav0",)), "AGENT=cap"),
        (lambda p: launch_plan.parse_capabilities(["uav0=wings"], ("uav0",)), "unknown 'wings'"),
        (lambda p: launch_plan.check_discovery("everywhere"), "invalid discovery range"),
    ],
)
def test_bad_gateway_options_are_refused(tmp_path: Path, call, message: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ConfigError, match=message):
        call(tmp_path)


def test_a_gateway_without_a_keystore_is_refused() -> None:
    options = LaunchOptions(("uav0",), parse_nodes("gateway"), "revinge", 1.0, None, None)
    with pytest.raises(ConfigError, match="need a keystore"):
        build_plan(options, launch_plan.CATALOG)
