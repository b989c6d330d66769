import pymap3d
import pytest

from sim.enu_frame import EnuFrame


@pytest.mark.parametrize(
    ("e", "n", "u"), [(0.0, 0.0, 0.0), (1500.0, -800.0, 120.0), (-4000.0, 3000.0, -5.0)]
)
def test_matches_pymap3d(e: float, n: float, u: float) -> None:
    frame = EnuFrame(58.4, 15.6, 80.0)
    x, y, z = pymap3d.enu2ecef(e, n, u, 58.4, 15.6, 80.0)
    assert frame.from_ecef(x, y, z) == pytest.approx((e, n, u), abs=1e-6)
    lat, lon, alt = frame.to_geodetic(e, n, u)
    assert frame.from_ecef(*pymap3d.geodetic2ecef(lat, lon, alt)) == pytest.approx(
        (e, n, u), abs=1e-6
    )
