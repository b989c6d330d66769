"""`hdrc3 workspace` + colcon: the packages build, and a node starts the way `ros2 run` finds it.

``ros2 run PKG EXE`` looks ``PKG`` up in the ament index (``AMENT_PREFIX_PATH``, set by sourcing
the workspace's ``install/setup.sh``) and runs ``<prefix>/lib/PKG/EXE``; ros2cli itself has no
PyPI wheel, so the test does those two steps. colcon and its ROS extensions are from PyPI.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.integration.conftest import HDRC3, Child

pytestmark = [pytest.mark.ros, pytest.mark.slow]

BIN = Path(sys.executable).parent
BUILD_S = 600.0


def _sourced(workspace: Path, command: str, *args: str) -> subprocess.CompletedProcess[str]:
    """Run ``command`` (``$0``) with ``args`` in a shell that sourced the workspace.

    From the workspace's directory: ``python -c`` imports from the working directory first,
    which must not be the source checkout.
    """
    script = f'. "{workspace}/install/setup.sh" && exec "$0" "$@"'
    return subprocess.run(
        ["sh", "-c", script, command, *args],
        cwd=workspace, capture_output=True, text=True, timeout=120,
    )  # fmt: skip


@pytest.mark.timeout(900)
def test_colcon_builds_the_control_kernel_and_it_starts_as_ros2_run_would(
    tmp_path: Path, ros_domain: int
) -> None:
    ws = tmp_path / "ws"
    made = subprocess.run([HDRC3, "workspace", str(ws)], capture_output=True, text=True)
    assert made.returncode == 0, made.stderr
    assert f"{ws / 'src' / 'hdrc3_control'}: control_kernel, perception_kernel" in made.stdout
    env = dict(os.environ, PATH=f"{BIN}{os.pathsep}{os.environ['PATH']}")
    build = subprocess.run(
        [str(BIN / "colcon"), "build", "--packages-up-to", "hdrc3_control"],
        cwd=ws, env=env, capture_output=True, text=True, timeout=BUILD_S,
    )  # fmt: skip
    assert build.returncode == 0, build.stdout[-3000:] + build.stderr[-3000:]

    # what ros2 run does: the package's prefix from the ament index, then lib/PKG/EXE
    lookup = "from ament_index_python.packages import get_package_prefix as p; print(p('{}'))"
    found = _sourced(ws, sys.executable, "-c", lookup.format("hdrc3_control"))
    assert found.returncode == 0, found.stderr
    prefix = Path(found.stdout.strip())
    assert prefix == ws / "install" / "hdrc3_control"
    exe = prefix / "lib" / "hdrc3_control" / "control_kernel"
    assert exe.is_file() and os.access(exe, os.X_OK)
    # the workspace's copy of the package, not the venv's
    where = _sourced(ws, sys.executable, "-c", "import hdrc3_control as p; print(p.__file__)")
    assert where.stdout.startswith(str(ws / "install" / "hdrc3_control")), where

    refused = _sourced(ws, str(exe), "--ros-args", "-p", "world:=nope")
    assert refused.returncode == 2, refused
    assert "unknown world 'nope'" in refused.stderr
    node = Child(
        ["--ros-args", "-p", "world:=revinge", "-p", f"checkpoint:={tmp_path / 'uav0.warm'}",
         "-r", "__ns:=/uav0"],
        prefix=("sh", "-c", f'. "{ws}/install/setup.sh" && exec "$0" "$@"'),
        program=str(exe),
    )  # fmt: skip
    try:
        node.wait_for_line("cold start: ", timeout=120)
        assert node.interrupt() == 0, node.lines
    finally:
        node.kill()
