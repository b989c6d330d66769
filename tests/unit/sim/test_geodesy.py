"""ENU <-> WGS84 conversions about a world origin."""

from __future__ import annotations

import math

import pymap3d
import pytest

from sim.geodesy import GeodeticOrigin, LocalFrame, enu_to_geodetic, geodetic_to_enu

ORIGIN = GeodeticOrigin(55.70, 13.47, 95.0)


def test_origin_maps_to_itself() -> None:
    point = enu_to_geodetic(ORIGIN, 0.0, 0.0, 0.0)
    assert (point.latitude, point.longitude, point.altitude) == pytest.approx((55.70, 13.47, 95.0))


@pytest.mark.parametrize(
    ("east", "north", "up"), [(100.0, 0.0, 0.0), (0.0, -250.0, 10.0), (300.0, 200.0, 50.0)]
)
def test_round_trip(east: float, north: float, up: float) -> None:
    point = enu_to_geodetic(ORIGIN, east, north, up)
    back = geodetic_to_enu(ORIGIN, point.latitude, point.longitude, point.altitude)
    assert back == pytest.approx((east, north, up), abs=1e-6)


def test_directions_and_scale() -> None:
    north = enu_to_geodetic(ORIGIN, 0.0, 1000.0, 0.0)
    east = enu_to_geodetic(ORIGIN, 1000.0, 0.0, 0.0)
    # One degree of latitude is ~111.2 km; of longitude ~111.3 km * cos(latitude).
    assert north.latitude - ORIGIN.latitude == pytest.approx(1000.0 / 111_200.0, rel=0.005)
    assert east.longitude - ORIGIN.longitude == pytest.approx(
        1000.0 / (111_320.0 * math.cos(math.radians(55.7))), rel=0.005
    )


@pytest.mark.parametrize(
    ("lat", "lon", "alt"),
    [(91.0, 0.0, 0.0), (0.0, 181.0, 0.0), (0.0, 0.0, 20_000.0), (math.nan, 0.0, 0.0)],
)
def test_bad_origin_rejected(lat: float, lon: float, alt: float) -> None:
    with pytest.raises(ValueError):
        GeodeticOrigin(lat, lon, alt)


@pytest.mark.parametrize(
    ("east", "north", "up"),
    [(0.0, 0.0, 0.0), (300.0, -200.0, 40.0), (-5000.0, 8000.0, 1500.0), (20_000.0, 0.0, -50.0)],
)
def test_fast_local_frame_matches_pymap3d(east: float, north: float, up: float) -> None:
    fast = LocalFrame(ORIGIN).to_geodetic(east, north, up)
    exact = enu_to_geodetic(ORIGIN, east, north, up)
    assert fast.latitude == pytest.approx(exact.latitude, abs=1e-9)  # ~0.1 mm
    assert fast.longitude == pytest.approx(exact.longitude, abs=1e-9)
    assert fast.altitude == pytest.approx(exact.altitude, abs=1e-4)


@pytest.mark.parametrize(
    ("e", "n", "u"), [(0.0, 0.0, 0.0), (1500.0, -800.0, 120.0), (-4000.0, 3000.0, -5.0)]
)
def test_local_frame_from_ecef_matches_pymap3d(e: float, n: float, u: float) -> None:
    frame = LocalFrame(GeodeticOrigin(58.4, 15.6, 80.0))
    x, y, z = pymap3d.enu2ecef(e, n, u, 58.4, 15.6, 80.0)
    assert frame.from_ecef(x, y, z) == pytest.approx((e, n, u), abs=1e-6)
    fix = frame.to_geodetic(e, n, u)
    ecef = pymap3d.geodetic2ecef(fix.latitude, fix.longitude, fix.altitude)
    assert frame.from_ecef(*ecef) == pytest.approx((e, n, u), abs=1e-6)
