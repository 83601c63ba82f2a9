"""Flight-controller compass parameters: ArduPilot ``COMPASS_OFS/DIA/ODI_*``, PX4 ``CAL_MAG0_*``.

trical's compass correction is ``h = M (m − b)`` in µT with M symmetric (app.calibration.magnetometer).
Both firmwares apply a full symmetric matrix, so nothing is dropped; they differ in sign and unit:

* ArduPilot, ``libraries/AP_Compass/AP_Compass_Backend.cpp``, ``AP_Compass_Backend::correct_field``:
  ``mag += offsets`` then ``mag = mat * mag`` with ``mat = [[DIA_X, ODI_X, ODI_Y], [ODI_X, DIA_Y, ODI_Z],
  [ODI_Y, ODI_Z, DIA_Z]]``, the field in milligauss (1 mG = 0.1 µT). Hence
  ``COMPASS_OFS = −10 b`` (mG), ``COMPASS_DIA = diag M``, ``COMPASS_ODI = (M_xy, M_xz, M_yz)``.
  ArduPilot's own calibrator accepts a fit with |offset| < ``COMPASS_OFFS_MAX`` (1800 mG by
  default), diagonals in 0.2…5 and |off-diagonals| < 1
  (``libraries/AP_Compass/CompassCalibrator.cpp``, ``CompassCalibrator::fit_acceptable``); the export
  refuses what it would refuse.
* PX4, ``src/lib/sensor_calibration/Magnetometer.hpp``, ``Magnetometer::Correct`` (the matrix built in ``Magnetometer.cpp``, ``ParametersUpdate``):
  ``_rotation * (_scale * (data − _offset))`` with ``_scale = [[XSCALE, XODIAG, YODIAG], [XODIAG,
  YSCALE, ZODIAG], [YODIAG, ZODIAG, ZSCALE]]``, the field in gauss (1 G = 100 µT). Hence
  ``CAL_MAG0_xOFF = b / 100`` (G), ``CAL_MAG0_xSCALE = diag M``, ``CAL_MAG0_xODIAG = (M_xy, M_xz, M_yz)``.

Both correct the field after the board's rotation (ArduPilot's ``rotate_field``; PX4's ``_rotation``
is applied last, so its parameters are in the sensor frame): the numbers fit when the logged axes are
the ones the firmware sees (ArduPilot's ``COMPASS_ORIENT`` / ``AHRS_ORIENTATION`` at none).
"""

from __future__ import annotations

import numpy as np

from .errors import ExportError
from .export_common import Export, describe, sensor_corrections, unit_label

MGAUSS_PER_UT = 10.0
GAUSS_PER_UT = 0.01
ARDUPILOT_OFFSET_MAX_MGAUSS = 1800.0
ARDUPILOT_DIAGONAL_RANGE = (0.2, 5.0)
ARDUPILOT_OFFDIAGONAL_MAX = 1.0
ARDUPILOT_SOURCE = "libraries/AP_Compass/AP_Compass_Backend.cpp (AP_Compass_Backend::correct_field)"
ARDUPILOT_ACCEPT_SOURCE = "libraries/AP_Compass/CompassCalibrator.cpp (CompassCalibrator::fit_acceptable)"
PX4_SOURCE = "src/lib/sensor_calibration/Magnetometer.hpp (Magnetometer::Correct) and Magnetometer.cpp (ParametersUpdate)"
PX4_SCALE_RANGE = (0.1, 3.0)


def _number(v: float) -> str:
    return f"{v:.9g}"  # 9 significant digits round-trip the firmware's float32 parameters


def compass_parameters(body: dict, target: str) -> dict:
    """The magnetometer's ``M`` and ``b`` (µT) of a compass calibration, checked for firmware.

    Raises
    ------
    ExportError
        A calibration without a magnetometer model, of raw counts, or one that must not be applied.
    """
    mag = [c for c in sensor_corrections(body) if c.sensor == "mag"]
    if not mag:
        raise ExportError(f"this calibration has no magnetometer model for {target}'s compass parameters")
    c = mag[0]
    if body.get("unit") != "uT":
        raise ExportError(f"{target} applies its compass parameters to readings its drivers give in physical units; "
                          f"this calibration maps readings in {unit_label(body.get('unit'))}, whose scale is unknown: "
                          "upload the log again with chip (the magnetometer's part and range, e.g. ak8963-16bit, "
                          "qmc5883l-2g, hmc5883l-1090, lis3mdl-4g) or mag_unit (uT, nT, gauss), and calibrate that")
    if not body.get("ok", False):
        raise ExportError(f"this calibration failed its checks ({'; '.join(body.get('reasons') or [])}): it must not "
                          f"be written to {target}; fix what the reasons say and calibrate again")
    M = np.asarray(c.M, dtype=float)
    return {"M": M, "b": np.asarray(c.o, dtype=float), "diagonal": np.diag(M).copy(),
            "offdiagonal": np.array([M[0, 1], M[0, 2], M[1, 2]]), "source": c.source}


