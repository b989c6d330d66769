"""`hdrc3 delegate FILE.tst --to any|AGENT[,AGENT]`: the ground operator delegates a mission (§10).

The operator (agent ``gcs`` by default) auctions every node whose agent is open among the
candidates' gateways (FIPA contract net, see ``hdrc3_delegation.contract_net``), awards the
nodes to the winners, which commit through their constraint servers and create the mission on
their TST managers, and starts the root; one line per protocol step, then one per node state
the contractors report, until all are done. ``--to any`` asks the file's agents; ``--max-agents``
caps how many of them share the mission. ``--responsible AGENT`` asks AGENT alone to answer for
the whole mission: its gateway auctions the nodes among itself and its peers, proposes their
bids together, awards them when awarded and relays their progress. With ``--launch`` the system
is started first (with a gateway per agent) and the aircraft are handed to autonomous mode as
``hdrc3 tst run`` does.

Exit codes: 0 the mission was delegated and succeeded, 1 it failed (or no allocation exists;
the reasons are printed), 3 a candidate's gateway is not running, 4 invalid input (the file, as
FILE:LINE:COLUMN; the candidates).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from rich.console import Console

from hdrc3.launch_plan import CAMERA_NODES, CATALOG, GATEWAY
from hdrc3.launched_system import LaunchedSystem
from hdrc3.safety_pilot import hand_over
from hdrc3_base.agents import parse_agents
from hdrc3_base.errors import ConfigError
from hdrc3_base.ros_runtime import RosProcess
from hdrc3_delegation.authentication import Authenticator
from hdrc3_delegation.contract_net import Delegation, Phase, Timing
from hdrc3_delegation.keystore import load_keystore
from hdrc3_delegation.ros_operator import RosDelegator
from hdrc3_tst.check import CheckStatus, load_file
from hdrc3_tst.resolver import ResolvedTst

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_UNREACHABLE = 3
EXIT_INVALID = 4
GATEWAY_WAIT_S = 30.0


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``delegate`` subcommand."""
    parser = subparsers.add_parser(
        "delegate",
        help="delegate a TST to agents: contract-net auction, commitment, execution",
        description=__doc__.split("\n\n")[-1] if __doc__ else None,
    )
    parser.add_argument("file", help="a .tst file whose nodes leave their agent open")
    parser.add_argument("--to", default="any", help="'any' (the file's agents) or AGENT[,AGENT]")
    parser.add_argument("--max-agents", type=int, default=None, help="at most N agents share it")
    parser.add_argument(
        "--responsible",
        metavar="AGENT",
        default=None,
        help="make AGENT answer for the whole mission: its gateway delegates it on to itself and"
        " the other agents of its launch (a network of responsibilities, section 10)",
    )
    parser.add_argument("--keystore", required=True, help="agent keys (hdrc3 keys generate)")
    parser.add_argument("--as", dest="operator", default="gcs", help="the delegating agent")
    parser.add_argument("--mission", default=None, help="mission id (default: FILE stem + time)")
    parser.add_argument("--answer-s", type=float, default=15.0, help="cfp reply-by, wall s")
    parser.add_argument("--timeout", type=float, default=3600.0, help="wall seconds in all")
    parser.add_argument("--launch", action="store_true", help="start the system first")
    parser.add_argument("--world", default=None, help="with --launch: world (default: the file's)")
    parser.add_argument("--speed", default="max", help="with --launch: real-time factor or 'max'")
    parser.add_argument("--domain-id", type=int, default=44, help="with --launch: ROS domain")
    parser.add_argument(
        "--capabilities",
        metavar="AGENT=CAP+CAP",
        action="append",
        help="with --launch: what an agent offers, e.g. uav2=flight+hook",
    )
    parser.add_argument("--record", default=None, help="with --launch: record to FILE.mcap")
    parser.add_argument(
        "--seed", type=int, default=0, help="with --launch: simulation seed (sensor outages)"
    )
    parser.set_defaults(handler=_delegate)


def _delegate(args: argparse.Namespace) -> int:
    console = Console(highlight=False, soft_wrap=True, markup=False)
    path = Path(args.file)
    check = load_file(path)
    for diag in check.diagnostics:
        console.print(str(diag))
    if check.status is not CheckStatus.OK or check.tst is None:
        console.print(f"{path}: {check.status.value}")
        return EXIT_INVALID
    candidates = check.tst.agents if args.to == "any" else parse_agents(args.to)
    if not candidates:
        raise ConfigError(f"{path} declares no agents: give --to AGENT[,AGENT]")
    if args.max_agents is not None and args.max_agents < 1:
        raise ConfigError(f"--max-agents must be >= 1, not {args.max_agents}")
    if args.responsible is not None and args.responsible not in candidates:
        raise ConfigError(
            f"--responsible {args.responsible} is not one of the agents {', '.join(candidates)}"
        )
    auth = Authenticator(args.operator, load_keystore(args.keystore))
    mission = args.mission or f"{path.stem}-{int(time.time())}"
    if not args.launch:
        return _run(console, args, auth, mission, candidates, check.tst, hand_over_first=False)
    world = args.world or check.tst.world
    if world is None:
        raise ConfigError("--launch needs a world: the file declares none; give --world")
    nodes = [k.name for k in CATALOG if k.default] + ["tst_manager", "path_planner", GATEWAY]
    if any(node.action == "scan-area" for node in check.tst.tree.nodes.values()):
        nodes += CAMERA_NODES
    extra = ["--keystore", str(Path(args.keystore).resolve())]
    for item in args.capabilities or ():
        extra += ["--capabilities", item]
    record = Path(args.record) if args.record else None
    with LaunchedSystem(
        candidates,
        world,
        args.speed,
        args.domain_id,
        record,
        nodes,
        console.print,
        args.seed,
        extra,
    ):
        return _run(console, args, auth, mission, candidates, check.tst, hand_over_first=True)


def _run(
    console: Console,
    args: argparse.Namespace,
    auth: Authenticator,
    mission: str,
    candidates: tuple[str, ...],
    tst: ResolvedTst,
    hand_over_first: bool,
) -> int:
    text = Path(args.file).read_text(encoding="utf-8")
    with RosProcess() as process:
        operator = RosDelegator(process, auth)
        missing = operator.wait_for_gateways(candidates, GATEWAY_WAIT_S)
        if missing:
            console.print(f"no gateway answers for {', '.join(missing)} (/<agent>/acl_inbox)")
            return EXIT_UNREACHABLE
        if hand_over_first:
            for agent in candidates:
                hand_over(process, operator.node, agent)
                console.print(f"safety pilot: {agent} engine on, RC switch to autonomous")
        timing = Timing(answer_s=args.answer_s, award_s=2 * args.answer_s, execution_s=args.timeout)
        asked = (args.responsible,) if args.responsible else candidates
        delegation = Delegation(
            auth.agent,
            f"{mission}@{auth.agent}",
            mission,
            text,
            tst,
            asked,
            args.max_agents,
            timing,
            whole=args.responsible is not None,
        )
        whole = f" (the whole mission; {args.responsible} re-delegates)" if args.responsible else ""
        console.print(f"delegating {mission} to {', '.join(asked)}{whole}")
        operator.run(delegation, args.timeout, console.print)
        for line in operator.refusals:
            console.print(f"refused: {line}")
    console.print(f"{delegation.messages_sent} speech acts sent by {auth.agent}")
    if delegation.phase is Phase.DONE:
        console.print(f"mission {mission} delegated and done")
        return EXIT_OK
    console.print(f"DELEGATION FAILED: {delegation.reason or delegation.phase.value}")
    return EXIT_FAILED
