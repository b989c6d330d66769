"""The laser_mapper node's conversions: a map cropped to its mapped cells, points as a cloud."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hdrc3_navigation.elevation_map import ElevationMap
from hdrc3_perception.laser_node import cloud_msg, cropped

NAN = math.nan


@pytest.mark.parametrize(
    ("mapped", "origin", "shape"),
    [
        (((2, 3), (4, 7)), (103.0, -48.0), (3, 5)),  # rows 2..4, columns 3..7
        (((0, 0),), (100.0, -50.0), (1, 1)),
        ((), (100.0, -50.0), (6, 10)),  # nothing mapped: the map as it is
    ],
)
def test_a_finished_map_is_cropped_to_its_mapped_cells(
    mapped: tuple[tuple[int, int], ...], origin: tuple[float, float], shape: tuple[int, int]
) -> None:
    heights = np.full((6, 10), NAN)
    returns = np.zeros((6, 10), dtype=np.int64)
    for row, col in mapped:
        heights[row, col], returns[row, col] = 2.0, 5
    m = cropped(ElevationMap("m", 100.0, -50.0, 1.0, heights, returns))
    assert (m.east0, m.north0) == origin and m.heights.shape == shape
    assert m.returns.shape == shape and int(m.returns.sum()) == 5 * len(mapped)
    assert isinstance(m.east0, float)


def test_points_become_a_float32_xyz_cloud_in_the_map_frame() -> None:
    points = np.array([[1.0, 2.0, 3.0], [-4.5, 5.25, 0.0]])
    msg = cloud_msg(points, 12.5)
    assert (msg.header.frame_id, msg.header.stamp.sec, msg.header.stamp.nanosec) == (
        "map",
        12,
        500_000_000,
    )
    assert [f.name for f in msg.fields] == ["x", "y", "z"] and msg.point_step == 12
    assert (msg.width, msg.height, msg.row_step) == (2, 1, 24)
    decoded = np.frombuffer(bytes(msg.data), dtype=np.float32).reshape(-1, 3)
    assert decoded == pytest.approx(points)
