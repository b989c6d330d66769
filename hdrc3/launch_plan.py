"""What `hdrc3 launch` starts: the node catalogue and the plan built from the command line.

Pure core: validates the user's choices (agents, nodes, world, speed, domain, recording) and turns
them into :class:`~hdrc3.supervisor.ProcessSpec` values; starting them is the launcher's job.
"""

from __future__ import annotations

import enum
import importlib.metadata
import math
import re
import socket
import sys
from collections.abc import Collection, Sequence
from dataclasses import dataclass
from pathlib import Path

from hdrc3.supervisor import ProcessSpec
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_env import DISCOVERY_RANGES, MAX_DOMAIN_ID

RECORDER = "recorder"
LIVE_VIEW = "live_view"
EXECUTION_MONITOR = "execution_monitor"
LASER_MAPPER = "laser_mapper"
GATEWAY = "gateway"


class Scope(enum.Enum):
    """Whether a node runs once per launch or once per agent (in the agent's namespace)."""

    GLOBAL = "global"
    AGENT = "agent"


@dataclass(frozen=True, slots=True)
class NodeKind:
    """One node the launcher knows how to start."""

    name: str
    executable: str
    scope: Scope
    description: str
    world_params: bool = False
    """True if the node takes the launch's agents/world/speed as ROS parameters."""
    default: bool = True
    """Started without --nodes; optional nodes start only when named."""
    seeded: bool = False
    """True if the node takes the launch's ``seed`` (the simulator)."""
    checkpoint: bool = False
    """True if the node takes a ``checkpoint`` file in the launch's run directory (to resume
    its state when the launcher restarts it; the platform server's: its open commands)."""


CATALOG: tuple[NodeKind, ...] = (
    NodeKind(
        "system_monitor",
        "hdrc3-system-monitor",
        Scope.GLOBAL,
        "diagnostics: liveness, restarts, CPU and memory of every supervised node",
    ),
    NodeKind(
        "world_sim",
        "hdrc3-world-sim",
        Scope.GLOBAL,
        "simulated world: /clock, the aircraft of every agent, their sensors and ground truth",
        world_params=True,
        seeded=True,
        checkpoint=True,
    ),
    NodeKind(
        "world_render",
        "hdrc3-world-render",
        Scope.GLOBAL,
        "camera images: colour (rgb8) and thermal (mono16 centi-kelvin) of every agent",
        world_params=True,
        default=False,
        seeded=True,
    ),
    NodeKind(
        "control_kernel",
        "hdrc3-control-kernel",
        Scope.AGENT,
        "PFC: flight modes driven by HCSMs at 50 Hz",
        world_params=True,
        checkpoint=True,
    ),
    NodeKind(
        "platform_server",
        "hdrc3-platform-server",
        Scope.AGENT,
        "DRC: FCL/PPCL services, platform events and the 25 Hz Data Interface (chapter 6.2)",
        world_params=True,
        checkpoint=True,
    ),
    NodeKind(
        "perception_kernel",
        "hdrc3-perception-kernel",
        Scope.AGENT,
        "PPC: pan-tilt, camera and laser control modes behind PPCL (chapter 5.2)",
        world_params=True,
    ),
    NodeKind(
        "saliency",
        "hdrc3-saliency",
        Scope.AGENT,
        "Algorithm 4: the saliency map from the camera images while the PPC engages it (11.1.1)",
        world_params=True,
        default=False,
    ),
    NodeKind(
        "pad_pose",
        "hdrc3-pad-pose",
        Scope.AGENT,
        "the landing pad's pose from the colour camera while the PPC engages it (5.4)",
        world_params=True,
        default=False,
    ),
    NodeKind(
        "color_tracker",
        "hdrc3-color-tracker",
        Scope.AGENT,
        "colour tracking of a seeded object and its ground position while the PPC engages it "
        "(6.1, 6.2.3)",
        world_params=True,
        default=False,
    ),
    NodeKind(
        LASER_MAPPER,
        "hdrc3-laser-mapper",
        Scope.AGENT,
        "elevation map from the laser while the PPC collects, stored in the planner's GIS (11.2)",
        world_params=True,
        default=False,
    ),
    NodeKind(
        "tst_manager",
        "hdrc3-tst-manager",
        Scope.AGENT,
        "TST factory and executors: missions as task specification trees (chapter 6.3)",
        world_params=True,
        default=False,
    ),
    NodeKind(
        "path_planner",
        "hdrc3-path-planner",
        Scope.AGENT,
        "path planner: PRM/RRT on OMPL with GIS on FCL, plan and motion_plan_info (chapter 7)",
        world_params=True,
        default=False,
    ),
    NodeKind(
        "dyknow",
        "hdrc3-dyknow",
        Scope.AGENT,
        "DyKnow: streams, state synchronisation and temporal-logic monitoring (chapter 8)",
        default=False,
    ),
    NodeKind(
        "task_planner",
        "hdrc3-task-planner",
        Scope.AGENT,
        "TALplanner plan service (chapter 9.2); flights from the path planner in the world",
        world_params=True,
        default=False,
    ),
    NodeKind(
        EXECUTION_MONITOR,
        "hdrc3-execution-monitor",
        Scope.AGENT,
        "execution monitor: monitor formulas over DyKnow streams and execution flags (chapter 9.3)",
        world_params=True,
        default=False,
    ),
    NodeKind(
        GATEWAY,
        "hdrc3-gateway",
        Scope.AGENT,
        "gateway: signed FIPA ACL speech acts, delegation and the constraint server (chapter 10)",
        world_params=True,
        default=False,
    ),
    NodeKind(
        LIVE_VIEW,
        "hdrc3-live-view",
        Scope.GLOBAL,
        "live view: the world, aircraft, paths, TSTs and events for Foxglove over a WebSocket",
        world_params=True,
        default=False,
    ),
)
ALWAYS_STARTED = frozenset({"system_monitor"})
CAMERA_NODES = ("world_render", "saliency", "pad_pose")
SIMULATED = ("world_sim", "world_render")
"""The nodes that make a world real (``--sim-world``); every other node holds it as a model."""
"""Started by ``--cameras`` in addition to the chosen nodes: the images and their pipelines."""


