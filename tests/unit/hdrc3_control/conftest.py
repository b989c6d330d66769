"""Closed-loop fixtures: the in-process harness of bench/control_sim.py (the sim is the world)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import pytest

_HARNESS = Path(__file__).resolve().parents[3] / "bench" / "control_sim.py"


def _load() -> ModuleType:
    name = "hdrc3_control_bench_harness"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, _HARNESS)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses resolve annotations through sys.modules
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def harness() -> ModuleType:
    """bench/control_sim.py as a module: SimFlight, takeoff, hover, fly_path, brake, land."""
    return _load()
