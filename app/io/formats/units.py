"""Unit and gravity checks that look at the data: inferring g vs m/s² vs LSB, refusing linear acceleration."""

from __future__ import annotations

import numpy as np

from ..errors import LogFormatError

STANDARD_GRAVITY = 9.80665
LINEAR_FRACTION = 0.25
"""A log whose median norm is below this fraction of g holds no gravity (linear acceleration)."""


def median_norm(acc: np.ndarray) -> float:
    sub = acc[: 200_000]
    return float(np.median(np.linalg.norm(sub, axis=1)))


def infer_acc_unit(acc: np.ndarray) -> str | None:
    """``g``, ``m/s^2`` or ``raw`` when the median norm leaves no doubt; None otherwise.

    A still or slowly turned device reads about 1 g: a median norm of 0.6–1.6 is in g, 6–14 is in
    m/s², and integer readings above 50 are counts of an ADC (LSB).
    """
    norm = median_norm(acc)
    if 0.6 <= norm <= 1.6:
        return "g"
    if 6.0 <= norm <= 14.0:
        return "m/s^2"
    sub = acc[: 10_000]
    if norm > 50 and np.allclose(sub, np.round(sub)):
        return "raw"
    return None


def refuse_linear_acceleration(acc: np.ndarray, unit: str, name: str, hint: str = "") -> None:
    """Refuse a log whose readings hold no gravity (a linear-acceleration / user-acceleration export)."""
    if unit not in ("g", "m/s^2") or len(acc) == 0:
        return
    g = 1.0 if unit == "g" else STANDARD_GRAVITY
    norm = median_norm(acc)
    if norm < LINEAR_FRACTION * g:
        if unit == "m/s^2" and 0.6 <= norm <= 1.6:
            raise LogFormatError(
                f"the readings of {name} have a median norm of {norm:.3g}, about 1 g, but their unit is m/s^2: "
                "if they are in g, give acc_unit=g (or name the unit in the header, e.g. acc_x (g))"
            )
        raise LogFormatError(
            f"{name} holds linear acceleration (gravity removed): its median norm is {norm:.3g} {unit}, "
            f"not about {g:g} {unit}. Calibration needs the raw accelerometer including gravity"
            + (f": {hint}" if hint else ": export 'acceleration including gravity' instead")
        )


def apply_lsb_per_g(acc: np.ndarray, unit: str, lsb_per_g: float | None) -> tuple[np.ndarray, str, list[str]]:
    """Convert counts to g with the sensor's sensitivity (LSB per g, e.g. 16384 for ±2 g on 16 bits)."""
    if lsb_per_g is None:
        return acc, unit, []
    if not (np.isfinite(lsb_per_g) and lsb_per_g > 0):
        raise LogFormatError(f"lsb_per_g must be a positive number (e.g. 16384 for ±2 g on 16 bits); got {lsb_per_g}")
    if unit != "raw":
        raise LogFormatError(
            f"lsb_per_g={lsb_per_g:g} converts counts (LSB) to g, but the accelerometer unit is {unit}: "
            "leave lsb_per_g out, or give acc_unit=raw for readings in counts"
        )
    return acc / lsb_per_g, "g", [f"readings in LSB divided by {lsb_per_g:g} LSB per g"]
