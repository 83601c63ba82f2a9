"""Reference gravity: the standard value and local normal gravity (WGS84)."""

import math

STANDARD_GRAVITY = 9.80665
"""Standard acceleration of gravity in m/s² (CGPM 1901), trical's default reference."""

# WGS84 ellipsoid constants (NIMA TR8350.2, 3rd ed., tables 3.1–3.3).
_GAMMA_E = 9.7803253359  # normal gravity at the equator, m/s²
_K = 0.00193185265241  # Somigliana's constant
_E2 = 0.00669437999013  # first eccentricity squared
_A = 6378137.0  # semi-major axis, m
_F = 1.0 / 298.257223563  # flattening
_M = 0.00344978650684  # ω²a²b/GM


def normal_gravity(latitude_deg: float, height_m: float = 0.0) -> float:
    """Local normal gravity on the WGS84 ellipsoid.

    Somigliana's closed formula on the ellipsoid, then the second-order free-air
    correction for the height above it (NIMA TR8350.2 eq. 4-1 and 4-3).

    Parameters
    ----------
    latitude_deg : float
        Geodetic latitude in degrees, in [-90, 90].
    height_m : float
        Ellipsoidal height in metres, in [-12 000, 100 000].

    Returns
    -------
    float
        Normal gravity in m/s².

    Raises
    ------
    ValueError
        If the latitude or the height is outside its range or not finite.
    """
    if not (math.isfinite(latitude_deg) and -90.0 <= latitude_deg <= 90.0):
        raise ValueError(f"latitude_deg must be in [-90, 90] degrees; got {latitude_deg}")
    if not (math.isfinite(height_m) and -12_000.0 <= height_m <= 100_000.0):
        raise ValueError(f"height_m must be in [-12000, 100000] metres; got {height_m}")
    s2 = math.sin(math.radians(latitude_deg)) ** 2
    gamma = _GAMMA_E * (1.0 + _K * s2) / math.sqrt(1.0 - _E2 * s2)
    h = height_m
    return gamma * (1.0 - 2.0 / _A * (1.0 + _F + _M - 2.0 * _F * s2) * h + 3.0 / _A**2 * h * h)
