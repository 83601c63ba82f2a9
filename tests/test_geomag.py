"""The IGRF-14 reference field (app/geomag.py) against the WMM2025 test values and IGRF itself."""

import datetime as dt
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from app.geomag import GeomagneticField, GeomagneticRangeError, decimal_year, reference_field
from tests.processes import run_ok

ROOT = Path(__file__).resolve().parents[1]

# WMM2025 test values, NOAA NCEI / British Geological Survey, "The US/UK World Magnetic Model for
# 2025-2030" (WMM2025 report), test-value table as distributed in WMM2025_TEST_VALUES.txt
# (copied from the copy in the ahrs project, ahrs/utils/WMM2025/WMM2025_TEST_VALUES.txt).
# decimal year, height above WGS84 (km), geodetic lat, lon (deg), X, Y, Z, H, F (nT), I, D (deg)
WMM2025 = [
    (2025.0, 0.0, 80.0, 0.0, 6521.6, 145.9, 54791.5, 6523.2, 55178.5, 83.21, 1.28),
    (2025.0, 0.0, 0.0, 120.0, 39677.8, -109.6, -10580.2, 39677.9, 41064.3, -14.93, -0.16),
    (2025.0, 0.0, -80.0, 240.0, 6117.5, 15751.9, -52022.5, 16898.1, 54698.2, -72.00, 68.78),
    (2025.0, 100.0, 80.0, 0.0, 6216.0, 92.4, 52598.8, 6216.7, 52964.9, 83.26, 0.85),
    (2025.0, 100.0, 0.0, 120.0, 37688.6, -96.2, -10152.1, 37688.7, 39032.1, -15.08, -0.15),
    (2025.0, 100.0, -80.0, 240.0, 5907.6, 14780.3, -49540.7, 15917.1, 52035.0, -72.19, 68.21),
    (2027.5, 0.0, 80.0, 0.0, 6500.8, 294.5, 54869.4, 6507.5, 55253.9, 83.24, 2.59),
    (2027.5, 0.0, 0.0, 120.0, 39701.6, -167.4, -10381.8, 39702.0, 41036.9, -14.65, -0.24),
    (2027.5, 0.0, -80.0, 240.0, 6200.7, 15730.3, -51783.7, 16908.3, 54474.2, -71.92, 68.49),
    (2027.5, 100.0, 80.0, 0.0, 6196.7, 233.8, 52670.5, 6201.1, 53034.3, 83.29, 2.16),
    (2027.5, 100.0, 0.0, 120.0, 37711.5, -148.7, -9969.8, 37711.8, 39007.4, -14.81, -0.23),
    (2027.5, 100.0, -80.0, 240.0, 5984.0, 14760.1, -49317.7, 15927.0, 51825.7, -72.10, 67.93),
]

# IGRF-14 and WMM2025 are different models of the same main field: at these 12 points they differ by
# at most 11.8 nT and 0.04° (measured), so the components and F are held to 20 nT and I, D to 0.05°.
NT_TOL = 20.0
DEG_TOL = 0.05
# Against IAGA's own IGRF-14 program the model is the same, so the figures agree to half a nT
# (the largest difference here is 0.2 nT).
IGRF_TOL = 0.5

# WGS84 (NIMA TR8350.2, 3rd ed., table 3.1).
A_KM = 6378.137
F_WGS84 = 1.0 / 298.257223563
E2 = F_WGS84 * (2.0 - F_WGS84)


def from_decimal_year(year: float) -> dt.datetime:
    """The datetime of a decimal year (the WMM convention: the fraction of that year's own length)."""
    whole = int(math.floor(year))
    start = dt.datetime(whole, 1, 1)
    return start + (dt.datetime(whole + 1, 1, 1) - start) * (year - whole)


@pytest.mark.parametrize("row", WMM2025, ids=lambda r: f"{r[0]}-{r[1]:g}km-{r[2]:g}N-{r[3]:g}E")
def test_matches_wmm2025_test_values(row):
    year, h_km, lat, lon, x, y, z, h, f, inc, dec = row
    field = reference_field(from_decimal_year(year), lat, lon, height_m=h_km * 1000.0)
    got = np.array([field.north_ut, field.east_ut, field.down_ut, field.horizontal_ut, field.field_ut]) * 1000.0
    np.testing.assert_allclose(got, [x, y, z, h, f], rtol=0, atol=NT_TOL)
    assert field.inclination_deg == pytest.approx(inc, abs=DEG_TOL)
    assert field.declination_deg == pytest.approx(dec, abs=DEG_TOL)
    assert field.model == "IGRF-14"


