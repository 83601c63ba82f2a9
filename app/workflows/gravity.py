"""The reference magnitude a calibration of an accelerometer is fitted to."""

from __future__ import annotations

from app.calibration import STANDARD_GRAVITY, normal_gravity


def reference_gravity(
    unit: str, gravity: float | None = None, latitude_deg: float | None = None, height_m: float | None = None
) -> tuple[float, list[str]]:
    """Reference magnitude in the calibrated output unit, and notes about how it was chosen.

    ``unit: g`` calibrates into g, so the magnitude is 1; otherwise an explicit ``gravity`` wins,
    then local normal gravity from ``latitude_deg`` (and ``height_m``), then 9.80665 m/s².
    """
    notes: list[str] = []
    if unit == "g":
        if gravity is not None or latitude_deg is not None:
            notes.append("readings in g calibrate into g with reference magnitude 1: gravity/latitude_deg ignored")
        return 1.0, notes
    if gravity is not None:
        if latitude_deg is not None:
            notes.append("both gravity and latitude_deg given: the explicit gravity is used")
        return float(gravity), notes
    if latitude_deg is not None:
        return normal_gravity(latitude_deg, 0.0 if height_m is None else height_m), notes
    if height_m is not None:
        notes.append("height_m without latitude_deg is ignored: give latitude_deg too")
    return STANDARD_GRAVITY, notes
