from __future__ import annotations

import array
import math
from typing import Any

import numpy as np
import pytest

from hdrc3_interfaces.msg import ElevationMap as ElevationMapMsg
from hdrc3_navigation.elevation_map import MAX_CELLS, ElevationMap
from hdrc3_navigation.gis import Gis, Zone
from hdrc3_navigation.messages import (
    elevation_map_from_msg,
    elevation_map_to_msg,
    world_from_msg,
    world_to_msg,
)
from hdrc3_navigation.runtime_world import RuntimeWorld
from sim.world import World

NAN = math.nan


def sample_map(returns: bool = True) -> ElevationMap:
    heights = np.arange(12, dtype=np.float64).reshape(3, 4) * 0.25 - 1.0  # exact in float32
    heights[1, 2] = NAN
    counts = np.arange(12, dtype=np.int64).reshape(3, 4) if returns else np.zeros((0, 0), int)
    return ElevationMap("scan 1", -12.5, 40.0, 0.5, heights, counts)


@pytest.mark.parametrize("returns", [True, False])
def test_elevation_map_round_trip(returns: bool) -> None:
    m = sample_map(returns)
    msg = elevation_map_to_msg(m)
    assert (msg.rows, msg.columns, len(msg.heights)) == (3, 4, 12)
    assert msg.heights.typecode == "f" and msg.returns.typecode == "I"
    assert msg.heights[1] == pytest.approx(-0.75)  # row-major: row 0 west to east first
    assert len(msg.returns) == (12 if returns else 0)
    back = elevation_map_from_msg(msg)
    assert isinstance(back, ElevationMap), back
    assert (back.name, back.east0, back.north0, back.resolution) == ("scan 1", -12.5, 40.0, 0.5)
    np.testing.assert_array_equal(back.heights, m.heights)  # NaN in the same cells
    np.testing.assert_array_equal(back.returns, m.returns)
    assert back.returns.shape == ((3, 4) if returns else (0, 0))


def good_fields() -> dict[str, Any]:
    return {
        "name": "scan",
        "east0": 0.0,
        "north0": 0.0,
        "resolution": 1.0,
        "rows": 2,
        "columns": 3,
        "heights": [0.0] * 6,
        "returns": [1] * 6,
    }


MALFORMED: list[tuple[dict[str, Any], str]] = [
    ({"heights": [0.0] * 5}, "5 heights for 2 rows x 3 columns (6 expected)"),
    ({"heights": []}, "0 heights"),
    ({"returns": [1] * 4}, "4 returns, expected 0 or 6"),
    ({"rows": 0, "heights": []}, "0 rows x 3 columns, both must be > 0"),
    ({"columns": 0, "heights": []}, "both must be > 0"),
    ({"rows": 4_000, "columns": 4_000, "heights": []}, f"more than {MAX_CELLS}"),
    ({"resolution": 0.0}, "resolution must be within"),
    ({"resolution": NAN}, "resolution must be within"),
    ({"resolution": -1.0}, "resolution must be within"),
    ({"east0": math.inf}, "origin must be finite"),
    ({"name": ""}, "name must be 1-64 printable characters"),
    ({"heights": [0.0, math.inf, 0.0, 0.0, 0.0, 0.0]}, "finite or NaN"),
]


@pytest.mark.parametrize(("change", "reason"), MALFORMED)
def test_malformed_elevation_map_messages_give_a_reason(
    change: dict[str, Any], reason: str
) -> None:
    fields = {**good_fields(), **change}
    msg = ElevationMapMsg(**fields)
    got = elevation_map_from_msg(msg)
    assert isinstance(got, str) and reason in got, got
    assert isinstance(elevation_map_from_msg(ElevationMapMsg(**good_fields())), ElevationMap)


class Loose:
    """Not a message: whatever a caller may hand over."""

    name = "x"
    rows = "two"
    columns = 3
    heights = array.array("f", [0.0] * 6)
    returns = array.array("I")


@pytest.mark.parametrize("msg", [Loose(), None, object()])
def test_elevation_map_from_anything_never_raises(msg: Any) -> None:
    assert isinstance(elevation_map_from_msg(msg), str)


def test_gis_state_carries_the_elevation_map_names(small_world: World) -> None:
    gis = Gis(small_world)
    gis.add_obstacle("crane", ((0.0, 0.0), (5.0, 0.0), (5.0, 5.0)), 0.0, 40.0)
    gis.add_elevation_map(sample_map())
    gis.add_elevation_map(ElevationMap("second", 0.0, 0.0, 1.0, np.zeros((2, 2))))
    world = RuntimeWorld.of(gis)
    assert world.elevation_maps == ("scan 1", "second")
    msg = world_to_msg(world)
    assert list(msg.elevation_maps) == ["scan 1", "second"]
    back = world_from_msg(msg)
    assert back == world
    assert back.obstacles == (Zone("crane", ((0.0, 0.0), (5.0, 0.0), (5.0, 5.0)), 0.0, 40.0),)
    assert world_from_msg(world_to_msg(RuntimeWorld())).elevation_maps == ()
