"""The operator's emergency-services mission as a TALF file (chapter sections 9.4 and 11.1).

The flagship flies from one TALF mission file (``examples/talf/emergency_services.talf``). It is
loaded and checked like any TALF file (syntax, names, arities; with ``capabilities``, whether some
AV has what each action needs), so bad input is refused with FILE:LINE:COLUMN before anything
flies. The mission's two library actions then say what to fly:

- ``scan-with-all-uavs(Region, speed)``: leg I scans that area at that speed with the file's AVs;
- ``deliver-supplies(depot, above, place, speed)``: leg II fetches boxes at the depot point's
  place (a ``point X = <depot> at h`` of the world) and flies at that speed. Where the boxes go
  is what leg I finds: the places the saliency map confirms replace the file's ``place``.

Pure: no rclpy.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

from hdrc3.emergency_mission import EmergencyMission
from hdrc3_base.errors import ConfigError
from hdrc3_deliberative.mission_syntax import AreaDecl, Name, Number, PointDecl, WorldDecl
from hdrc3_deliberative.talf_diagnostics import TalfDiagnostic, TalfStatus
from hdrc3_deliberative.talf_load import load_file
from hdrc3_deliberative.talf_syntax import ActionTerm, TalfFile
from hdrc3_tst.actions import ACTIONS

_D = TypeVar("_D", AreaDecl, PointDecl)
SCAN = "scan-with-all-uavs"
DELIVER = "deliver-supplies"


@dataclass(frozen=True)
class SpecResult:
    """The mission read from the file, or why it cannot fly (diagnostics with positions)."""

    status: TalfStatus
    mission: EmergencyMission | None
    diagnostics: tuple[TalfDiagnostic | str, ...] = ()


def _term(tree: TalfFile, name: str) -> ActionTerm | None:
    for mission in tree.missions():
        for cact in mission.body.walk():
            task = cact.task
            if isinstance(task, ActionTerm) and task.name == name:
                return task
    return None


def _number(term: ActionTerm, index: int) -> float:
    arg = term.args[index]
    if not isinstance(arg, Number):
        raise ConfigError(f"{term.pos}: {term.name} argument {index + 1} must be a number")
    return float(arg.value)


def _declared(tree: TalfFile, term: ActionTerm, index: int, kind: type[_D]) -> _D:
    arg = term.args[index]
    for item in tree.items:
        if isinstance(item, kind) and isinstance(arg, Name) and item.name == arg.id:
            return item
    what = kind.__name__.removesuffix("Decl").lower()
    raise ConfigError(f"{term.pos}: {term.name} argument {index + 1} must name an {what}")


def mission_from_tree(tree: TalfFile, kits: tuple[str, ...]) -> EmergencyMission:
    """The flagship's mission from a checked TALF file (ConfigError with the position)."""
    scan = _term(tree, SCAN)
    deliver = _term(tree, DELIVER)
    if scan is None or deliver is None:
        raise ConfigError(f"the mission must use {SCAN} (leg I) and {DELIVER} (leg II)")
    worlds = [i.name for i in tree.items if isinstance(i, WorldDecl)]
    if not worlds:
        raise ConfigError("the file declares no world")
    region = _declared(tree, scan, 0, AreaDecl)
    depot = _declared(tree, deliver, 0, PointDecl)
    assert isinstance(region, AreaDecl) and isinstance(depot, PointDecl)
    if depot.place is None:
        raise ConfigError(
            f"{depot.pos}: the depot point must be a world place: `point X = depot at h`"
        )
    return EmergencyMission(
        worlds[0],
        tree.agents(),
        region.vertices,
        scan_speed=_number(scan, 1),
        cruise_speed=_number(deliver, 3),
        cruise_altitude=depot.altitude,
        kits=kits,
        depot=depot.place,
    )


def load_mission(
    path: Path,
    kits: tuple[str, ...] = ("food", "medicine"),
    capabilities: Mapping[str, frozenset[str]] | None = None,
) -> SpecResult:
    """Load, check and read the mission file (never raises on bad input)."""
    loaded = load_file(path, ACTIONS, capabilities)
    if loaded.status is not TalfStatus.OK or loaded.tree is None:
        return SpecResult(loaded.status, None, loaded.diagnostics)
    try:
        return SpecResult(TalfStatus.OK, mission_from_tree(loaded.tree, kits))
    except ConfigError as exc:
        return SpecResult(TalfStatus.INVALID, None, (str(exc),))
