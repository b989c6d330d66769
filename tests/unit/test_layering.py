"""The package layers: a package imports only packages of lower layers, never the CLI package.

Read from the source with ``ast`` (``hdrc3.ros_workspace.module_imports``: every import
statement, also those inside functions), so a lazy import cannot hide an upward dependency.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3.ros_workspace import module_imports

ROOT = Path(__file__).resolve().parents[2]
LAYERS: dict[str, int] = {
    "hdrc3_base": 0,
    "hdrc3_interfaces": 0,  # generated messages, importable by every node adapter
    "hdrc3_hcsm": 1,
    "hdrc3_dyknow": 1,
    "sim": 1,
    "hdrc3_control": 2,
    "hdrc3_platform_server": 3,
    "hdrc3_navigation": 3,  # path planning needs the PFC's segment type and limits (layer 2)
    "hdrc3_perception": 4,  # Algorithm 4 (§11.1.1); laser maps (§11.2) are the GIS's map type
    "hdrc3_deliberative": 4,
    "hdrc3_tst": 5,  # executors call the Platform Server; goal nodes use TALplanner's domains
    "hdrc3_delegation": 6,  # contractors price TST nodes and hand them to the TST manager
    "hdrc3": 9,  # the CLI, launcher and demo: the top, imported by nobody
}
"""Layer of each top-level package; the architecture of ../shared/DESIGN.md, bottom up."""
SIM_DATA = frozenset(
    {
        "sim.world",
        "sim.world_loader",
        "sim.world_generator",
        "sim.landing_pattern",
        "sim.airframe",
        "sim.geodesy",
    }
)
"""The simulator modules the autonomy stack may use: world files are data (terrain, origin),
and so is the landing pad's printed pattern (the pose estimator knows it) and the payload's
mounting calibration (``sim.airframe``), and so is the geodesy of a world's origin
(``sim.geodesy``: the origin's type and its local ENU frame, the control kernel's WGS84 output);
the generator writes such files (``hdrc3 world generate``)."""
SIM_HARNESSES = frozenset({"hdrc3_control.kernel_harness"})
"""Stack modules that couple a kernel with the simulator in one process (tests and benches)."""


def module_name(path: Path) -> str:
    """``hdrc3_control/kernel_harness.py`` -> ``hdrc3_control.kernel_harness``."""
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def violations(package: str) -> list[str]:
    """Every import in ``package`` that breaks the layering, as ``file:line imports module``."""
    found = []
    for path in sorted((ROOT / package).rglob("*.py")):
        importer = module_name(path)
        for line, module in module_imports(path):
            target = module.split(".")[0]
            if target == package or target not in LAYERS:
                continue
            allowed = LAYERS[target] < LAYERS[package]
            if target == "sim" and package != "sim":
                allowed = module in SIM_DATA or importer in SIM_HARNESSES
            if not allowed:
                found.append(f"{path.relative_to(ROOT)}:{line} imports {module}")
    return found


@pytest.mark.parametrize("package", sorted(p for p in LAYERS if p != "hdrc3_interfaces"))
def test_no_import_goes_up_or_sideways(package: str) -> None:
    assert (ROOT / package).is_dir()
    assert violations(package) == []


def test_every_package_has_a_layer() -> None:
    packages = {p.parent.name for p in ROOT.glob("*/__init__.py")} - {"tests", "bench"}
    assert packages <= set(LAYERS), packages - set(LAYERS)


@pytest.mark.parametrize(
    ("package", "source", "found"),
    [
        ("hdrc3_hcsm", "from hdrc3.cli import main\n", "imports hdrc3.cli"),
        (
            "hdrc3_control",
            "import hdrc3_platform_server.codes\n",
            "imports hdrc3_platform_server.codes",
        ),
        ("hdrc3_dyknow", "def f():\n    from sim import world\n", "imports sim"),
        ("hdrc3_control", "from sim.truth_state import TruthState\n", "imports sim.truth_state"),
        ("hdrc3_dyknow", "from hdrc3_hcsm.event import WireEvent\n", "imports hdrc3_hcsm.event"),
    ],
)
def test_the_check_finds_a_planted_violation(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, package: str, source: str, found: str
) -> None:
    (tmp_path / package).mkdir()
    (tmp_path / package / "planted.py").write_text(source)
    monkeypatch.setattr(f"{__name__}.ROOT", tmp_path)
    assert [v.split(" ", 1)[1] for v in violations(package)] == [found]