@dataclass(frozen=True, slots=True)
class LaunchOptions:
    """Validated choices of one `hdrc3 launch`."""

    agents: tuple[str, ...]
    nodes: tuple[str, ...]
    world: str
    speed: float
    """Real-time factor; ``math.inf`` means as fast as possible."""
    record: Path | None
    domain_id: int | None
    run_dir: Path | None = None
    """Directory of this launch's run files (checkpoints); None: no checkpoints."""
    seed: int = 0
    """The simulation's seed (sensor noise and outages, wind): the same seed, the same world."""
    live_port: int | None = None
    """WebSocket port of the live view (None: its default), when ``live_view`` is started."""
    monitor_spec: Path | None = None
    """Monitor specification of the ``execution_monitor`` nodes (None: the packaged default)."""
    keystore: Path | None = None
    """Agent keys of the ``gateway`` nodes (required when they run)."""
    capabilities: tuple[tuple[str, tuple[str, ...]], ...] = ()
    """(agent, capability names) of agents whose gateway offers less than every capability."""
    acl_domain: int | None = None
    """ROS domain of the gateways' speech acts (None: the launch's own domain)."""
    acl_discovery: str = ""
    """Discovery range of that domain only ("": the environment's, loopback by default)."""
    record_exclude: str = ""
    """Regular expression of topics the recording leaves out ("": none)."""
    sim_world: str | None = None
    """The world the simulator (and its renderer) make real, when it is not the one the stack's
    nodes hold as their model (``world``): a stale map, as the laser's elevation map finds it
    (section 11.2). None: the same world."""


def parse_nodes(
    text: str | None, catalog: Sequence[NodeKind] = CATALOG, extra: Collection[str] = ()
) -> tuple[str, ...]:
    """Parse ``a,b`` into catalogue node names; None selects the default nodes.

    ``extra`` nodes are added to the chosen ones (``--cameras``: :data:`CAMERA_NODES`, ``--live``:
    :data:`LIVE_VIEW`); the result is in catalogue order, each node once.
    """
    known = [kind.name for kind in catalog]
    if text is None:
        return tuple(kind.name for kind in catalog if kind.default or kind.name in extra)
    nodes = tuple(n.strip() for n in text.split(",") if n.strip())
    unknown = [n for n in nodes if n not in known]
    if unknown:
        raise ConfigError(f"unknown node {unknown[0]!r}; known nodes: {', '.join(known)}")
    return tuple(n for n in known if n in nodes or n in ALWAYS_STARTED or n in extra)


