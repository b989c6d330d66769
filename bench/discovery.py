"""How long a new ROS process takes to hear an existing one: DDS discovery on loopback (issue 21).

A restarted node (``bench/faults.py``'s kills) is useful only once it and its peers have found
each other. This measures that alone, without the flying stack: one publisher of a latched
message (reliable, transient local) and ``--idle`` idle participants (default 6, the processes
of a one-aircraft launch) run in their own ROS domain on loopback; then ``--probes`` times a
new process creates a node with a subscription and records how long after the node's creation
the message arrives (both directions of discovery: the publisher must find the new reader, the
reader the publisher). Each configuration gets fresh participants:

* ``fast dds defaults``: a profile with Fast DDS's own discovery timing (an announcement every
  3 s, 5 initial announcements 100 ms apart);
* ``hdrc3 profile``: ``hdrc3_base/dds_discovery.xml``, which every hdrc3 process uses unless the
  user names a profile file (an announcement every 0.5 s, 10 initial ones 50 ms apart).

Printed per configuration: mean, median, 90th percentile and maximum, in seconds of wall time.

Run: ``.venv/bin/python bench/discovery.py [--probes 20] [--idle 6] [--domain-id 88]``
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from hdrc3_base.ros_env import PROFILES_VARS, discovery_profile

TOPIC = "/discovery_probe"
PROBE_LIMIT_S = 15.0
SETTLE_S = 4.0
"""The publisher and the idle participants find each other before the first probe."""
FAST_DDS_DEFAULTS = """<?xml version="1.0" encoding="UTF-8" ?>
<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <participant profile_name="fast_dds_defaults" is_default_profile="true">
    <rtps><builtin><discovery_config>
      <leaseDuration><sec>20</sec><nanosec>0</nanosec></leaseDuration>
      <leaseAnnouncement><sec>3</sec><nanosec>0</nanosec></leaseAnnouncement>
      <initialAnnouncements><count>5</count>
        <period><sec>0</sec><nanosec>100000000</nanosec></period></initialAnnouncements>
    </discovery_config></builtin></rtps>
  </participant>
</profiles>
"""


def role(name: str) -> int:
    """Run one participant: ``pub``, ``idle`` or ``probe`` (prints its delay, or ``none``)."""
    import rclpy
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    from std_msgs.msg import String

    qos = QoSProfile(
        depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
    )
    context = Context()
    rclpy.init(context=context)
    executor = SingleThreadedExecutor(context=context)
    if name == "probe":
        start = time.monotonic()
        node = Node(f"probe_{os.getpid()}", context=context)
        heard: list[float] = []
        node.create_subscription(String, TOPIC, lambda _msg: heard.append(time.monotonic()), qos)
        executor.add_node(node)
        while not heard and time.monotonic() - start < PROBE_LIMIT_S:
            executor.spin_once(timeout_sec=0.02)
        print(f"{heard[0] - start:.3f}" if heard else "none", flush=True)
        return 0
    node = Node(f"{name}_{os.getpid()}", context=context)
    if name == "pub":
        node.create_publisher(String, TOPIC, qos).publish(String(data="here"))
    executor.add_node(node)
    while True:  # until the bench terminates it
        executor.spin_once(timeout_sec=1.0)


def measure(label: str, profile: str, args: argparse.Namespace) -> list[float | None]:
    """Delays of ``args.probes`` new processes with ``profile`` for every participant."""
    env = {k: v for k, v in os.environ.items() if k not in PROFILES_VARS}
    env.update(
        {
            PROFILES_VARS[0]: profile,
            "ROS_DOMAIN_ID": str(args.domain_id),
            "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST",
        }
    )
    me = [sys.executable, str(Path(__file__).resolve()), "--role"]
    standing = [subprocess.Popen([*me, "pub"], env=env)]
    standing += [subprocess.Popen([*me, "idle"], env=env) for _ in range(args.idle)]
    delays: list[float | None] = []
    try:
        time.sleep(SETTLE_S)
        for _ in range(args.probes):
            out = subprocess.run([*me, "probe"], env=env, capture_output=True, text=True)
            line = out.stdout.strip().splitlines()[-1] if out.stdout.strip() else "none"
            delays.append(None if line == "none" else float(line))
    finally:
        for process in standing:
            process.terminate()
        for process in standing:
            process.wait(10)
    heard = sorted(d for d in delays if d is not None)
    missing = len(delays) - len(heard)
    if heard:
        p90 = heard[min(len(heard) - 1, round(0.9 * (len(heard) - 1)))]
        print(
            f"{label:18} {len(heard)}/{len(delays)} heard: mean {statistics.fmean(heard):.2f} s, "
            f"median {statistics.median(heard):.2f} s, p90 {p90:.2f} s, max {heard[-1]:.2f} s"
            + (f", {missing} not within {PROBE_LIMIT_S:g} s" if missing else ""),
            flush=True,
        )
    else:
        print(f"{label:18} none of {len(delays)} heard within {PROBE_LIMIT_S:g} s", flush=True)
    return delays


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--probes", type=int, default=20)
    parser.add_argument("--idle", type=int, default=6)
    parser.add_argument("--domain-id", type=int, default=88)
    parser.add_argument("--role", choices=("pub", "idle", "probe"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.role:
        return role(args.role)
    print(
        f"new process -> first message of an existing publisher, {args.idle} idle participants, "
        f"{args.probes} probes each (ROS domain {args.domain_id}, loopback)",
        flush=True,
    )
    with tempfile.TemporaryDirectory() as tmp:
        defaults = Path(tmp, "fast_dds_defaults.xml")
        defaults.write_text(FAST_DDS_DEFAULTS, encoding="utf-8")
        measure("fast dds defaults", str(defaults), args)
    measure("hdrc3 profile", discovery_profile(), args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
