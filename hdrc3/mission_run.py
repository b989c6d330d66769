"""One TST mission flown on a running system: create, execute, follow until the root ends.

Shared by ``hdrc3 tst run`` and ``hdrc3 demo`` (which flies two missions, one per leg, on the
same launched system). The caller owns the :class:`RosProcess` and the :class:`TstClient`; this
module prints one line per node state change (through the client's ``on_status``), aborts the
mission on a timeout or Ctrl-C, and returns the outcome as a value.
"""

from __future__ import annotations

import csv
import enum
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rosgraph_msgs.msg import Clock

from hdrc3_base.ros_runtime import RosProcess
from hdrc3_base.stamps import stamp_s
from hdrc3_tst.check import CheckStatus
from hdrc3_tst.mission_client import Created, Reply, TstClient
from hdrc3_tst.model import NodeState

ABORT_WAIT_S = 30.0
LAST_STATUS_WAIT_S = 10.0
"""Wall seconds to wait, once the root has ended, for the other nodes' last statuses."""
SETTLE_S = 3.0
"""Sim seconds a launched run goes on after its root ended."""
SETTLE_WAIT_S = 30.0


class Outcome(enum.Enum):
    """How a mission run ended."""

    SUCCEEDED = "succeeded"
    FAILED = "failed"
    ABORTED = "aborted"
    INVALID = "invalid"
    """The text did not check (diagnostics printed)."""
    REFUSED = "refused"
    """A TST manager refused it or could not be reached."""


@dataclass(frozen=True)
class Flown:
    """The result of :func:`fly`: the outcome, every node's last status, a one-line verdict."""

    outcome: Outcome
    latest: dict[str, Any]
    verdict: str
    root: str = ""


def status_line(msg: Any) -> str:
    """One ``TstNodeStatus`` as a line: agent/node kind state, times, reason."""
    times = "" if math.isnan(msg.start) else f" TS {msg.start:.1f} s"
    times += "" if math.isnan(msg.end) else f" TE {msg.end:.1f} s"
    reason = f": {msg.reason}" if msg.reason else ""
    return f"{msg.agent}/{msg.node_id} {msg.kind} {msg.state}{times}{reason}"


def culprit(latest: dict[str, Any]) -> Any | None:
    """The failed node deepest in the tree (the one whose reason explains the others)."""
    failed = [m for m in latest.values() if m.state == NodeState.FAILED.value]
    parents = {m.parent.partition("/")[2] for m in failed}
    leaves = [m for m in failed if m.node_id not in parents]
    return leaves[0] if leaves else (failed[0] if failed else None)


def write_timeline(path: Path, latest: dict[str, Any]) -> None:
    """Every node's last status as CSV (node, agent, parent, kind, state, times, reason)."""
    with path.open("w", newline="", encoding="utf-8") as out:
        writer = csv.writer(out)
        writer.writerow(["node", "agent", "parent", "kind", "state", "start_s", "end_s", "reason"])
        for m in latest.values():
            writer.writerow(
                [m.node_id, m.agent, m.parent, m.kind, m.state, m.start, m.end, m.reason]
            )


def replies_ok(log: Callable[[str], None], replies: list[Reply] | tuple[Reply, ...]) -> bool:
    """Print each manager's reply; True if all accepted."""
    for reply in replies:
        word = "ok" if reply.ok else f"refused (code {reply.code})"
        log(f"{reply.agent}: {word} {reply.reason}".rstrip())
        for line in reply.conflict:
            log(f"  conflict: {line}")
    return all(r.ok for r in replies)


def _running(latest: dict[str, Any]) -> bool:
    """True while a node is reported running or paused."""
    busy = (NodeState.RUNNING.value, NodeState.PAUSED.value)
    return any(m.state in busy for m in latest.values())


def _created_ok(log: Callable[[str], None], created: Created) -> Outcome | None:
    for diag in created.check.diagnostics:
        log(str(diag))
    if created.check.status is not CheckStatus.OK:
        return Outcome.INVALID
    if created.fixed:
        log(f"bound: {', '.join(created.fixed)}")
    if not replies_ok(log, created.replies):
        return Outcome.REFUSED
    return None


def fly(
    process: RosProcess,
    client: TstClient,
    log: Callable[[str], None],
    mission: str,
    text: str,
    source: str,
    agents: tuple[str, ...],
    timeout: float,
) -> Flown:
    """Create ``text`` as ``mission`` on its agents' managers, run its root, wait for the end.

    A timeout (wall seconds) or Ctrl-C aborts the mission on every involved agent.
    """
    created = client.create(mission, text, source, agents)
    refused = _created_ok(log, created)
    if refused is not None:
        return Flown(refused, {}, f"mission {mission} {refused.value}")
    log(
        f"mission {mission} on {', '.join(created.involved)} "
        f"(abort: hdrc3 tst abort {mission} --agents {','.join(created.involved)})"
    )
    started = client.execute(mission, created.root_agent, created.root)
    if not replies_ok(log, [started]):
        return Flown(Outcome.REFUSED, {}, f"mission {mission}: the root was not started")

    def root_done() -> bool:
        return client.finished(mission, created.root) is not None

    if not process.spin_until(root_done, timeout):
        reason = "operator stop (Ctrl-C)" if process.stop_requested.is_set() else "timeout"
        log(f"aborting mission {mission}: {reason}")
        process.stop_requested.clear()
        client.abort(mission, created.involved, reason)
        process.spin_until(root_done, ABORT_WAIT_S)
    # other agents' last statuses may arrive after the root's (another publisher)
    process.spin_until(lambda: not _running(client.latest(mission)), LAST_STATUS_WAIT_S)
    latest = client.latest(mission)
    root = latest.get(created.root)
    if root is not None and root.state == NodeState.SUCCEEDED.value:
        verdict = f"mission {mission} succeeded in {root.end - root.start:.1f} s"
        return Flown(Outcome.SUCCEEDED, latest, verdict, created.root)
    if root is not None and root.state == NodeState.ABORTED.value:
        return Flown(Outcome.ABORTED, latest, f"MISSION ABORTED: {status_line(root)}", created.root)
    bad = culprit(latest)
    what = status_line(bad) if bad is not None else "the root did not end"
    return Flown(Outcome.FAILED, latest, f"MISSION FAILED: {what}", created.root)


def settle(process: RosProcess, client: TstClient) -> None:
    """Let SETTLE_S of sim time pass before the launch stops.

    The recording then holds the last node statuses (the recorder is another subscriber) and
    the aircraft's final state.
    """
    clock: list[float] = []

    def on_clock(msg: Any) -> None:
        clock.append(stamp_s(msg.clock))

    client.node.create_subscription(Clock, "/clock", on_clock, 10)
    if process.spin_until(lambda: bool(clock), SETTLE_WAIT_S):
        until = clock[-1] + SETTLE_S
        process.spin_until(lambda: clock[-1] >= until, SETTLE_WAIT_S)
