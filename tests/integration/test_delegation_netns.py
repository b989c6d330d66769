"""Delegation across hosts (issue 17's "Done when"): three agents in network namespaces.

Each agent is a host of its own: a network namespace the test creates, its own simulated RMAX,
control kernel, Platform Server, PPC, TST manager and path planner on loopback there, and its
gateway, whose speech acts alone travel over the test's bridge (another ROS domain, discovery
widened to the subnet inside these namespaces only). The ground operator runs ``hdrc3 delegate``
in a fourth namespace. uav2 has no camera. First Example 6.1 (every agent open) is delegated to
any two of the three and flown: uav2 refuses the scans, two aircraft scan concurrently, one flies
to Dest4. Then a short mission is delegated and, mid-delegation, uav0's link is cut: the protocol
times out on it, uav1 and uav2 take the mission, and uav0 never commits, even after its link is
back and held acts arrive.
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
NO_CAMERA = "flight+ptu+hook"


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
                    *(["--capabilities", f"{agent}={NO_CAMERA}"] if agent == "uav2" else []),
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


def delegate(
    run_in: Callable[..., Any], keystore: Path, acl_domain: int, mission: str, file: str
) -> Any:
    return run_in(
        "gcs", "delegate", str(EXAMPLES / file), "--to", "any",
        "--max-agents", "2", "--keystore", str(keystore), "--mission", mission,
        "--answer-s", "8", "--timeout", "900",
        discovery="SUBNET", domain=acl_domain,
    )  # fmt: skip


@pytest.mark.timeout(1800)
def test_three_hosts_delegate_fly_and_survive_a_partition(hosts: Any) -> None:
    network, run_in, launches, keystore, acl_domain = hosts

    first = delegate(run_in, keystore, acl_domain, "hosts", "example_6_1_delegated.tst")
    assert first.finish(timeout=900) == 0, "\n".join(first.lines)
    text = "\n".join(first.lines)
    assert "mission hosts delegated and done" in text
    assert "refuse uav2: uav2 has no camera for scan-area (tau2)" in text
    won = {
        line.split(": ")[0][4:]: line.rsplit(": ", 1)[1]
        for line in first.lines
        if line.startswith("won ")
    }
    assert set(won) == {"tau2", "tau3", "tau4"} and won["tau2"] != won["tau3"], won
    assert {won["tau2"], won["tau3"]} == {"uav0", "uav1"}
    for node in ("tau2", "tau3", "tau4"):
        assert f"{won[node]}: {node} succeeded" in text, text

    second = delegate(run_in, keystore, acl_domain, "cut", "delegate_two_pads.tst")
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
