"""Benchmark: bursts of concurrent service calls to the FCL, PPCL and simulator services.

Starts ``hdrc3 launch --nodes world_sim,platform_server`` for one agent on a private ROS domain,
then N client processes (default 5), each with its own rclpy context. At a common wall-clock start
every client sends a burst of calls at once without waiting (``call_async``), round robin over
``fcl/climb`` (NaN altitude: FCL_NOT_ACCEPTED), ``fcl/yaw`` (no control kernel:
FCL_NOT_ACCEPTED), ``ppcl/ptu_limits`` (PPCL_OK) and ``/world_sim/teleport`` (unknown frame:
INVALID_ARGUMENT) - every one of them has a defined answer - then waits (bounded) for all answers
before the next burst. Refusals are answers; a call without an answer after the wait is lost.
Before the start every client gets one answer from each service (sent again until answered), so
that a lost count is a queueing loss and not DDS dropping the first answers to a new client.

Figures: calls sent, answered, lost per client and in total; slowest answer of a burst (wall).
Target (issue 21): 1,000 calls in bursts from 5 clients, 100 % answered.
``--client-qos default`` makes the clients use rclpy's default service QoS (keep last 10 answers)
to show the client half of the cause.

Run: .venv/bin/python bench/service_burst.py [--clients 5] [--bursts 2] [--burst-size 100]
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import time
from typing import Any

AGENT = "uav0"
ANSWER_WAIT_S = 60.0
"""Wall time a client waits for the answers of one burst."""


def _clients(node: Any, qos: Any) -> list[tuple[Any, Any]]:
    """(client, request factory) pairs, one per service used."""
    from hdrc3_interfaces.srv import FclClimb, FclYaw, PpclPtuLimits, SimTeleport

    def make(srv: Any, name: str, **fields: Any) -> tuple[Any, Any]:
        client = node.create_client(srv, name, qos_profile=qos)
        return client, lambda: srv.Request(**fields)

    return [
        make(FclClimb, f"/{AGENT}/fcl/climb", altitude=float("nan")),
        make(FclYaw, f"/{AGENT}/fcl/yaw", heading=0.5),
        make(PpclPtuLimits, f"/{AGENT}/ppcl/ptu_limits"),
        make(SimTeleport, "/world_sim/teleport", agent=AGENT, frame=99),
    ]


def client_main(args: argparse.Namespace) -> int:
    """One client process: bursts at the common start time; prints one JSON line."""
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.qos import qos_profile_services_default

    from hdrc3_base.ros_runtime import SERVICE_QOS, RosProcess, first_answer

    qos = qos_profile_services_default if args.client_qos == "default" else SERVICE_QOS
    with RosProcess(domain_id=args.domain_id, handle_signals=False) as process:
        node = Node(f"burst_client_{args.client}", context=process.context)
        executor = SingleThreadedExecutor(context=process.context)
        executor.add_node(node)
        clients = _clients(node, qos)

        def spin(done: Any, timeout: float) -> bool:
            wait_until = time.monotonic() + timeout
            while not done() and time.monotonic() < wait_until:
                executor.spin_once(timeout_sec=0.05)
            return bool(done())

        deadline = time.monotonic() + 60.0
        while not all(c.service_is_ready() for c, _ in clients):
            if time.monotonic() > deadline:
                print(json.dumps({"client": args.client, "error": "services not found"}))
                return 1
            executor.spin_once(timeout_sec=0.1)
        # one answer per client first (each is a refusal or a query: repeatable), so that the
        # burst measures queueing, not DDS discovery dropping the first answers to a new client
        for client, request in clients:
            if first_answer(client, request(), 30.0, spin) is None:
                print(json.dumps({"client": args.client, "error": "no first answer"}))
                return 1
        while time.time() < args.start:
            executor.spin_once(timeout_sec=min(0.1, max(0.0, args.start - time.time())))
        sent = answered = 0
        slowest = 0.0
        for _ in range(args.bursts):
            begin = time.monotonic()
            futures = []
            for i in range(args.burst_size):
                client, request = clients[i % len(clients)]
                futures.append(client.call_async(request()))
            sent += len(futures)
            wait_until = begin + ANSWER_WAIT_S
            while not all(f.done() for f in futures) and time.monotonic() < wait_until:
                executor.spin_once(timeout_sec=0.05)
            answered += sum(1 for f in futures if f.done() and f.result() is not None)
            slowest = max(slowest, time.monotonic() - begin)
        print(
            json.dumps(
                {"client": args.client, "sent": sent, "answered": answered, "slowest": slowest}
            ),
            flush=True,
        )
        node.destroy_node()
    return 0


def _spawn(cmd: list[str], env: dict[str, str]) -> subprocess.Popen[bytes]:
    return subprocess.Popen(
        cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True, env=env
    )


def _wait_line(proc: subprocess.Popen[bytes], needle: bytes, timeout: float) -> bool:
    assert proc.stdout is not None
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        line = proc.stdout.readline()
        if not line:
            return False
        if needle in line:
            return True
    return False


def run(args: argparse.Namespace) -> int:
    """Start the nodes and the clients; print the table; exit 0 if every call was answered."""
    env = dict(os.environ, ROS_DOMAIN_ID=str(args.domain_id), PYTHONUNBUFFERED="1")
    env.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    hdrc3 = os.path.join(os.path.dirname(sys.executable), "hdrc3")
    launch = _spawn(
        [hdrc3, "launch", "--agents", AGENT, "--nodes", "world_sim,platform_server"], env
    )
    results: list[dict[str, Any]] = []
    try:
        if not _wait_line(launch, b"READY", 120.0):
            print("the nodes did not start", flush=True)
            return 1
        start = time.time() + 8.0  # every client has found its services by then (loaded host)
        procs = [
            _spawn(
                [
                    sys.executable,
                    __file__,
                    "--client",
                    str(i),
                    "--start",
                    str(start),
                    "--bursts",
                    str(args.bursts),
                    "--burst-size",
                    str(args.burst_size),
                    "--client-qos",
                    args.client_qos,
                    "--domain-id",
                    str(args.domain_id),
                ],
                env,
            )
            for i in range(args.clients)
        ]
        for proc in procs:
            out, _ = proc.communicate(timeout=60.0 + args.bursts * (ANSWER_WAIT_S + 10.0))
            lines = [ln for ln in out.decode(errors="replace").splitlines() if ln.startswith("{")]
            results.append(json.loads(lines[-1]) if lines else {"error": out.decode()[-300:]})
    finally:
        os.killpg(launch.pid, signal.SIGINT)
        try:
            launch.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(launch.pid, signal.SIGKILL)
    print(
        f"service bursts: {args.clients} clients x {args.bursts} bursts x {args.burst_size} calls "
        f"(client QoS: {args.client_qos})",
        flush=True,
    )
    print(f"{'client':>6} {'sent':>6} {'answered':>9} {'lost':>5} {'slowest burst, s':>17}")
    sent = answered = 0
    for r in results:
        if "error" in r:
            print(f"{r.get('client', '?'):>6} error: {r['error']}", flush=True)
            continue
        sent, answered = sent + r["sent"], answered + r["answered"]
        print(
            f"{r['client']:>6} {r['sent']:>6} {r['answered']:>9} {r['sent'] - r['answered']:>5} "
            f"{r['slowest']:>17.2f}",
            flush=True,
        )
    share = 100.0 * answered / sent if sent else 0.0
    print(f"total: {answered} of {sent} answered ({share:.1f} %); target 100 %", flush=True)
    return 0 if sent == args.clients * args.bursts * args.burst_size and answered == sent else 1


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, default=5)
    parser.add_argument("--bursts", type=int, default=2)
    parser.add_argument("--burst-size", type=int, default=100)
    parser.add_argument("--client-qos", choices=("deep", "default"), default="deep")
    parser.add_argument("--domain-id", type=int, default=92)
    parser.add_argument("--client", type=int, default=-1, help=argparse.SUPPRESS)
    parser.add_argument("--start", type=float, default=0.0, help=argparse.SUPPRESS)
    args = parser.parse_args()
    return client_main(args) if args.client >= 0 else run(args)


if __name__ == "__main__":
    sys.exit(main())
