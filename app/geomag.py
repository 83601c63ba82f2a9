"""Reference geomagnetic field (IGRF-14) for the magnetometer and compass checks.

The field is the International Geomagnetic Reference Field, 14th generation (IAGA Working Group V-MOD,
Alken et al., "International Geomagnetic Reference Field: the fourteenth generation", Earth, Planets
and Space, 2025): main-field models every five years from 1900.0 to 2025.0 and a secular-variation
forecast from 2025.0 to 2030.0. It is evaluated by ``ppigrf``.

Why ``ppigrf`` (``ppigrf>=2.1``):

- It is the IGRF working group's own pure-Python implementation (published under the IAGA-VMOD
  organisation, author K. M. Laundal), ships the IGRF-14 coefficients from version 2.1, and
  covers the whole span 1900–2030 that the calibration needs (recordings from any year).
- It takes geodetic latitude and height above the WGS84 ellipsoid and returns geodetic east, north
  and up components (``ppigrf.igrf(lon, lat, h_km, date)``), converting to geocentric and back
  itself (its ``geod2geoc`` / ``geoc2geod``), so nothing here re-implements the ellipsoid.
- It interpolates the coefficients in calendar time (pandas), so leap years need no care from us.

Its cost is pandas; the alternatives were weighed: ``pyIGRF`` 1.0 (IGRF-14, numpy only, but a
one-author port that prints instead of raising out of range, and extrapolates to 2035), ``pyIGRF14``
(a fork of it), ``geomaglib`` (NOAA/CIRES' building blocks with the IGRF-14 coefficients, but no
ready IGRF evaluation and an 8 MB geoid table) and ``pygeomag`` / ``wmm-calculator`` (WMM only:
2025–2030, so no use for older recordings). The package is imported inside
:func:`reference_field` only, so the CLI's start-up does not pay for pandas; ``app.calibration``
(numpy and scipy only) never imports this module.
"""

from __future__ import annotations

import datetime as _dt
import math
from dataclasses import asdict, dataclass

MODEL = "IGRF-14"
# The span of IGRF-14: the 1900.0 model to the end of the 2025–2030 secular-variation forecast.
FIRST_YEAR = 1900
LAST_YEAR = 2030
_FIRST = _dt.datetime(FIRST_YEAR, 1, 1)
_LAST = _dt.datetime(LAST_YEAR, 1, 1)


class GeomagneticRangeError(ValueError):
    """A date outside the model's span, or a latitude, longitude or height it cannot take."""


@dataclass(frozen=True)
class GeomagneticField:
    """The main geomagnetic field at one place and time, in the local geodetic frame.

    North, east and down are the components X, Y, Z along geodetic north, east and the downward
    normal of the WGS84 ellipsoid; ``horizontal_ut`` is H = √(X² + Y²), ``field_ut`` is
    F = √(H² + Z²), ``inclination_deg`` is I = atan2(Z, H) (positive down) and ``declination_deg``
    is D = atan2(Y, X) (positive east of true north).
    """

    field_ut: float
    inclination_deg: float
    declination_deg: float
    north_ut: float
    east_ut: float
    down_ut: float
    horizontal_ut: float
    model: str

    def to_dict(self) -> dict:
        """The plain form: every field by its name."""
        return asdict(self)


def _as_datetime(when: _dt.date | _dt.datetime | str) -> _dt.datetime:
    """A naive UTC datetime from a date, a datetime or an ISO 8601 string."""
    if isinstance(when, str):
        text = when.strip()
        try:
            parsed: _dt.date = _dt.datetime.fromisoformat(text.replace("Z", "+00:00"))
        except ValueError:
            try:
                parsed = _dt.date.fromisoformat(text)
            except ValueError:
                raise GeomagneticRangeError(
                    f"date {when!r} is not an ISO 8601 date: give it as YYYY-MM-DD or YYYY-MM-DDTHH:MM:SS"
                ) from None
        when = parsed
    if isinstance(when, _dt.datetime):
        if when.tzinfo is not None:
            when = when.astimezone(_dt.UTC).replace(tzinfo=None)
        return when
    if isinstance(when, _dt.date):
        return _dt.datetime(when.year, when.month, when.day)
    raise GeomagneticRangeError(
        f"date {when!r} is a {type(when).__name__}: give a datetime.date, a datetime.datetime or an ISO 8601 string"
    )