def test_elements_are_consistent_and_plain_form_names_every_field():
    field = reference_field("2025-06-01", 52.2, 0.12, 20.0)
    assert field.horizontal_ut == pytest.approx(math.hypot(field.north_ut, field.east_ut), rel=1e-12)
    assert field.field_ut == pytest.approx(math.hypot(field.horizontal_ut, field.down_ut), rel=1e-12)
    assert math.tan(math.radians(field.declination_deg)) == pytest.approx(field.east_ut / field.north_ut, rel=1e-9)
    d = field.to_dict()
    assert d == {
        "field_ut": field.field_ut,
        "inclination_deg": field.inclination_deg,
        "declination_deg": field.declination_deg,
        "north_ut": field.north_ut,
        "east_ut": field.east_ut,
        "down_ut": field.down_ut,
        "horizontal_ut": field.horizontal_ut,
        "model": "IGRF-14",
    }
    assert GeomagneticField(**d) == field


def test_decimal_year_counts_leap_years():
    assert decimal_year("2024-07-02") == 2024.5  # 183 of 366 days
    assert decimal_year("2027-07-02T12:00:00") == 2027.5  # 182.5 of 365 days
    assert decimal_year(dt.date(2000, 3, 1)) == pytest.approx(2000 + 60 / 366, abs=1e-12)
    assert decimal_year(dt.date(1900, 3, 1)) == pytest.approx(1900 + 59 / 365, abs=1e-12)  # 1900: no leap year
    assert decimal_year(from_decimal_year(2027.5)) == 2027.5
    aware = dt.datetime(2025, 1, 1, 1, 0, tzinfo=dt.timezone(dt.timedelta(hours=2)))  # 2024-12-31T23:00Z
    assert decimal_year(aware) == pytest.approx(2024 + (365 + 23 / 24) / 366, abs=1e-12)


def test_dates_may_be_iso_strings_dates_or_datetimes():
    by_str = reference_field("1985-04-20", 45.0, 10.0)
    assert reference_field(dt.date(1985, 4, 20), 45.0, 10.0) == by_str
    assert reference_field(dt.datetime(1985, 4, 20), 45.0, 10.0) == by_str
    assert reference_field("1985-04-20T02:00:00+02:00", 45.0, 10.0) == by_str


# IGRF-14 by IAGA's reference Fortran synthesis program igrf14syn (geodetic input), as tabulated in
# test/IGRF14_test_geodetic.txt of the SatelliteToolboxGeomagneticField.jl project (generated by its
# IGRF_Test program); the rows up to 1000 km, most before 2000.
# decimal year, height above WGS84 (km), geodetic colatitude, east longitude (deg), X, Y, Z, F (nT)
IGRF14SYN = [
    (1900.0, 232.32, 68.00, 165.11, 27505.75351, 3089.91355, 16985.87684, 32475.12977),
    (1912.3, 461.20, 0.27, 149.15, 5.54379, 2869.14288, 47029.33285, 47116.77154),
    (1923.1, 28.67, 44.61, 28.77, 22141.72136, -93.49024, 39125.76146, 44956.53206),
    (1926.2, 39.97, 17.26, 353.96, 9103.92056, -3990.87427, 50222.73073, 51196.98360),
    (1932.1, 461.71, 32.33, 59.94, 13310.84345, 2387.49449, 41502.52630, 43650.18182),
    (1935.4, 97.80, 66.25, 118.16, 34965.73111, -780.61590, 22635.35126, 41660.18290),
    (1936.8, 720.12, 68.98, 171.98, 22055.54809, 2837.76473, 12825.32720, 25670.78354),
    (1949.3, 360.29, 89.92, 55.30, 28321.31444, -1639.25832, -9690.11452, 29978.03094),
    (1958.9, 32.01, 52.63, 186.65, 24524.29311, 4674.21697, 31554.57461, 40236.55597),
    (1971.9, 372.19, 4.23, 244.39, -1032.48029, 117.36753, 48759.11091, 48770.18236),
    (1988.0, 138.16, 56.85, 318.49, 23164.89042, -7333.27843, 32808.52011, 40826.31642),
    (1990.6, 34.18, 34.51, 24.06, 16779.17251, 1244.60056, 46474.73203, 49426.61609),
    (2012.2, 77.18, 4.81, 190.69, 750.03774, 394.68103, 55395.16588, 55401.64919),
    (2022.1, 829.10, 46.47, 114.85, 17590.40262, -1731.07191, 33147.28408, 37565.42714),
    (2027.9, 139.86, 45.06, 138.29, 23759.41728, -4335.97718, 42511.80742, 48893.39810),
]


@pytest.mark.parametrize("row", IGRF14SYN, ids=lambda r: f"{r[0]}-{r[1]:g}km-colat{r[2]:g}-{r[3]:g}E")
def test_matches_iagas_igrf14syn(row):
    # The same model: igrf14syn interpolates linearly in decimal years, ppigrf in calendar time,
    # which differ by under a day in five years (well under 1 nT at these rates of change).
    year, h_km, colat, lon, x, y, z, f = row
    field = reference_field(from_decimal_year(year), 90.0 - colat, lon, height_m=h_km * 1000.0)
    got = np.array([field.north_ut, field.east_ut, field.down_ut, field.field_ut]) * 1000.0
    np.testing.assert_allclose(got, [x, y, z, f], rtol=0, atol=IGRF_TOL)


