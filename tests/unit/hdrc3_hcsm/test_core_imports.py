"""The core must not import rclpy (only ros_transport.py may)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import hdrc3_hcsm

CORE = sorted(
    f"hdrc3_hcsm.{p.stem}"
    for p in Path(hdrc3_hcsm.__file__).parent.glob("*.py")
    if p.stem not in ("__init__", "ros_transport")
)


def test_core_modules_do_not_import_rclpy() -> None:
    code = (
        "import importlib, sys\n"
        f"for name in {CORE!r}: importlib.import_module(name)\n"
        "import hdrc3.cli.hcsm\n"
        "roots = ('rclpy', 'hdrc3_interfaces')\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in roots))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    )
    assert out.stdout.strip() == "[]"
    assert len(CORE) >= 15
