"""Delegation across hosts (issue 17's "Done when"): three agents in network namespaces.

Each agent is a host of its own: a network namespace the test creates, its own simulated RMAX,
control kernel, Platform Server, PPC, TST manager and path planner on loopback there, and its
gateway, whose speech acts alone travel over the test's bridge (another ROS domain, discovery
widened to the subnet inside these namespaces only). The ground operator runs ``hdrc3 delegate``
in a fourth namespace. First the mission is delegated to any two of the three and flown; then it
is delegated again and, mid-delegation, one agent's link is cut: the protocol times out on it,
the other two take the mission, and the cut agent never commits, even after its link is back
and held acts arrive.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

pytestmark = [pytest.mark.ros, pytest.mark.slow, pytest.mark.flight]

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tst"
AGENTS = ("uav0", "uav1", "uav2")
NODES = "world_sim,control_kernel,platform_server,perception_kernel,tst_manager,path_planner"


@pytest.fixture
def hosts(
    hdrc3_cli: Callable[..., Any], ros_domain: int, tmp_path: Path
) -> Iterator[tuple[Any, Callable[..., Any], dict[str, Any], Path, int]]:
    from hdrc3_delegation.keystore import write_keystore
    from tests.integration import netns
    from tests.integration.conftest import Child

    why = netns.available()
    if why:
        pytest.skip(why)
    keystore = tmp_path / "keys.toml"
    write_keystore(keystore, ("gcs", *AGENTS))
    acl_domain = (ros_domain + 50) % 100  # inside the test's namespaces only: no other test there
    children: list[Any] = []

    def run_in(
        party: str, *args: str, discovery: str = "LOCALHOST", domain: int = ros_domain
    ) -> Any:
        env = {"ROS_DOMAIN_ID": str(domain), "ROS_AUTOMATIC_DISCOVERY_RANGE": discovery}
        child = Child(list(args), prefix=network.prefix(party), env=env)
        children.append(child)
        return child

    with netns.Network(("gcs", *AGENTS)) as network:
        try:
            launches = {
                agent: run_in(
                    agent,
                    "launch",
                    "--agents",
                    agent,
                    "--world",
                    "revinge",
                    "--speed",
                    "max",
                    "--nodes",
                    NODES,
                    "--keystore",
                    str(keystore),
                    "--seed",
                    "2",
                    "--acl-domain",
                    str(acl_domain),
                    "--acl-discovery",
                    "SUBNET",
                )
                for agent in AGENTS
            }
            for launch in launches.values():
                launch.wait_for_line("READY", timeout=240)
            for agent in AGENTS:
                rc = run_in(agent, "rc", agent, "--mode", "autonomous", "--engine", "on")
                assert rc.finish(timeout=60) == 0, rc.lines
            yield network, run_in, launches, keystore, acl_domain
        finally:
            for child in children:
                if child.proc.poll() is None:
                    child.proc.send_signal(2)
            for child in children:
                try:
                    child.finish(timeout=30)
                except AssertionError:
                    child.kill()


def delegate(run_in: Callable[..., Any], keystore: Path, acl_domain: int, mission: str) -> Any:
    return run_in(
        "gcs", "delegate", str(EXAMPLES / "delegate_two_pads.tst"), "--to", "any",
        "--max-agents", "2", "--keystore", str(keystore), "--mission", mission,
        "--answer-s", "8", "--timeout", "400",
        discovery="SUBNET", domain=acl_domain,
    )  # fmt: skip


@pytest.mark.timeout(1200)
def test_three_hosts_delegate_fly_and_survive_a_partition(hosts: Any) -> None:
    network, run_in, launches, keystore, acl_domain = hosts

    first = delegate(run_in, keystore, acl_domain, "hosts")
    assert first.finish(timeout=400) == 0, "\n".join(first.lines)
    text = "\n".join(first.lines)
    assert "mission hosts delegated and done" in text
    won = [line for line in first.lines if line.startswith("won ")]
    assert len(won) == 2 and len({line.rsplit(": ", 1)[1] for line in won}) == 2, won

    second = delegate(run_in, keystore, acl_domain, "cut")
    second.wait_for_line("cfp a1, a2 ->", timeout=120)
    victim = "uav0"
    network.cut(victim)
    cut_at = time.monotonic()
    assert second.finish(timeout=400) == 0, "\n".join(second.lines)
    text = "\n".join(second.lines)
    assert "mission cut delegated and done" in text, text
    assert (
        f"{victim} did not answer by reply-by: excluded" in text
        or f"{victim} dropped: did not agree by reply-by" in text
    ), text
    assert not any(line.startswith(f"{victim}: ") for line in second.lines), text
    network.heal(victim)
    launches[victim].poll_output(max(0.0, 20.0 - (time.monotonic() - cut_at)))
    victim_log = "\n".join(launches[victim].lines)
    assert "cut: committed" not in victim_log, victim_log[-3000:]
