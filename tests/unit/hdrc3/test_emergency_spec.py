"""The flagship's TALF mission file: read into a mission, or refused before anything flies."""

from __future__ import annotations

from pathlib import Path

import pytest

from hdrc3.cli.demo import MISSIONS
from hdrc3.cli.main import main
from hdrc3.emergency_spec import load_mission
from hdrc3_deliberative.talf_diagnostics import TalfStatus

HEADER = """world revinge
agents uav0, uav1
area Region = polygon((-170, -185), (-130, -185), (-130, -145), (-170, -145))
point OverDepot = supply_depot at 20
point Depot2 = (-160, 100, 20)
point Field = west_field at 0
"""
GOOD = """mission m:
  [TS, TE] with a, b, c, d do (
    [a, b] scan-with-all-uavs(Region, 4) ;
    [c, d] deliver-supplies(OverDepot, OverDepot, Field, 7)
  ) where TS = 0
"""


@pytest.mark.parametrize("name", ["emergency.talf", "emergency_short.talf"])
def test_the_shipped_missions_load(name: str) -> None:
    spec = load_mission(Path(str(MISSIONS.joinpath(name))))
    assert spec.status is TalfStatus.OK, spec.diagnostics
    assert spec.mission is not None
    assert spec.mission.agents == ("uav0", "uav1")
    assert spec.mission.depot == "supply_depot"


def test_the_region_speeds_and_depot_come_from_the_library_actions(tmp_path: Path) -> None:
    path = tmp_path / "m.talf"
    path.write_text(HEADER + GOOD)
    spec = load_mission(path, ("food",))
    assert spec.mission is not None
    m = spec.mission
    assert m.region == ((-170, -185), (-130, -185), (-130, -145), (-170, -145))
    assert (m.scan_speed, m.cruise_speed, m.cruise_altitude) == (4.0, 7.0, 20.0)
    assert (m.world, m.depot, m.kits) == ("revinge", "supply_depot", ("food",))


@pytest.mark.parametrize(
    ("body", "status", "message"),
    [
        ("mission m: [t, t2]", TalfStatus.SYNTAX_ERROR, "m.talf:7:19"),
        ("mission m: [t, t2] scan-everything(Region)", TalfStatus.INVALID, "unknown action"),
        (
            "mission m: [t, t2] scan-with-all-uavs(Region, 4)",
            TalfStatus.INVALID,
            "must use scan-with-all-uavs (leg I) and deliver-supplies (leg II)",
        ),
        (
            GOOD.replace("deliver-supplies(OverDepot", "deliver-supplies(Depot2"),
            TalfStatus.INVALID,
            "the depot point must be a world place",
        ),
    ],
)
def test_a_bad_mission_file_is_refused_with_its_reason(
    tmp_path: Path, body: str, status: TalfStatus, message: str
) -> None:
    path = tmp_path / "m.talf"
    path.write_text(HEADER + body)
    spec = load_mission(path)
    assert spec.mission is None
    assert spec.status is status
    assert any(message in str(d) for d in spec.diagnostics), spec.diagnostics


def test_a_fleet_without_cameras_cannot_fly_leg_one(tmp_path: Path) -> None:
    path = tmp_path / "m.talf"
    path.write_text(HEADER + GOOD)
    hook_only = frozenset({"flight", "hook"})
    spec = load_mission(path, capabilities={"uav0": hook_only, "uav1": hook_only})
    assert spec.status is TalfStatus.UNSATISFIABLE
    assert any("camera" in str(d) for d in spec.diagnostics)


def test_the_demo_refuses_a_bad_file_before_anything_flies(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "m.talf"
    path.write_text(HEADER + "mission m: [t, t2] hover(x)")
    assert main(["demo", "--mission", str(path), "--out", str(tmp_path / "out")]) == 4
    captured = capsys.readouterr()
    assert "m.talf:7:26: error T101: unbound variable 'x'" in captured.out
    assert "nothing flew" in captured.err
    assert not (tmp_path / "out" / "run.mcap").exists()
