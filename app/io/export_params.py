"""Flight-controller parameter exports: ArduPilot ``INS_ACCOFFS_*``/``INS_ACCSCAL_*``, PX4 ``CAL_ACC0_*``
(a compass calibration's ``COMPASS_*`` and ``CAL_MAG0_*``: app.io.export_compass).

Both firmwares correct each accelerometer axis with an offset and a scale only, in the sensor
frame, readings in m/s², before rotating into the body frame:

* ArduPilot, ``libraries/AP_InertialSensor/AP_InertialSensor_Backend.cpp``,
  ``AP_InertialSensor_Backend::_rotate_and_correct_accel``: ``accel -= _accel_offset`` then
  ``accel.x *= accel_scale.x`` (and y, z) — ``a_i = INS_ACCSCAL_i · (m_i − INS_ACCOFFS_i)``.
  Accepted ranges: ``INS_ACCOFFS_*`` −3.5…3.5 m/s/s and ``INS_ACCSCAL_*`` 0.8…1.2
  (``@Range`` in ``libraries/AP_InertialSensor/AP_InertialSensor_Params.cpp``; the same scale
  bounds in ``libraries/AP_AccelCal/AccelCalibrator.cpp``, ``AccelCalibrator::accept_result``).
* PX4, ``src/lib/sensor_calibration/Accelerometer.hpp``, ``Accelerometer::Correct``:
  ``_rotation * ((data - _thermal_offset - _offset).emult(_scale))`` —
  ``a_i = CAL_ACC0_iSCALE · (m_i − CAL_ACC0_iOFF)`` (thermal offset zero without thermal calibration).

A wizard session's calibration with a ``gyroscope_bias`` adds ArduPilot's ``INS_GYROFFS_X/Y/Z`` in rad/s
(``@Units: rad/s`` in ``AP_InertialSensor_Params.cpp``): ``_rotate_and_correct_gyro`` in the same backend
file does ``gyro -= _gyro_offset`` in the sensor frame, so ``w_i = m_i − INS_GYROFFS_i``.

trical's correction is ``a = M (m − o)``; the export keeps ``o`` and the diagonal ``D`` of ``M``.  The
dropped off-diagonal terms leave a residual ``(M − D)(m − o) = (I − D M⁻¹) a``, whose largest value
over readings of magnitude g is ``‖I − D M⁻¹‖₂ · g``: the export's comment header reports it, overall
and per axis.
"""

from __future__ import annotations

import numpy as np

from .errors import ExportError
from .log import ACC_PHYSICAL_UNITS
from .export_common import Export, accelerometer_correction, describe, only_compass
from ..calibration.gravity import STANDARD_GRAVITY
from .export_compass import to_ardupilot_compass, to_px4_compass

# The standard gravity is also ArduPilot's GRAVITY_MSS and PX4's CONSTANTS_ONE_G (9.80665 m/s²).

ARDUPILOT_OFFSET_RANGE = (-3.5, 3.5)
ARDUPILOT_SCALE_RANGE = (0.8, 1.2)
ARDUPILOT_SOURCE = "libraries/AP_InertialSensor/AP_InertialSensor_Backend.cpp (_rotate_and_correct_accel)"
ARDUPILOT_GYRO_SOURCE = "libraries/AP_InertialSensor/AP_InertialSensor_Backend.cpp (_rotate_and_correct_gyro)"
ARDUPILOT_RANGE_SOURCE = "libraries/AP_InertialSensor/AP_InertialSensor_Params.cpp (@Range)"
PX4_SOURCE = "src/lib/sensor_calibration/Accelerometer.hpp (Accelerometer::Correct)"
PX4_SCALE_RANGE = (0.1, 3.0)
"""min/max of CAL_ACCn_xSCALE in PX4's parameter reference (offsets have none); read from a table
generated from PX4's parameter metadata, not from PX4's source itself."""


def offset_scale(body: dict, target: str) -> dict:
    """Per-axis offset (m/s²) and scale of a calibration, and the residual of the dropped terms.

    Parameters
    ----------
    body : dict
        A stored calibration of an affine-in-the-reading model.
    target : str
        Firmware name, for messages.

    Returns
    -------
    dict
        ``offset_mps2``, ``scale`` (arrays of 3), ``residual_max`` (worst case over readings of
        magnitude ``gravity``, in the calibration's output unit), ``residual_axis`` (per axis),
        ``residual_max_mps2`` and ``output_unit``.

    Raises
    ------
    ExportError
        Calibrations of readings in counts (the firmware applies its parameters to m/s²).
    """
    correction = accelerometer_correction(body)
    M, o = correction.M, correction.o
    unit = body.get("unit")
    if unit not in ACC_PHYSICAL_UNITS:
        raise ExportError(
            f"{target} applies its offsets and scales to readings its drivers already give in m/s², but this "
            f"calibration maps readings in counts, whose scale is unknown: upload the log again with chip (the "
            f"accelerometer's part and range, e.g. mpu6050-2g) or lsb_per_g (counts per g, e.g. 16384), and "
            f"calibrate that to export it for {target}"
        )
    to_mps2 = 1.0 if unit == "m/s^2" else STANDARD_GRAVITY
    D = np.diag(np.diag(M))
    R = np.eye(3) - D @ np.linalg.inv(M)
    gravity = float(body.get("gravity") or (1.0 if unit == "g" else STANDARD_GRAVITY))
    residual_max = float(np.linalg.norm(R, 2) * gravity)
    return {
        "offset_mps2": o * to_mps2,
        "scale": np.diag(M).copy(),
        "residual_max": residual_max,
        "residual_axis": np.linalg.norm(R, axis=1) * gravity,
        "residual_max_mps2": residual_max * to_mps2,
        "output_unit": body.get("output_unit"),
        "matrix": M,
        "source": correction.source,
    }


