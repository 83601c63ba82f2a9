"""Whether a flight log's compass measures at all, before anything is fitted to it.

A compass that is unplugged, disabled or dead still has its rows in a log: ArduPilot logs the corrected
field, so a compass reading 0 shows the stored offsets, and the raw readings read back from it are 0 or
the same value throughout. Such readings must never reach the fit: a zero vector has a heading of 0, so
its "heading error before" equals the declination and any fit looks like an improvement, or the fit is
singular and the answer speaks of headings not flown. Three facts of the readings alone, each against the
field the attitude expects (``e = C_nbᵀ B_ned``), tell a compass that does not measure:

1. **Zero**: the readings' median magnitude below :data:`ZERO_UT` (no place on Earth has a field below
   22 µT; the readings' noise alone is larger).
2. **Not turning**: the vehicle turned (the expected field's 5–95 % range on some axis is at least
   :data:`MIN_TURN` of the field) while the readings' range on every axis stays below
   :data:`MIN_FOLLOW` of the expected field's: the compass does not see the vehicle turn (stuck, or
   reading something other than the Earth's field).
3. **A wrong scale**: on the axes the vehicle turned, the readings' ranges over the expected field's have a
   median outside :data:`SCALE_RATIO`: the compass turns with the vehicle but by a field far from the Earth's
   (a wrong scale in the driver or the log, or a compass reading something else), which no offset or soft
   iron fitted on top corrects. The ranges are taken, not the magnitude, because an uncalibrated compass's
   hard iron (tens of µT on a frame) moves the magnitude and is exactly what a fit corrects.
"""

from __future__ import annotations

import numpy as np

from ..shared.errors import CalibrationError

ZERO_UT = 1.0
"""A median reading below 1 µT: the compass reads zero."""

MIN_TURN = 0.25
"""The expected field's widest 5–95 % range, as a share of the field, that shows the vehicle turned."""

MIN_FOLLOW = 0.2
"""The readings' widest 5–95 % range below this share of the expected field's: they do not follow the turns.
A healthy compass's range is 0.9–1.3 times the expected field's on the real logs (log171.bin's three compasses),
its soft iron and offsets aside."""

SCALE_RATIO = (0.35, 1.65)
"""The readings' turning range against the Earth field's: ArduPilot's pre-arm field-strength ratios
(AP_Arming::compass_checks refuses a field outside 185–875 mG, "0.35 * 530 milligauss" to "1.65 * 530"),
applied to how far the field turns rather than to its magnitude."""


class CompassNotMeasuringError(CalibrationError):
    """The compass's readings do not measure the Earth's field: nothing can be fitted to them."""

    code = "compass_not_measuring"


def _range(a: np.ndarray) -> np.ndarray:
    """The 5–95 % range of each column."""
    lo, hi = np.percentile(a, [5, 95], axis=0)
    return hi - lo


def not_measuring(mag, expected) -> str | None:
    """Why a flight's compass readings do not measure the Earth's field, or None when they may.

    Parameters
    ----------
    mag : array_like, shape (N, 3)
        Raw readings in µT.
    expected : array_like, shape (N, 3)
        The field the attitude expects in the body frame, µT.

    Returns
    -------
    str or None
        What the readings show (the cause, without a remedy), or None.
    """
    m = np.asarray(mag, dtype=float)
    e = np.asarray(expected, dtype=float)
    field = float(np.median(np.linalg.norm(e, axis=1)))
    size = float(np.median(np.linalg.norm(m, axis=1)))
    if size < ZERO_UT:
        return f"the compass reads {size:.1f} µT for the whole flight, where the Earth's field is {field:.1f} µT"
    turn, follow = float(_range(e).max()), float(_range(m).max())
    if turn >= MIN_TURN * field and follow < MIN_FOLLOW * turn:
        return (
            f"the compass's readings stay within {follow:.1f} µT while the vehicle turned the Earth's field through "
            f"{turn:.1f} µT on an axis: it does not see the vehicle turn (stuck, or not reading the Earth's field)"
        )
    turned = _range(e) >= MIN_TURN * field
    if turned.any():
        scale = float(np.median(_range(m)[turned] / _range(e)[turned]))
        lo, hi = SCALE_RATIO
        if not lo <= scale <= hi:
            return (
                f"the compass's readings turn {scale:.2f} times as far as the Earth's field of {field:.1f} µT at the "
                f"log's place (a wrong scale, or a compass reading something other than the Earth's field)"
            )
    return None


def check_measuring(mag, expected, *, remedy: str | None = None) -> None:
    """Refuse a compass that does not measure (:func:`not_measuring`), with the checks a person can make.

    Raises
    ------
    CompassNotMeasuringError
        With the cause and ``remedy`` (by default: its wiring, that it is enabled, a magnet nearby).
    """
    why = not_measuring(mag, expected)
    if why is None:
        return
    remedy = remedy or "check its wiring and that it is enabled, and keep magnets and power wires away from it"
    raise CompassNotMeasuringError(f"this compass does not measure: {why}. Nothing was fitted to it; {remedy}")
