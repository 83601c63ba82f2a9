import pytest

from app.calibration import STANDARD_GRAVITY, normal_gravity


def test_wgs84_normal_gravity():
    # NIMA TR8350.2 table 3.4: γ_e and γ_p of the WGS84 ellipsoid.
    assert normal_gravity(0.0) == pytest.approx(9.7803253359, abs=1e-10)
    assert normal_gravity(90.0) == pytest.approx(9.8321849378, abs=1e-9)
    assert normal_gravity(-90.0) == normal_gravity(90.0)
    # Free-air gradient near the surface is about −3.086 µm/s² per metre.
    assert (normal_gravity(45.0, 100.0) - normal_gravity(45.0)) / 100.0 == pytest.approx(-3.086e-6, rel=2e-3)
    assert STANDARD_GRAVITY == 9.80665


@pytest.mark.parametrize("lat, h", [(91, 0), (float("nan"), 0), (0, 1e6)])
def test_out_of_range(lat, h):
    with pytest.raises(ValueError):
        normal_gravity(lat, h)
