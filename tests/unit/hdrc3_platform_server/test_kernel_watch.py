"""Deaths of an agent's kernels in the launcher's snapshots, each reported once."""

from __future__ import annotations

import pytest

from hdrc3_platform_server.kernel_watch import KernelExit, KernelWatch, ProcessReport

PFC_LOST = "control kernel (PFC) exited (code -9): the command was lost"
PPC_LOST = "perception kernel (PPC) exited (code 1): the command was lost"


def pfc(alive: bool, restarts: int, node: str = "/uav0/control_kernel") -> ProcessReport:
    return ProcessReport(node, alive, restarts, 0 if alive else -9)


@pytest.mark.parametrize(
    ("snapshots", "expected"),
    [
        ([[pfc(True, 0)], [pfc(True, 0)]], [[], []]),
        # kill -9: back-off, then the restart; one report, at the exit
        ([[pfc(True, 0)], [pfc(False, 0)], [pfc(True, 1)], [pfc(True, 1)]],
         [[], [KernelExit("PFC", PFC_LOST)], [], []]),
        # the back-off snapshot was missed: the restart count tells
        ([[pfc(True, 0)], [pfc(True, 1)]],
         [[], [KernelExit("PFC", "control kernel (PFC) restarted: the command was lost")]]),
        # a server (re)started after the kernel's crash: not news
        ([[pfc(False, 2)], [pfc(True, 3)]], [[], []]),
        # another agent's kernel, the world simulator: not this server's
        ([[pfc(True, 0, "/uav1/control_kernel")], [pfc(False, 0, "/uav1/control_kernel")]],
         [[], []]),
        ([[pfc(True, 0, "/uav0/platform_server")], [pfc(False, 0, "/uav0/platform_server")]],
         [[], []]),
        ([[ProcessReport("/uav0/perception_kernel", True, 0, 0)],
          [ProcessReport("/uav0/perception_kernel", False, 0, 1)]],
         [[], [KernelExit("PPC", PPC_LOST)]]),
    ],
)  # fmt: skip
def test_each_death_is_reported_once(
    snapshots: list[list[ProcessReport]], expected: list[list[KernelExit]]
) -> None:
    watch = KernelWatch("uav0")
    assert [watch.update(s) for s in snapshots] == expected
