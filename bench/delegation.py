"""Benchmark: task allocation by delegation over DDS, and forged speech acts (issue 17).

**Allocation.** A child process hosts N contractors (one rclpy node each, on loopback, a domain
of its own): each with its authenticator, its constraint server pricing flights with the real
PRM/RRT path planner of revinge (one planner shared in the process) and a fake TST manager (the
allocation ends when every winner agreed; nothing flies). This process is the ground operator:
it delegates a generated 10-node TST (a sequence of three concurrent pairs of fly-tos, every
agent open) with ``Delegation`` and ``RosDelegator`` and measures the wall time from the first
cfp to the last agree, and counts the speech acts both ways. It allocates twice: "cold" includes
the contractors' first answers (their publishers to the operator match then) and the planner's
first queries; "warm" is a second mission on the same system. Targets: 5 agents <= 1 s, 20
agents <= 5 s.

**Forgery.** 1,000 attempts against an ``Authenticator``: tampered fields, wrong keys, unknown
senders, random signatures, replays of accepted messages, stale and future timestamps; and 1,000
genuine messages as the control (all must be accepted). Target: 0 forged or replayed accepted.

Run: .venv/bin/python bench/delegation.py [--agents 5 20] [--domain 97]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import random
import subprocess
import sys
import time
from typing import Any

MISSION_GROUPS = 3


def mission(agents: list[str]) -> str:
    """1 + 3 * 3 = 10 nodes: a sequence of three concurrent pairs of fly-tos, agents open."""
    lines = ["world revinge", f"agents {', '.join(agents)}"]
    points = [(-250 + 60 * i, -60 + 40 * (i % 2), 30) for i in range(2 * MISSION_GROUPS)]
    lines += [f"point W{i} = ({e}, {n}, {u})" for i, (e, n, u) in enumerate(points)]
    group_vars = ", ".join(f"S{g}, E{g}" for g in range(MISSION_GROUPS))
    lines.append(f"m(P, TS, TE) = with {group_vars} sequence")
    for g in range(MISSION_GROUPS):
        a, b = 2 * g, 2 * g + 1
        lines.append(
            f"  g{g}(S{g}, E{g}) = with Pa{g}, Ta{g}, Ua{g}, Pb{g}, Tb{g}, Ub{g} concurrent"
        )
        lines.append(f"    f{a}(Pa{g}, Ta{g}, Ua{g}) = fly-to(Ta{g}, Ua{g}, 8, W{a});")
        lines.append(f"    f{b}(Pb{g}, Tb{g}, Ub{g}) = fly-to(Tb{g}, Ub{g}, 8, W{b})")
        end = ";" if g < MISSION_GROUPS - 1 else ""
        lines.append(
            f"  where S{g} <= Ta{g} and Ua{g} <= E{g} and S{g} <= Tb{g} and Ub{g} <= E{g}{end}"
        )
    order = " and ".join(f"E{g} <= S{g + 1}" for g in range(MISSION_GROUPS - 1))
    lines.append(f"where TS <= S0 and {order} and E{MISSION_GROUPS - 1} <= TE and TE <= 3600")
    return "\n".join(lines) + "\n"


def agent_names(count: int) -> list[str]:
    return [f"uav{i}" for i in range(count)]


def host(count: int, keystore: str) -> int:
    """The contractors' process: serve until stdin closes."""
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node

    from hdrc3_base.ros_runtime import RosProcess
    from hdrc3_delegation.authentication import Authenticator
    from hdrc3_delegation.constraint_server import AgentProfile, ConstraintServer
    from hdrc3_delegation.contract_net import Contractor
    from hdrc3_delegation.fakes import FakeManager
    from hdrc3_delegation.keystore import load_keystore
    from hdrc3_delegation.messages import from_msg
    from hdrc3_delegation.node import ACL_QOS, Outbox, inbox
    from hdrc3_delegation.task_cost import PlannerMotion, TaskCoster
    from hdrc3_interfaces.msg import AclMessage as AclMessageMsg
    from hdrc3_navigation.planner import PathPlanner
    from hdrc3_platform_server.geo_frame import frame_from_world
    from hdrc3_tst.worlds import WorldCache
    from sim.world_loader import load_world

    keys = load_keystore(keystore)
    planner = PathPlanner(load_world("revinge"))
    planner.roadmap()
    frame = frame_from_world("revinge")
    rng = random.Random(1)
    worlds = WorldCache()  # one per process, as each gateway process keeps its own
    with RosProcess() as process:
        executor = SingleThreadedExecutor(context=process.context)
        for name in agent_names(count):
            node = Node("gateway", namespace=f"/{name}", context=process.context)
            auth = Authenticator(name, keys)
            start = (rng.uniform(-280, 100), rng.uniform(-150, 100), 0.0)
            start = (start[0], start[1], frame.ground_up(start[0], start[1]))
            coster = TaskCoster(PlannerMotion(planner), frame.ground_up)
            server = ConstraintServer(AgentProfile(name), coster, start, worlds=worlds)
            contractor = Contractor(name, server, FakeManager())
            outbox = Outbox(node, auth)

            def on_acl(
                ros: Any, auth: Any = auth, contractor: Any = contractor, outbox: Any = outbox
            ) -> None:
                now = time.time()
                decoded = from_msg(ros)
                if decoded.message is not None and auth.verify(decoded.message, now).accepted:
                    outbox.send(contractor.handle(decoded.message, now))

            node.create_subscription(AclMessageMsg, inbox(name), on_acl, ACL_QOS)
            executor.add_node(node)
        print("HOST READY", flush=True)
        while not process.stop_requested.is_set():
            executor.spin_once(timeout_sec=0.1)
            if os.getppid() == 1:
                break
    return 0


