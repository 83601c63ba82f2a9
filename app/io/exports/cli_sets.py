"""Betaflight's and INAV's CLI ``set`` lines: the accelerometer's zero (and INAV's gain).

Both firmwares hold the accelerometer's calibration in the sensor's raw counts, before the board's alignment:

* Betaflight (``src/main/sensors/acceleration.c``, the update that subtracts
  ``accelerationRuntime.accelerationTrims->raw``): ``accADC_i = m_i − acc_calibration_i``, in counts of ``acc_1G``
  per g; 4.0 and later store it as ``set acc_calibration = x,y,z`` (a real 4.0.5 ``diff all`` has three values;
  4.3 added a fourth, 1 once calibrated), 3.x as ``acc_zero_x``, ``acc_zero_y``, ``acc_zero_z``. Betaflight holds
  no scale.
* INAV (``src/main/sensors/acceleration.c``, ``applyAccelerationZero``, before ``applySensorAlignment``):
  ``accADC_i = (m_i − acczero_i) · accgain_i / 4096``, counts of ``acc_1G`` per g: a gain of 4096 is 1.0
  (``performAcclerationCalibration``: ``accGain = lrintf(scale · 4096)``).

``acc_1G`` is the driver's: 2048 counts per g for the parts both firmwares run at ±16 g (``acc->acc_1G = 512 * 4``
in INAV's drivers of the MPU-6000, MPU-6500, ICM-42605, LSM6DSL, ASM330LHH and Betaflight's alike); INAV's
MPU-6050 of an early revision has 1024, and a part with another ``acc_1G`` needs its numbers scaled. In trical's
m/s², ``o = zero · 9.80665 / acc_1G`` and ``M = diag(gain / 4096)`` (Betaflight: ``M = I``). The values are whole
numbers: a zero is rounded to 1 / 2048 g (4.8 mm/s²), a gain to 1 / 4096 (0.024 %).
"""

from __future__ import annotations

import numpy as np

from ...calibration.shared.gravity import STANDARD_GRAVITY
from ..errors import ExportError
from .common import Export, accelerometer_correction, describe, only_compass, result_class
from .params import offset_scale

ACC_1G = 2048
"""Counts per g of the parts Betaflight and INAV run at ±16 g (their drivers' ``acc_1G = 512 * 4``)."""
INAV_GAIN_ONE = 4096
"""INAV's ``accgain`` of 1.0."""
INT16 = (-32768, 32767)
"""The range of a zero (an int16 in both firmwares' parameter groups)."""
INAV_GAIN_RANGE = (1, 8192)
"""INAV's ``accgain_*`` range (its settings table)."""
ACCELEROMETER_ONLY = ("betaflight", "inav")
"""The formats of this module: they carry an accelerometer's correction alone (both firmwares hold their compass in
the magnetometer's raw counts, whose scale a compass calibration does not give), so a compass's calibration is
refused them."""

BETAFLIGHT_SOURCE = "src/main/sensors/acceleration.c (accelerationTrims: accADC = m - acc_calibration)"
INAV_SOURCE = "src/main/sensors/acceleration.c (applyAccelerationZero: accADC = (m - acczero) * accgain / 4096)"


def counts_of(offset_mps2) -> np.ndarray:
    """An offset in m/s² as the firmwares' counts (``acc_1G`` per g)."""
    return np.asarray(offset_mps2, dtype=float) / STANDARD_GRAVITY * ACC_1G


def offset_and_scale(body: dict, target: str) -> tuple[np.ndarray, np.ndarray, str]:
    """The accelerometer's offset (m/s²) and per-axis scale for ``target``: an imported calibration's own numbers,
    else the firmware's model fitted on the correction as the ArduPilot export fits it (app.io.exports.params), and
    a line saying which.

    Raises
    ------
    ExportError
        A compass's calibration (the firmware holds it in the magnetometer's raw counts), or one in counts.
    """
    if only_compass(body):
        raise ExportError(
            f"{target} holds a compass's calibration in the magnetometer's raw counts, whose scale a compass "
            "calibration does not give, and trical writes only the accelerometer's: use the json export"
        )
    if result_class(body).EXACT_PARAMETERS:
        c = accelerometer_correction(body)
        if body.get("unit") != "m/s^2":
            raise ExportError(f"{target} takes an accelerometer's calibration in m/s²: use the json export")
        return np.asarray(c.o, dtype=float), np.diag(c.M).astype(float), "the imported calibration's own numbers"
    p = offset_scale(body, target)
    return (
        np.asarray(p["offset_mps2"], dtype=float),
        np.asarray(p["scale"], dtype=float),
        "fitted on the calibration as ArduPilot's own calibration fits them (offset and scale per axis)",
    )


