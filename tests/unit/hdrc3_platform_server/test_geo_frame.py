from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from hdrc3_base.errors import ConfigError
from hdrc3_platform_server.geo_frame import WorldFrame, frame_from_world


@pytest.mark.parametrize("enu", [(0.0, 0.0, 0.0), (300.0, -200.0, 30.0), (-4000.0, 2500.0, 120.0)])
def test_round_trip(enu: tuple[float, float, float]) -> None:
    frame = WorldFrame(55.70, 13.47, 95.0)
    back = frame.to_enu(*frame.to_wgs84(*enu))
    assert back == pytest.approx(enu, abs=1e-6)


def test_300_m_east_is_about_0_0048_deg_of_longitude_at_revinge() -> None:
    frame = WorldFrame(55.70, 13.47, 95.0)
    lon, lat, _ = frame.to_wgs84(300.0, 0.0, 0.0)
    assert lon - 13.47 == pytest.approx(
        300.0 / (6378137.0 * math.cos(math.radians(55.7))) * 180 / math.pi, rel=1e-2
    )
    assert lat == pytest.approx(55.70, abs=1e-6)


def test_world_file_gives_origin_extent_and_terrain() -> None:
    frame = frame_from_world("revinge")
    assert (frame.latitude, frame.longitude, frame.altitude) == (55.70, 13.47, 95.0)
    assert frame.bounds == (-300.0, -200.0, 300.0, 200.0)
    assert frame.inside(1200.0, 0.0) and not frame.inside(1400.0, 0.0)
    assert frame.ground_up(300.0, 200.0) == pytest.approx(3.0)


@pytest.mark.parametrize(
    "values",
    [(math.nan, 13.0, 0.0), (95.0, 13.0, 0.0), (55.0, 190.0, 0.0)],
)
def test_bad_origins(values: tuple[float, float, float]) -> None:
    with pytest.raises(ConfigError):
        WorldFrame(*values)


def test_unknown_world() -> None:
    with pytest.raises(ConfigError, match="cannot load world"):
        frame_from_world("no_such_world_here")


@pytest.mark.parametrize("bad", [math.nan, math.inf])
def test_a_state_with_a_non_finite_coordinate_has_no_enu_position(bad: float) -> None:
    frame = frame_from_world("revinge")
    good = SimpleNamespace(
        longitude=frame.longitude, latitude=frame.latitude, altitude=frame.altitude
    )
    assert frame.state_enu(good) == pytest.approx((0.0, 0.0, 0.0), abs=1e-6)
    assert frame.state_enu(SimpleNamespace(longitude=bad, latitude=0.0, altitude=0.0)) is None