def parse_speed(text: str) -> float:
    """Parse a real-time factor: a positive number, or ``max``."""
    if text.strip().lower() == "max":
        return math.inf
    try:
        speed = float(text)
    except ValueError:
        raise ConfigError(
            f"invalid --speed {text!r}: expected a positive number or 'max'"
        ) from None
    if not math.isfinite(speed) or speed <= 0:
        raise ConfigError(f"invalid --speed {text!r}: expected a positive number or 'max'")
    return speed


def check_world(world: str) -> str:
    """Accept a shipped world name or an existing world file (``.toml``)."""
    from sim.world_loader import shipped_worlds  # the world data ships with the sim package

    shipped = shipped_worlds()
    if world in shipped:
        return world
    path = Path(world)
    if path.suffix == ".toml" and path.is_file():
        return str(path.resolve())
    raise ConfigError(
        f"unknown world {world!r}: not a world file; shipped worlds: {', '.join(shipped)}"
    )


def check_seed(seed: int) -> int:
    """A simulation seed, or ConfigError."""
    if seed < 0:
        raise ConfigError(f"seed must be an integer >= 0, got {seed}")
    return seed


def check_discovery(text: str | None) -> str:
    """A discovery range name (or "" for the environment's)."""
    if not text:
        return ""
    if text.upper() not in DISCOVERY_RANGES:
        raise ConfigError(f"invalid discovery range {text!r}: one of {', '.join(DISCOVERY_RANGES)}")
    return text.upper()


def check_domain_id(domain_id: int | None) -> int | None:
    """Reject ROS domain ids outside 0..101."""
    if domain_id is not None and not 0 <= domain_id <= MAX_DOMAIN_ID:
        raise ConfigError(f"invalid --domain-id {domain_id}: expected 0..{MAX_DOMAIN_ID}")
    return domain_id


def check_live_port(port: int | None, host: str = "127.0.0.1") -> int | None:
    """A free TCP port for the live view, or ConfigError (out of range, or in use)."""
    if port is None:
        return None
    if not 1 <= port <= 65535:
        raise ConfigError(f"invalid --live-port {port}: expected 1..65535")
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        try:
            probe.bind((host, port))
        except OSError as exc:
            raise ConfigError(
                f"--live-port {port}: {host}:{port} is not free ({exc.strerror}); choose another"
            ) from None
    return port


def check_monitor_spec(path: str | None) -> Path | None:
    """Check that a monitor specification file exists; return its absolute path."""
    if path is None:
        return None
    spec = Path(path)
    if not spec.is_file():
        raise ConfigError(f"monitor specification {spec} is not a file")
    return spec.resolve()


def check_keystore(path: str | None) -> Path | None:
    """Check that a keystore file exists; return its absolute path."""
    if path is None:
        return None
    keystore = Path(path)
    if not keystore.is_file():
        raise ConfigError(f"keystore {keystore} is not a file (create one: hdrc3 keys generate)")
    return keystore.resolve()


def parse_capabilities(
    items: Sequence[str] | None, agents: Sequence[str]
) -> tuple[tuple[str, tuple[str, ...]], ...]:
    """``AGENT=cap+cap`` items (e.g. ``uav2=flight+hook``) -> (agent, names); ConfigError if bad."""
    from hdrc3_tst.actions import Capability  # the registry's capabilities are the names

    known = {c.value for c in Capability}
    out: dict[str, tuple[str, ...]] = {}
    for item in items or ():
        agent, sep, caps = item.partition("=")
        names = tuple(c.strip() for c in caps.split("+") if c.strip())
        if not sep or agent not in agents:
            raise ConfigError(
                f"--capabilities {item!r}: expected AGENT=cap+cap, AGENT one of {list(agents)}"
            )
        unknown = [n for n in names if n not in known]
        if unknown:
            raise ConfigError(
                f"--capabilities {item!r}: unknown {unknown[0]!r}; "
                f"known: {', '.join(sorted(known))}"
            )
        out[agent] = names
    return tuple(out.items())


RAW_IMAGES = r"/camera/[^/]+/image_raw$"
"""The cameras' raw images (``--record-exclude`` pattern): about 8 MB per sim second per
aircraft with both cameras at full rate, and no mission product reads them back."""


