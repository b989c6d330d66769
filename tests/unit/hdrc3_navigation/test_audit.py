from __future__ import annotations

import numpy as np
import pytest

from hdrc3_control.path_segment import PathSegment
from hdrc3_navigation.audit import WorldAudit
from sim.world import World


@pytest.mark.parametrize(
    ("start", "end", "found"),
    [
        ((-60.0, 0.0, 15.0), (-60.0, 50.0, 15.0), set()),
        ((-40.0, 0.0, 15.0), (40.0, 0.0, 15.0), {"building wall"}),
        ((-40.0, 0.0, 28.0), (40.0, 0.0, 28.0), {"building wall"}),  # 3 m over the roof
        ((-60.0, 0.0, 3.0), (-60.0, 50.0, 3.0), {"terrain"}),
        ((30.0, -65.0, 20.0), (95.0, -65.0, 20.0), {"no-fly zone zone"}),
        ((-60.0, 60.0, 12.0), (-60.0, 90.0, 12.0), {"vegetation hedge"}),
    ],
)
def test_audit_finds_what_a_segment_touches(
    small_world: World,
    start,
    end,
    found: set[str],  # type: ignore[no-untyped-def]
) -> None:
    seg = PathSegment.straight(start, end, 5.0)
    assert {v.what for v in WorldAudit(small_world).check_segments([seg], 5.9)} == found


def test_extra_zones_and_flown_tracks(small_world: World) -> None:
    audit = WorldAudit(
        small_world, [("temp", ((-70.0, -10.0), (-50.0, -10.0), (-50.0, 10.0)), 0.0, 50.0)]
    )
    track = np.array([[-60.0, -30.0, 15.0], [-55.0, -5.0, 15.0], [-60.0, 30.0, 15.0]])
    assert [v.what for v in audit.check_points(track, 5.9)] == ["no-fly zone temp"]