def decimal_year(when: _dt.date | _dt.datetime | str) -> float:
    """The decimal year of a date: the year plus the fraction of that year elapsed.

    The fraction is the time since 1 January 00:00 over the length of that year, 365 or 366 days
    (the convention of the IGRF and WMM software: 2024-07-02 is 2024 + 183/366 = 2024.5).
    """
    t = _as_datetime(when)
    start = _dt.datetime(t.year, 1, 1)
    length = _dt.datetime(t.year + 1, 1, 1) - start
    return t.year + (t - start) / length


def reference_field(
    when: _dt.date | _dt.datetime | str,
    latitude_deg: float,
    longitude_deg: float,
    height_m: float = 0.0,
) -> GeomagneticField:
    """The IGRF-14 main field at a place and time.

    Parameters
    ----------
    when : datetime.date, datetime.datetime or str
        The date (a date is taken at 00:00 UTC; an aware datetime is converted to UTC; a string is
        ISO 8601, e.g. ``"2025-03-14"`` or ``"2025-03-14T12:00:00Z"``). Must lie in 1900-01-01 …
        2030-01-01.
    latitude_deg : float
        Geodetic latitude on the WGS84 ellipsoid, degrees in [−90, 90].
    longitude_deg : float
        Longitude, degrees east in [−360, 360].
    height_m : float, optional
        Height above the WGS84 ellipsoid in metres (not above sea level); −10 km … 1000 km.

    Returns
    -------
    GeomagneticField
        The field in µT and degrees, in the geodetic north-east-down frame.

    Raises
    ------
    GeomagneticRangeError
        For a date outside 1900–2030 or an impossible latitude, longitude or height; the message
        says the valid range.
    """
    t = _as_datetime(when)
    if not _FIRST <= t <= _LAST:
        raise GeomagneticRangeError(
            f"date {t.date().isoformat()} is outside {MODEL}'s span {FIRST_YEAR}-01-01 … {LAST_YEAR}-01-01: "
            f"give a date from {FIRST_YEAR} to {LAST_YEAR}, or give field_ut, the local field's magnitude in µT"
        )
    lat, lon, h = (float(latitude_deg), float(longitude_deg), float(height_m))
    if not math.isfinite(lat) or not -90.0 <= lat <= 90.0:
        raise GeomagneticRangeError(
            f"latitude {latitude_deg!r}° is outside −90 … 90: give the geodetic latitude in degrees, north positive"
        )
    if not math.isfinite(lon) or not -360.0 <= lon <= 360.0:
        raise GeomagneticRangeError(
            f"longitude {longitude_deg!r}° is outside −360 … 360: give the longitude in degrees, east positive"
        )
    if not math.isfinite(h) or not -10_000.0 <= h <= 1_000_000.0:
        raise GeomagneticRangeError(
            f"height {height_m!r} m is outside −10 km … 1000 km: give the height above the WGS84 ellipsoid in metres"
        )
    # At the geographic poles the spherical components are singular in φ; a latitude a hair inside
    # moves the point by millimetres.
    lat = max(min(lat, 90.0 - 1e-9), -90.0 + 1e-9)

    import ppigrf  # lazily: pulls pandas, which the CLI's start-up must not pay for

    east, north, up = (float(v.squeeze()) for v in ppigrf.igrf(lon, lat, h / 1000.0, t))
    x, y, z = north / 1000.0, east / 1000.0, -up / 1000.0  # nT → µT, up → down
    horizontal = math.hypot(x, y)
    return GeomagneticField(
        field_ut=math.hypot(horizontal, z),
        inclination_deg=math.degrees(math.atan2(z, horizontal)),
        declination_deg=math.degrees(math.atan2(y, x)),
        north_ut=x,
        east_ut=y,
        down_ut=z,
        horizontal_ut=horizontal,
        model=MODEL,
    )