def _igrf_geodetic_by_hand(when: dt.datetime, lat_deg: float, lon_deg: float, h_km: float) -> np.ndarray:
    """X, Y, Z (nT) through ppigrf's geocentric entry point and our own WGS84 conversion.

    Geodetic → geocentric position and the rotation of the vector back to geodetic north and down
    follow Chulliat et al., "The US/UK World Magnetic Model for 2020-2025", NOAA technical report,
    eqs. (7) and (17).
    """
    import ppigrf

    phi = math.radians(lat_deg)
    rc = A_KM / math.sqrt(1.0 - E2 * math.sin(phi) ** 2)
    p = (rc + h_km) * math.cos(phi)
    zc = (rc * (1.0 - E2) + h_km) * math.sin(phi)
    r = math.hypot(p, zc)
    phi_c = math.asin(zc / r)
    b_r, b_theta, b_phi = (float(v.squeeze()) for v in ppigrf.igrf_gc(r, 90.0 - math.degrees(phi_c), lon_deg, when))
    x_c, z_c = -b_theta, -b_r
    psi = phi_c - phi
    return np.array([x_c * math.cos(psi) - z_c * math.sin(psi), b_phi, x_c * math.sin(psi) + z_c * math.cos(psi)])


@pytest.mark.parametrize(
    ("when", "lat", "lon", "h_km"),
    [
        (dt.datetime(1950, 1, 1), 48.0, 2.0, 0.0),
        (dt.datetime(1957, 8, 15), -33.9, 18.4, 1.5),
        (dt.datetime(1903, 5, 1), 70.0, -150.0, 300.0),
    ],
)
def test_pre_2000_dates_agree_with_the_geocentric_path(when, lat, lon, h_km):
    field = reference_field(when, lat, lon, height_m=h_km * 1000.0)
    got = np.array([field.north_ut, field.east_ut, field.down_ut]) * 1000.0
    np.testing.assert_allclose(got, _igrf_geodetic_by_hand(when, lat, lon, h_km), rtol=0, atol=0.01)


def test_coefficients_are_interpolated_in_calendar_time():
    # Halfway in time from 1950-01-01 to 1955-01-01 (913 of 1826 days, 1952 being a leap year) is
    # 1952-07-02 00:00 = 1952.5; the field is linear in the coefficients, so it is the mean.
    a, b = reference_field("1950-01-01", 60.0, 25.0), reference_field("1955-01-01", 60.0, 25.0)
    mid = reference_field("1952-07-02", 60.0, 25.0)
    assert decimal_year("1952-07-02") == 1952.5
    for name in ("north_ut", "east_ut", "down_ut"):
        assert getattr(mid, name) == pytest.approx((getattr(a, name) + getattr(b, name)) / 2, abs=1e-9)


@pytest.mark.parametrize("when", ["1899-12-31", dt.date(2030, 1, 2), dt.datetime(2031, 6, 1), "1850-06-01"])
def test_dates_outside_1900_2030_are_refused_naming_the_span(when):
    with pytest.raises(GeomagneticRangeError, match=r"1900-01-01 … 2030-01-01") as err:
        reference_field(when, 45.0, 10.0)
    assert "give a date from 1900 to 2030" in str(err.value)


def test_span_ends_are_accepted():
    assert reference_field("1900-01-01", 0.0, 0.0).field_ut > 20.0
    assert reference_field("2030-01-01", 0.0, 0.0).field_ut > 20.0


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("2025-01-01", 91.0, 0.0), "latitude 91.0° is outside −90 … 90"),
        (("2025-01-01", float("nan"), 0.0), "latitude nan° is outside"),
        (("2025-01-01", 10.0, 400.0), "longitude 400.0° is outside −360 … 360"),
        (("2025-01-01", 10.0, 0.0, 2.0e6), "height 2000000.0 m is outside −10 km … 1000 km"),
        (("01/02/2025", 10.0, 0.0), "not an ISO 8601 date: give it as YYYY-MM-DD"),
    ],
)
def test_bad_places_and_dates_say_what_to_give(args, message):
    with pytest.raises(GeomagneticRangeError, match=message):
        reference_field(*args)


def test_poles_give_a_finite_field():
    north = reference_field("2025-01-01", 90.0, 0.0)
    assert north.inclination_deg == pytest.approx(88.0, abs=2.0)
    assert all(math.isfinite(v) for v in (north.north_ut, north.east_ut, north.down_ut))


def test_the_igrf_package_is_imported_only_when_asked_for():
    code = (
        "import sys, app.calibration, app.geomag\n"
        "print(','.join(sorted(n for n in sys.modules if n.split('.')[0] in ('ppigrf', 'pandas'))))\n"
    )
    out = run_ok([sys.executable, "-c", code], timeout_s=120, cwd=ROOT)
    assert out.stdout.strip() == "", f"importing app.calibration and app.geomag pulled in: {out.stdout}"