def _header(body: dict, p: dict, lines: list[str]) -> list[str]:
    field = (body.get("metrics") or {}).get("field_ut")
    comments = describe(body, p["source"]) + lines + [
        f"calibrated field magnitude {field:.2f} uT" if field else "calibrated field magnitude: estimated",
        "Axes are those of the logged data: the numbers fit the firmware only if they are the compass's axes "
        "as the firmware sees them (no extra orientation).",
    ]
    return [f"# {c}" for c in comments]


def to_ardupilot_compass(body: dict) -> Export:
    """ArduPilot parameter file: ``COMPASS_OFS_X/Y/Z`` (mG), ``COMPASS_DIA_*``, ``COMPASS_ODI_*``, ``COMPASS_SCALE``."""
    p = compass_parameters(body, "ArduPilot")
    offsets = -MGAUSS_PER_UT * p["b"]
    problems = [f"COMPASS_OFS_{a} = {v:.0f} mGauss is beyond ±{ARDUPILOT_OFFSET_MAX_MGAUSS:g}"
                for a, v in zip("XYZ", offsets) if abs(v) >= ARDUPILOT_OFFSET_MAX_MGAUSS]
    lo, hi = ARDUPILOT_DIAGONAL_RANGE
    problems += [f"COMPASS_DIA_{a} = {v:.4g} is outside {lo:g}…{hi:g}" for a, v in zip("XYZ", p["diagonal"])
                 if not lo < v < hi]
    problems += [f"COMPASS_ODI_{a} = {v:.4g} is beyond ±1" for a, v in zip("XYZ", p["offdiagonal"])
                 if abs(v) >= ARDUPILOT_OFFDIAGONAL_MAX]
    if problems:
        raise ExportError("ArduPilot would not accept this compass calibration: " + "; ".join(problems)
                          + f" ({ARDUPILOT_ACCEPT_SOURCE}); use the json or c export")
    lines = _header(body, p, [
        f"ArduPilot applies, in milligauss ({ARDUPILOT_SOURCE}):",
        "  mag += COMPASS_OFS; mag = [[DIA_X, ODI_X, ODI_Y], [ODI_X, DIA_Y, ODI_Z], [ODI_Y, ODI_Z, DIA_Z]] * mag",
        "  so COMPASS_OFS = -b (in mGauss, 1 uT = 10 mGauss) and DIA/ODI = M; COMPASS_SCALE 1 leaves M as it is.",
    ])
    lines += [f"COMPASS_OFS_{a} {_number(v)}" for a, v in zip("XYZ", offsets)]
    lines += [f"COMPASS_DIA_{a} {_number(v)}" for a, v in zip("XYZ", p["diagonal"])]
    lines += [f"COMPASS_ODI_{a} {_number(v)}" for a, v in zip("XYZ", p["offdiagonal"])]
    lines.append("COMPASS_SCALE 1")
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_ardupilot.parm")


def to_px4_compass(body: dict) -> Export:
    """PX4 ``param set`` lines: ``CAL_MAG0_xOFF`` (gauss), ``CAL_MAG0_xSCALE``, ``CAL_MAG0_xODIAG``."""
    p = compass_parameters(body, "PX4")
    lo, hi = PX4_SCALE_RANGE
    bad = [f"CAL_MAG0_{a}SCALE = {v:.4g}" for a, v in zip("XYZ", p["diagonal"]) if not lo <= v <= hi]
    if bad:
        raise ExportError(f"this compass calibration is not a magnetometer's: {', '.join(bad)} outside {lo:g}…{hi:g}: "
                          "check the log's unit, or use the json export")
    lines = _header(body, p, [
        f"PX4 applies, in gauss ({PX4_SOURCE}):",
        "  corrected = R * (S * (data - CAL_MAG0_OFF)), S = [[XSCALE, XODIAG, YODIAG], [XODIAG, YSCALE, ZODIAG], "
        "[YODIAG, ZODIAG, ZSCALE]]",
        "  so CAL_MAG0_xOFF = b (in gauss, 1 uT = 0.01 G) and S = M.",
        "Set CAL_MAG0_ID to the magnetometer's device id: PX4 uses the calibration slot whose id matches.",
    ])
    lines += [f"param set CAL_MAG0_{a}OFF {_number(v)}" for a, v in zip("XYZ", GAUSS_PER_UT * p["b"])]
    lines += [f"param set CAL_MAG0_{a}SCALE {_number(v)}" for a, v in zip("XYZ", p["diagonal"])]
    lines += [f"param set CAL_MAG0_{a}ODIAG {_number(v)}" for a, v in zip("XYZ", p["offdiagonal"])]
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_px4.txt")