def _number(v: float) -> str:
    # 9 significant digits round-trip the firmware's float32 parameters.
    return f"{v:.9g}"


def _residual_lines(p: dict, target: str) -> list[str]:
    unit = p["output_unit"]
    axis = ", ".join(f"{a} {v:.6g}" for a, v in zip("xyz", p["residual_axis"]))
    return [
        f"{target} has no cross-axis terms: the off-diagonal terms of M are dropped.",
        "residual (trical minus this export) = (I - D M^-1) a, D = diag(M); over readings of magnitude g:",
        f"dropped_terms_residual_max: {p['residual_max']:.6g} {unit} "
        f"({p['residual_max_mps2'] / STANDARD_GRAVITY * 1000:.4g} mg)",
        f"dropped_terms_residual_per_axis: {axis} {unit}",
        "Axes are those of the logged data: the numbers fit the firmware only if they are the IMU's sensor axes.",
    ]


def to_ardupilot(body: dict) -> Export:
    """ArduPilot parameter file: ``INS_ACCOFFS_X/Y/Z`` (m/s²) and ``INS_ACCSCAL_X/Y/Z``, and ``INS_GYROFFS_X/Y/Z``
    (rad/s) when the calibration has a ``gyroscope_bias``.

    Raises
    ------
    ExportError
        Counts calibrations, and values outside ArduPilot's accepted ranges (the reason named).
    """
    if only_compass(body):
        return to_ardupilot_compass(body)
    p = offset_scale(body, "ArduPilot")
    problems = []
    lo, hi = ARDUPILOT_OFFSET_RANGE
    for axis, v in zip("XYZ", p["offset_mps2"]):
        if not lo <= v <= hi:
            problems.append(f"INS_ACCOFFS_{axis} = {v:.4g} m/s/s is outside {lo:g}…{hi:g} m/s/s")
    lo, hi = ARDUPILOT_SCALE_RANGE
    for axis, v in zip("XYZ", p["scale"]):
        if not lo <= v <= hi:
            problems.append(f"INS_ACCSCAL_{axis} = {v:.4g} is outside {lo:g}…{hi:g}")
    if problems:
        raise ExportError(
            "ArduPilot would not accept this calibration: " + "; ".join(problems)
            + f" (ArduPilot's ranges, {ARDUPILOT_RANGE_SOURCE}). Check the log's unit (g read as m/s² or the "
            "reverse gives such values) and that the axes are the IMU's; otherwise use the json or c export"
        )
    comments = describe(body, p["source"]) + [
        f"ArduPilot applies, per axis in the sensor frame ({ARDUPILOT_SOURCE}):",
        "  a_i = INS_ACCSCAL_i * (m_i - INS_ACCOFFS_i), m and INS_ACCOFFS in m/s/s",
    ] + _residual_lines(p, "ArduPilot")
    gyro = body.get("gyroscope_bias")
    if gyro:
        half = ", ".join(f"{a} {v:.3g}" for a, v in zip("XYZ", gyro["half_width_rad_s"]))
        comments += [
            f"Gyroscope bias over {gyro['count']} still captures, 95 % half-widths {half} rad/s "
            f"(interval from the {gyro['interval_from']}).",
            f"ArduPilot applies, per axis in the sensor frame ({ARDUPILOT_GYRO_SOURCE}):",
            "  w_i = m_i - INS_GYROFFS_i, m and INS_GYROFFS in rad/s",
            "ArduPilot measures INS_GYROFFS again at each boot unless INS_GYR_CAL is 0 (Never).",
        ]
    lines = [f"# {c}" for c in comments]
    lines += [f"INS_ACCOFFS_{a} {_number(v)}" for a, v in zip("XYZ", p["offset_mps2"])]
    lines += [f"INS_ACCSCAL_{a} {_number(v)}" for a, v in zip("XYZ", p["scale"])]
    if gyro:
        lines += [f"INS_GYROFFS_{a} {_number(v)}" for a, v in zip("XYZ", gyro["rad_s"])]
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_ardupilot.parm")


def to_px4(body: dict) -> Export:
    """PX4 parameters ``CAL_ACC0_XOFF``… (m/s²) and ``CAL_ACC0_XSCALE``…, as ``param set`` lines."""
    if only_compass(body):
        return to_px4_compass(body)
    p = offset_scale(body, "PX4")
    lo, hi = PX4_SCALE_RANGE
    bad = [f"CAL_ACC0_{a}SCALE = {v:.4g}" for a, v in zip("XYZ", p["scale"]) if not lo <= v <= hi]
    if bad:
        raise ExportError(
            f"PX4 would not accept this calibration: {', '.join(bad)} outside its parameter range {lo:g}…{hi:g}"
            + (" (a negative scale means an axis of the log is inverted relative to the sensor)"
               if np.any(p["scale"] < 0) else "")
            + ": check the log's unit and axes, or use the json export"
        )
    comments = describe(body, p["source"]) + [
        f"PX4 applies, per axis in the sensor frame ({PX4_SOURCE}):",
        "  a_i = CAL_ACC0_iSCALE * (m_i - CAL_ACC0_iOFF), m and CAL_ACC0_iOFF in m/s^2",
        "Set CAL_ACC0_ID to the accelerometer's device id: PX4 uses the calibration slot whose id matches.",
    ] + _residual_lines(p, "PX4")
    lines = [f"# {c}" for c in comments]
    lines += [f"param set CAL_ACC0_{a}OFF {_number(v)}" for a, v in zip("XYZ", p["offset_mps2"])]
    lines += [f"param set CAL_ACC0_{a}SCALE {_number(v)}" for a, v in zip("XYZ", p["scale"])]
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_px4.txt")
