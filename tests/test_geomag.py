"""The Earth's field from IGRF-14 (app.geomag) against the World Magnetic Model's published test values."""

import datetime
import subprocess
import sys

import numpy as np
import pytest

from app.geomag import GeomagneticRangeError, decimal_year, reference_field
from tests.conftest import DATA
from tests.live_server import ROOT

# WMM2025 and IGRF-14 are different models of the same field: at these 12 test points they agree to
# 12 nT and 0.04° (the largest differences, measured); the test allows 20 nT and 0.05°.
TOLERANCE_NT = 20.0
TOLERANCE_DEG = 0.05
ROWS = np.loadtxt(DATA / "wmm2025_test_values.txt")


def _day(decimal: float) -> datetime.datetime:
    year = int(decimal)
    return datetime.datetime(year, 1, 1) + datetime.timedelta(days=(decimal - year) * 365)


@pytest.mark.parametrize("row", ROWS.tolist(), ids=lambda r: f"{r[0]}-{r[1]:g}km-{r[2]:g},{r[3]:g}")
def test_igrf_agrees_with_the_wmm2025_test_values(row):
    year, height_km, lat, lon, x, y, z, h, f, inc, dec = row
    field = reference_field(_day(year), lat, lon, height_km * 1000.0)
    got = np.array([field.north_ut, field.east_ut, field.down_ut, field.horizontal_ut, field.field_ut]) * 1000.0
    np.testing.assert_allclose(got, [x, y, z, h, f], atol=TOLERANCE_NT)
    assert field.inclination_deg == pytest.approx(inc, abs=TOLERANCE_DEG)
    assert field.declination_deg == pytest.approx(dec, abs=TOLERANCE_DEG)
    assert field.model == "IGRF-14" and field.to_dict()["field_ut"] == field.field_ut


def test_old_days_are_covered_and_the_field_has_moved():
    then = reference_field("1950-06-01", 60.17, 24.94)  # Helsinki
    now = reference_field("2026-12-02", 60.17, 24.94)
    assert 45.0 < then.field_ut < 60.0 and 45.0 < now.field_ut < 60.0
    assert 70.0 < now.inclination_deg < 80.0
    # the declination at Helsinki moved east by several degrees in 76 years
    assert now.declination_deg - then.declination_deg > 3.0


def test_decimal_years_count_leap_days():
    assert decimal_year(datetime.datetime(2024, 7, 2, 0)) == pytest.approx(2024 + 183 / 366)
    assert decimal_year(datetime.datetime(2025, 7, 2, 12)) == pytest.approx(2025 + 182.5 / 365)
    assert decimal_year("2026-01-01") == pytest.approx(2026 + 0.5 / 365)  # a day is taken at noon


@pytest.mark.parametrize("when, lat, lon, words", [
    ("1899-12-31", 0.0, 0.0, "1900–2030"), ("2031-01-02", 0.0, 0.0, "1900–2030"),
    ("not a day", 0.0, 0.0, "YYYY-MM-DD"), ("2026-01-01", 91.0, 0.0, "latitude"),
    ("2026-01-01", 0.0, 400.0, "longitude"),
])
def test_outside_the_model_says_the_range(when, lat, lon, words):
    with pytest.raises(GeomagneticRangeError, match=words):
        reference_field(when, lat, lon)


def test_the_model_s_package_loads_only_when_asked():
    code = ("import sys, app.geomag, app.calibration.magnetometer, app.workflow\n"
            "print(','.join(n for n in ('ppigrf', 'pandas') if n in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""