def _whole(values, names, limits, target) -> list[int]:
    lo, hi = limits
    out = [round(float(v)) for v in values]
    bad = [f"{n} = {v}" for n, v in zip(names, out) if not lo <= v <= hi]
    if bad:
        raise ExportError(
            f"{target} would not accept this calibration: {', '.join(bad)} outside {lo}…{hi}: check the log's unit, "
            "or use the json export"
        )
    return out


def to_betaflight(body: dict) -> Export:
    """Betaflight CLI: ``set acc_calibration = x,y,z,1`` (4.3 and later; 4.0 to 4.2 take the first three), in counts
    at 2048 per g."""
    offset, scale, how = offset_and_scale(body, "Betaflight")
    zero = _whole(counts_of(offset), [f"acc_calibration {a}" for a in "xyz"], INT16, "Betaflight")
    c = accelerometer_correction(body)
    comments = describe(body, c.source) + [
        f"Betaflight subtracts a zero per axis in the sensor's raw counts ({BETAFLIGHT_SOURCE}),",
        f"  counts of acc_1G = {ACC_1G} per g (the parts run at +-16 g: MPU-6000, MPU-6500, ICM-42688-P, BMI270);",
        "  another part's acc_1G needs these numbers scaled by acc_1G / 2048.",
        f"Offsets {how}.",
        "Not carried: Betaflight holds no scale (scales "
        + ", ".join(f"{v:.5f}" for v in scale)
        + " are dropped) and no cross-axis terms; the compass's calibration is not written (Betaflight holds it in "
        "the magnetometer's raw counts, whose scale a calibration in uT does not give).",
        f"Rounded to whole counts: 1/{ACC_1G} g = {STANDARD_GRAVITY / ACC_1G * 1000:.2f} mm/s^2 at most half of that.",
        "Betaflight 4.0 to 4.2: set acc_calibration to the first three numbers; 3.x: acc_zero_x/y/z.",
    ]
    lines = [f"# {c}" for c in comments]
    lines.append(f"set acc_calibration = {zero[0]},{zero[1]},{zero[2]},1")
    lines.append("save")
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_betaflight.txt")


def to_inav(body: dict) -> Export:
    """INAV CLI: ``set acczero_x`` … (counts at 2048 per g) and ``set accgain_x`` … (4096 = 1.0)."""
    offset, scale, how = offset_and_scale(body, "INAV")
    zero = _whole(counts_of(offset), [f"acczero_{a}" for a in "xyz"], INT16, "INAV")
    gain = _whole(scale * INAV_GAIN_ONE, [f"accgain_{a}" for a in "xyz"], INAV_GAIN_RANGE, "INAV")
    c = accelerometer_correction(body)
    comments = describe(body, c.source) + [
        f"INAV corrects per axis in the sensor's raw counts ({INAV_SOURCE}),",
        f"  counts of acc_1G = {ACC_1G} per g (the parts run at +-16 g); gain {INAV_GAIN_ONE} = 1.0.",
        f"Offsets and scales {how}.",
        "Not carried: cross-axis terms; the compass's calibration is not written (INAV's magzero/maggain are in the "
        "magnetometer's raw counts, whose scale a calibration in uT does not give).",
        f"Rounded to whole numbers: a zero to 1/{ACC_1G} g, a gain to 1/{INAV_GAIN_ONE}.",
    ]
    lines = [f"# {c}" for c in comments]
    lines += [f"set acczero_{a} = {v}" for a, v in zip("xyz", zero)]
    lines += [f"set accgain_{a} = {v}" for a, v in zip("xyz", gain)]
    lines.append("save")
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_inav.txt")