def allocate(count: int, keystore: str, domain: int) -> dict[str, Any]:
    from hdrc3_base.ros_runtime import RosProcess
    from hdrc3_delegation.authentication import Authenticator
    from hdrc3_delegation.contract_net import Delegation, Phase, Timing
    from hdrc3_delegation.keystore import load_keystore
    from hdrc3_delegation.ros_operator import RosDelegator
    from hdrc3_tst.check import load_text

    env = dict(os.environ, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    child = subprocess.Popen(
        [sys.executable, __file__, "--host", str(count), "--keystore", keystore],
        stdout=subprocess.PIPE,
        text=True,
        env=env,
    )
    try:
        assert child.stdout is not None
        for line in child.stdout:
            if "HOST READY" in line:
                break
        agents = agent_names(count)
        text = mission(agents)
        tst = load_text(text).tst
        assert tst is not None, "the generated mission does not load"
        os.environ["ROS_DOMAIN_ID"] = str(domain)
        with RosProcess() as process:
            operator = RosDelegator(process, Authenticator("gcs", load_keystore(keystore)))
            missing = operator.wait_for_gateways(tuple(agents), 60.0)
            assert not missing, missing
            runs = []
            allocated = (Phase.STARTING, Phase.EXECUTING, Phase.DONE, Phase.FAILED)
            for attempt in ("cold", "warm"):
                delegation = Delegation(
                    "gcs", f"{attempt}{count}", attempt, text, tst, agents, timing=Timing()
                )
                received = operator.received_count
                t0 = time.perf_counter()
                operator.run(delegation, 120.0, until=lambda d: d.phase in allocated)
                runs.append(
                    {
                        "run": attempt,
                        "allocation_s": time.perf_counter() - t0,
                        "phase": delegation.phase.value,
                        "acts_sent": delegation.messages_sent,
                        "acts_received": operator.received_count - received,
                        "agents_used": len(set(delegation.assignment.values())),
                    }
                )
            return {"agents": count, "nodes": len(tst.tree.nodes), "runs": runs}
    finally:
        child.terminate()
        child.wait(timeout=30)


def forgeries(attempts: int = 1000) -> dict[str, int]:
    from hdrc3_delegation.acl import AclMessage, Performative
    from hdrc3_delegation.authentication import Authenticator
    from hdrc3_delegation.keystore import Keystore

    rng = random.Random(7)
    keys = Keystore({a: rng.randbytes(32) for a in ("gcs", "uav0", "uav1")})
    stranger = Keystore({"gcs": rng.randbytes(32), "mallory": rng.randbytes(32)})
    receiver = Authenticator("uav0", keys)
    gcs = Authenticator("gcs", keys)
    base = AclMessage(Performative.CFP, "gcs", ("uav0",), '{"x":1}', conversation_id="c")
    now = 1_000_000.0
    genuine_ok = 0
    history: list[AclMessage] = []
    for i in range(attempts):
        msg = gcs.sign(dataclasses.replace(base, content=f'{{"i":{i}}}'), now + i * 0.01)
        genuine_ok += receiver.verify(msg, now + i * 0.01).accepted
        history.append(msg)
    kinds = ("tamper", "wrong_key", "stranger", "random_sig", "replay", "stale", "future")
    accepted = 0
    t = now + attempts * 0.01
    for i in range(attempts):
        kind = kinds[i % len(kinds)]
        original = rng.choice(history)
        if kind == "tamper":
            field = rng.choice(
                ["content", "receivers", "reply_by", "conversation_id", "sender", "nonce"]
            )
            value: Any = {
                "content": original.content + " ",
                "receivers": ("uav0", "uav1"),
                "reply_by": original.reply_by + 1.0,
                "conversation_id": "d",
                "sender": "uav1",
                "nonce": "00" * 16,
            }[field]
            msg = dataclasses.replace(original, **{field: value})
        elif kind == "wrong_key":
            msg = Authenticator("gcs", stranger).sign(base, t)
        elif kind == "stranger":
            msg = Authenticator("mallory", stranger).sign(
                dataclasses.replace(base, sender="mallory"), t
            )
        elif kind == "random_sig":
            msg = dataclasses.replace(gcs.sign(base, t), signature=rng.randbytes(32).hex())
        elif kind == "replay":
            msg = original
        elif kind == "stale":
            msg = gcs.sign(base, t - 3600.0)
        else:
            msg = gcs.sign(base, t + 3600.0)
        accepted += receiver.verify(msg, t).accepted
    return {
        "genuine": attempts,
        "genuine_accepted": genuine_ok,
        "forged": attempts,
        "forged_accepted": accepted,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--agents", type=int, nargs="*", default=[5, 20])
    parser.add_argument("--domain", type=int, default=97)
    parser.add_argument("--host", type=int, default=0, help=argparse.SUPPRESS)
    parser.add_argument("--keystore", default="", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.host:
        return host(args.host, args.keystore)
    import tempfile

    from hdrc3_delegation.keystore import write_keystore

    forged = forgeries()
    print(
        f"forgery: {forged['forged_accepted']} of {forged['forged']} forged, replayed or stale "
        "accepted "
        f"(target 0); genuine accepted {forged['genuine_accepted']} of {forged['genuine']}",
        flush=True,
    )
    with tempfile.TemporaryDirectory() as tmp:
        for count in args.agents:
            keystore = os.path.join(tmp, f"keys{count}.toml")
            write_keystore(keystore, ["gcs", *agent_names(count)])
            result = allocate(count, keystore, args.domain)
            target = 1.0 if count <= 5 else 5.0
            for run in result["runs"]:
                print(
                    f"allocation ({run['run']}): {result['nodes']}-node TST among {count} "
                    f"agents: {run['allocation_s']:.2f} s wall (target <= {target:g} s), "
                    f"{run['acts_sent']} acts sent + {run['acts_received']} received, "
                    f"{run['agents_used']} agents used, phase {run['phase']}",
                    flush=True,
                )
    return 0


if __name__ == "__main__":
    sys.exit(main())
