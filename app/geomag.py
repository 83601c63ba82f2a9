"""The Earth's main field at a place and day, from the International Geomagnetic Reference Field.

The compass calibration (app.calibration.magnetometer) references the calibrated field to the
magnitude the Earth's field has where and when the device was turned, and checks its dip against
the model's inclination. The field comes from IGRF-14 (Alken et al., "International Geomagnetic
Reference Field: the fourteenth generation", Earth, Planets and Space, 2025; IAGA Division V,
Working Group V-MOD), valid from 1900 to 2030, through the ``ppigrf`` package (Laundal et al.,
pure Python and numpy, the IAGA coefficient file shipped with it). IGRF, not the World Magnetic
Model: WMM2025 covers only 2025–2030, and a recording may be older; at the places NOAA publishes
WMM2025 test values for, the two models agree to about 100 nT and 0.1° (tests/test_geomag.py).

Kept out of the pure core (the package needs pandas) and imported only when a request gives a place.
"""

from __future__ import annotations

import calendar
import datetime
import math
from dataclasses import asdict, dataclass

MODEL = "IGRF-14"
FIRST_YEAR, LAST_YEAR = 1900, 2030
"""IGRF-14's span: definitive and provisional models 1900–2020, the 2025 model, and its secular
variation predicted to 2030."""


class GeomagneticRangeError(ValueError):
    """A day or place the model does not cover; the message gives the valid range."""


@dataclass(frozen=True)
class GeomagneticField:
    """The main field at a place and day: magnitude, angles and components in µT (north, east, down)."""

    field_ut: float
    inclination_deg: float
    declination_deg: float
    north_ut: float
    east_ut: float
    down_ut: float
    horizontal_ut: float
    model: str = MODEL

    def to_dict(self) -> dict:
        return asdict(self)


def _day(when) -> datetime.datetime:
    if isinstance(when, str):
        try:
            when = datetime.date.fromisoformat(when.strip()[:10])
        except ValueError:
            raise GeomagneticRangeError(f"{when!r} is not a day: give it as YYYY-MM-DD") from None
    if isinstance(when, datetime.datetime):
        return when.replace(tzinfo=None)
    if isinstance(when, datetime.date):
        return datetime.datetime(when.year, when.month, when.day, 12)  # noon: the middle of the day
    raise GeomagneticRangeError(f"{when!r} is not a day: give a date, a datetime or YYYY-MM-DD")


def decimal_year(when) -> float:
    """The day as a decimal year (2024-07-02 noon → 2024.5; leap years have 366 days)."""
    t = _day(when)
    start = datetime.datetime(t.year, 1, 1)
    days = 366 if calendar.isleap(t.year) else 365
    return t.year + (t - start).total_seconds() / (days * 86400.0)


def reference_field(when, latitude_deg: float, longitude_deg: float, height_m: float = 0.0) -> GeomagneticField:
    """IGRF-14's main field at a geodetic place and a day.

    Parameters
    ----------
    when : datetime.date, datetime.datetime or str
        The day (ISO ``YYYY-MM-DD``; a date is taken at noon UTC), 1900–2030.
    latitude_deg, longitude_deg : float
        Geodetic (WGS84) latitude, −90…90, and longitude, east positive, −180…360.
    height_m : float
        Height above the WGS84 ellipsoid.

    Returns
    -------
    GeomagneticField

    Raises
    ------
    GeomagneticRangeError
        A day outside 1900–2030, or a place outside the ranges.
    """
    t = _day(when)
    year = decimal_year(t)
    if not FIRST_YEAR <= year <= LAST_YEAR:
        raise GeomagneticRangeError(f"{t.date().isoformat()} is outside {MODEL}'s span, {FIRST_YEAR}–{LAST_YEAR}: give "
                                    f"the day of the recording, or field_ut for the local field's magnitude")
    if not (math.isfinite(latitude_deg) and -90.0 <= latitude_deg <= 90.0):
        raise GeomagneticRangeError(f"latitude {latitude_deg} is outside −90…90°")
    if not (math.isfinite(longitude_deg) and -180.0 <= longitude_deg <= 360.0):
        raise GeomagneticRangeError(f"longitude {longitude_deg} is outside −180…360°")
    if not (math.isfinite(height_m) and -12_000.0 <= height_m <= 1_000_000.0):
        raise GeomagneticRangeError(f"height {height_m} m is outside −12 km…1000 km")
    import ppigrf  # pandas and the coefficient file: loaded only when a place is given

    east, north, up = (float(v.ravel()[0]) for v in ppigrf.igrf(longitude_deg, latitude_deg, height_m / 1000.0, t))
    down = -up
    horizontal = math.hypot(north, east)
    field = math.sqrt(horizontal ** 2 + down ** 2)
    return GeomagneticField(
        field_ut=field / 1000.0, inclination_deg=math.degrees(math.atan2(down, horizontal)),
        declination_deg=math.degrees(math.atan2(east, north)), north_ut=north / 1000.0, east_ut=east / 1000.0,
        down_ut=down / 1000.0, horizontal_ut=horizontal / 1000.0)