def check_topic_pattern(pattern: str | None) -> str:
    """Check a regular expression of topic names (None: none)."""
    if not pattern:
        return ""
    try:
        re.compile(pattern)
    except re.error as exc:
        raise ConfigError(
            f"--record-exclude {pattern!r} is not a regular expression: {exc}"
        ) from None
    return pattern


def check_record_path(path: str | None) -> Path | None:
    """Check that a recording can be created at ``path``."""
    if path is None:
        return None
    out = Path(path)
    if out.suffix != ".mcap":
        raise ConfigError(f"recording file {out} must end in .mcap")
    if not out.parent.resolve().is_dir():
        raise ConfigError(f"directory {out.parent} of the recording does not exist")
    if out.is_dir():
        raise ConfigError(f"{out} is a directory")
    return out


def _executable(name: str) -> str:
    """Console scripts live beside the running interpreter (the venv's bin directory)."""
    candidate = Path(sys.executable).parent / name
    return str(candidate) if candidate.exists() else name


def entry_point(executable: str) -> str:
    """``module:function`` of an installed console script, "" if it is not one of ours."""
    for script in importlib.metadata.entry_points(group="console_scripts", name=executable):
        return str(script.value)
    return ""


def build_plan(options: LaunchOptions, catalog: Sequence[NodeKind] = CATALOG) -> list[ProcessSpec]:
    """Turn validated options into the processes to start (the recorder last)."""
    specs: list[ProcessSpec] = []
    for kind in catalog:
        if kind.name not in options.nodes:
            continue
        args: list[str] = ["--ros-args"]
        if kind.world_params:
            agents = ",".join(f"'{a}'" for a in options.agents)
            speed = "0.0" if math.isinf(options.speed) else repr(options.speed)
            world = options.world
            if options.sim_world is not None and kind.name in SIMULATED:
                world = options.sim_world
            args += ["-p", f"agents:=[{agents}]", "-p", f"world:={world}"]
            args += ["-p", f"speed:={speed}"]
        if kind.seeded:
            args += ["-p", f"seed:={options.seed}"]
        if kind.name == LIVE_VIEW and options.live_port is not None:
            args += ["-p", f"port:={options.live_port}"]
        if kind.name == EXECUTION_MONITOR and options.monitor_spec is not None:
            args += ["-p", f"monitor_spec:={options.monitor_spec}"]
        if kind.name == GATEWAY:
            if options.keystore is None:
                raise ConfigError("the gateway nodes need a keystore: give --keystore FILE")
            args += ["-p", f"keystore:={options.keystore}"]
            if options.acl_domain is not None:
                args += ["-p", f"acl_domain:={options.acl_domain}"]
                args += ["-p", f"acl_discovery:={options.acl_discovery}"] * bool(
                    options.acl_discovery
                )
        if kind.scope is Scope.GLOBAL:
            if kind.checkpoint and options.run_dir is not None:
                args += ["-p", f"checkpoint:={options.run_dir / kind.name}.checkpoint"]
            specs.append(
                ProcessSpec(
                    kind.name,
                    (_executable(kind.executable), *args),
                    f"/{kind.name}",
                    entry=entry_point(kind.executable),
                )
            )
            continue
        for agent in options.agents:
            own = list(args)
            if kind.checkpoint and options.run_dir is not None:
                own += ["-p", f"checkpoint:={options.run_dir / agent}.{kind.name}.checkpoint"]
            caps = dict(options.capabilities).get(agent)
            if kind.name == GATEWAY and caps is not None:
                own += ["-p", "capabilities:=[" + ",".join(f"'{c}'" for c in caps) + "]"]
            specs.append(
                ProcessSpec(
                    f"{agent}/{kind.name}",
                    (_executable(kind.executable), *own, "-r", f"__ns:=/{agent}"),
                    f"/{agent}/{kind.name}",
                    entry=entry_point(kind.executable),
                )
            )
    if options.record is not None:
        # with the live view, the recording holds its channels too (the same Foxglove layout)
        live: tuple[str, ...] = ()
        if LIVE_VIEW in options.nodes:
            live = ("--live-channels", "--world", options.world)
        if options.record_exclude:
            live += ("--exclude", options.record_exclude)
        specs.append(
            ProcessSpec(
                RECORDER,
                (_executable("hdrc3"), "record", str(options.record), "--all", *live),
                "/hdrc3_recorder",
                entry=entry_point("hdrc3"),
            )
        )
    return specs
