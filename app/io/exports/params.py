"""Flight-controller parameter exports: ArduPilot ``INS_ACCOFFS_*``/``INS_ACCSCAL_*``, PX4 ``CAL_ACC0_*``
(a compass calibration's ``COMPASS_*`` and ``CAL_MAG0_*``: app.io.exports.compass).

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

trical's correction is ``a = M (m − o)``; neither firmware holds its cross-axis terms. The offsets and scales
exported are fitted on the calibration's own still readings as ArduPilot's own calibration fits them, to the
magnitude ``|S (m − b)| = g`` (app.calibration.still.firmware_model), not taken from ``M``'s diagonal: ``M`` also turns
the sensor's axes into the frame the poses define (the table's tilt, the board's mounting), which the
firmware's level calibration takes. The comment header gives the norm error the firmware reaches with these
numbers on the readings, beside the raw one and trical's full model's, and splits what it cannot hold of ``M``
into that rotation (degrees) and the axes' non-orthogonality (mg).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...calibration.shared.errors import CalibrationError
from ...calibration.shared.gravity import STANDARD_GRAVITY
from ...calibration.still.firmware_model import offset_scale_fit
from ..errors import ExportError
from ..log import ACC_PHYSICAL_UNITS
from ..plural import counted
from .common import (
    Export,
    accelerometer_correction,
    accelerometer_readings,
    describe,
    only_compass,
    result_class,
    sensor_corrections,
)
from .compass import GAUSS_PER_UT, MGAUSS_PER_UT, to_ardupilot_compass, to_px4_compass

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


@dataclass(frozen=True)
class Level:
    """A firmware's own level calibration: its name, where a person starts it, the parameters it sets (and
    what they hold), the largest tilt they take in degrees (None: no bound known)."""

    name: str
    where: str
    params: str
    holds: str
    bound_deg: float | None


LEVEL = {
    "ArduPilot": Level(
        "ArduPilot's level calibration",
        "Mission Planner: Calibrate Level",
        "AHRS_TRIM_X and AHRS_TRIM_Y",
        "roll and pitch, in rad, within +-0.1745 = +-10 deg: @Range in libraries/AP_AHRS/AP_AHRS.cpp",
        10.0,
    ),
    "PX4": Level(
        "PX4's level horizon calibration",
        "QGroundControl: Sensors > Level Horizon",
        "SENS_BOARD_X_OFF and SENS_BOARD_Y_OFF",
        "roll and pitch, in degrees",
        None,
    ),
}


def _mg(v: float) -> str:
    """A figure in mg for a sentence: two decimals under 10 mg, one above."""
    return f"{v:.{2 if v < 10 else 1}f}"


def offset_scale(body: dict, target: str) -> dict:
    """Per-axis offset (m/s²) and scale of the firmware's model fitted on a calibration's still readings, and
    what it reaches on them (app.calibration.still.firmware_model).

    Parameters
    ----------
    body : dict
        A stored calibration of an affine-in-the-reading model.
    target : str
        Firmware name, for messages.

    Returns
    -------
    dict
        ``offset_mps2``, ``scale`` (arrays of 3), ``fit``
        (:class:`~app.calibration.still.firmware_model.OffsetScaleFit`, in the calibration's unit), ``gravity`` (in
        that unit), ``output_unit`` and ``source``.

    Raises
    ------
    ExportError
        Calibrations of readings in counts (the firmware applies its parameters to m/s²).
    """
    correction = accelerometer_correction(body)
    unit = body.get("unit")
    if unit not in ACC_PHYSICAL_UNITS:
        raise ExportError(
            f"{target} applies its offsets and scales to readings its drivers already give in m/s², but this "
            f"calibration maps readings in counts, whose scale is unknown: upload the log again with chip (the "
            f"accelerometer's part and range, e.g. mpu6050-2g) or lsb_per_g (counts per g, e.g. 16384), and "
            f"calibrate that to export it for {target}"
        )
    to_mps2 = 1.0 if unit == "m/s^2" else STANDARD_GRAVITY
    gravity = float(body.get("gravity") or (1.0 if unit == "g" else STANDARD_GRAVITY))
    try:
        fit = offset_scale_fit(correction.M, correction.o, gravity, accelerometer_readings(body))
    except CalibrationError as exc:
        raise ExportError(f"{exc}: use the json export") from None
    return {
        "offset_mps2": fit.offset * to_mps2,
        "scale": fit.scale,
        "fit": fit,
        "gravity": gravity,
        "output_unit": body.get("output_unit"),
        "source": correction.source,
    }


def firmware_summary(body: dict, target: str) -> dict:
    """What the firmware reaches with its exported offsets and scales, in figures and in words, for the page.

    Returns
    -------
    dict
        ``target``; ``count`` and ``from_readings``; the norm errors in mg (``firmware_max_mg``,
        ``firmware_mean_mg``, ``raw_max_mg``, ``raw_mean_mg``, ``full_max_mg``, ``full_mean_mg``,
        ``any_direction_max_mg``); ``rotation_deg``, ``nonorthogonality_mg``; ``improves`` (the firmware's
        figure below raw's) and ``words`` (one sentence).
    """
    fit = offset_scale(body, target)["fit"]

    def mg(v):
        return float(1000.0 * v)  # relative norm errors to thousandths of g

    out = {
        "target": target,
        "count": fit.count,
        "from_readings": fit.from_readings,
        "firmware_max_mg": mg(fit.norm_error.max()),
        "firmware_mean_mg": mg(fit.norm_error.mean()),
        "raw_max_mg": mg(fit.norm_error_raw.max()),
        "raw_mean_mg": mg(fit.norm_error_raw.mean()),
        "full_max_mg": mg(fit.norm_error_full.max()),
        "full_mean_mg": mg(fit.norm_error_full.mean()),
        "any_direction_max_mg": mg(fit.norm_error_any_direction),
        "rotation_deg": fit.rotation_deg,
        "nonorthogonality_mg": mg(fit.nonorthogonality),
        "improves": fit.improves,
    }
    where = f"on the {counted(fit.count, 'still reading')}" if fit.from_readings else "on readings in 14 directions"
    if not fit.improves:
        out["words"] = (
            f"{target}'s offsets and scales would leave {_mg(out['firmware_max_mg'])} mg {where}, no "
            f"better than raw ({_mg(out['raw_max_mg'])} mg): use the full correction (M and o) instead"
        )
        return out
    exact = " (6 numbers fit 6 readings exactly)" if fit.dof == 0 else ""
    level = LEVEL[target]
    out["words"] = (
        f"With these offsets and scales {target} reaches at most {_mg(out['firmware_max_mg'])} mg {where}{exact} "
        f"and {_mg(out['any_direction_max_mg'])} mg in any direction; raw {_mg(out['raw_max_mg'])} mg, trical's "
        f"full model {_mg(out['full_max_mg'])} mg."
        + (
            f" trical's model also turns the axes {fit.rotation_deg:.1f}° (the table's tilt or the board's "
            f"mounting), which no offset or scale holds: {level.name} takes the tilt ({level.params})."
            if fit.rotation_deg >= 0.05
            else ""
        )
    )
    return out


FIRMWARE_TARGETS = {"ardupilot": "ArduPilot", "px4": "PX4"}
"""The offset-and-scale exports, by format key."""


def firmware_figures(body: dict) -> dict:
    """:func:`firmware_summary` of each offset-and-scale export (by format key) that the calibration gives: none
    for a compass's or a calibration those exports refuse (their own message says why)."""
    out: dict[str, dict] = {}
    try:
        if only_compass(body):
            return out
    except ExportError:
        return out
    for key, target in FIRMWARE_TARGETS.items():
        try:
            out[key] = firmware_summary(body, target)
        except ExportError:
            continue
    return out


def _number(v: float) -> str:
    # 9 significant digits round-trip the firmware's float32 parameters.
    return f"{v:.9g}"


def _fit_lines(p: dict, target: str, formula: str) -> list[str]:
    """The comment lines that say what the firmware reaches with these numbers, and what it cannot hold."""
    fit = p["fit"]

    def mg(v):
        return f"{1000.0 * v:.3f}"  # relative norm errors to thousandths of g

    if fit.from_readings:
        on = f"the calibration's {counted(fit.count, 'still reading')}"
        exact = (
            "6 numbers fit 6 readings exactly, so this figure tests nothing: the figure for any direction "
            "below, or more poses, does"
            if fit.dof == 0
            else f"{counted(fit.dof, 'reading')} more than the 6 numbers"
        )
    else:
        on = (
            "the readings trical's full model puts at magnitude g in 14 directions (the calibration holds fewer than 6)"
        )
        exact = "fitted on those readings"
    level = LEVEL[target]
    tilt = float(np.hypot(*fit.rotation_axes_deg[:2]))
    lines = [
        f"{target} holds an offset and a scale per axis and no cross-axis terms. These are fitted to {on}, as "
        "ArduPilot's own accelerometer calibration fits them (libraries/AP_AccelCal/AccelCalibrator.cpp, "
        "calc_residual: GRAVITY_MSS - |diag(s) (m + offset)|, least squares): to the magnitude |a| = g, which no "
        "tilt of the poses changes.",
        f"Norm error | |a| - g | on {on}, largest and mean ({exact}):",
        f"firmware_norm_error_max_mg: {mg(fit.norm_error.max())}  (this file, {formula})",
        f"firmware_norm_error_mean_mg: {mg(fit.norm_error.mean())}",
        f"raw_norm_error_max_mg: {mg(fit.norm_error_raw.max())}",
        f"raw_norm_error_mean_mg: {mg(fit.norm_error_raw.mean())}",
        f"trical_norm_error_max_mg: {mg(fit.norm_error_full.max())}  (trical's full model, a = M (m - o))",
        f"trical_norm_error_mean_mg: {mg(fit.norm_error_full.mean())}",
        f"firmware_norm_error_any_direction_mg: {mg(fit.norm_error_any_direction)}  (every direction, on readings "
        "trical's full model puts at magnitude g)",
        "What these numbers cannot hold of trical's M = R P (polar decomposition: R a rotation, P symmetric):",
        f"rotation_deg: {fit.rotation_deg:.3f}  (about x {fit.rotation_axes_deg[0]:.3f}, y "
        f"{fit.rotation_axes_deg[1]:.3f}, z {fit.rotation_axes_deg[2]:.3f} deg): the sensor's axes against the "
        "poses' frame - the table's tilt or the board's mounting. It changes no magnitude, so no offset or scale "
        f"holds it: {level.name} ({level.where}) takes its tilt ({tilt:.2f} deg about x and y) into {level.params} "
        f"({level.holds})"
        + (
            f"; beyond {level.bound_deg:g} deg it cannot: mount the board level"
            if level.bound_deg is not None and tilt > level.bound_deg
            else ""
        )
        + ". The turn about z (in the board's plane) is no tilt: it matters only for a board turned on its frame.",
        f"nonorthogonality_mg: {mg(fit.nonorthogonality)}  (largest part of a reading the off-diagonal terms of P "
        f"make, g |I - D P^-1|, D = diag(P); the axes are "
        + ", ".join(f"{n} {v:+.3f}" for n, v in zip(("xy", "xz", "yz"), fit.axis_angles_deg))
        + f" deg off 90): {target} has no term for it.",
        "Axes are those of the logged data: the numbers fit the firmware only if they are the IMU's sensor axes.",
    ]
    return lines


def to_ardupilot(body: dict) -> Export:
    """ArduPilot parameter file: ``INS_ACCOFFS_X/Y/Z`` (m/s²) and ``INS_ACCSCAL_X/Y/Z``, and ``INS_GYROFFS_X/Y/Z``
    (rad/s) when the calibration has a ``gyroscope_bias``.

    Raises
    ------
    ExportError
        Counts calibrations, and values outside ArduPilot's accepted ranges (the reason named).
    """
    if result_class(body).EXACT_PARAMETERS:
        return _exact(body, "ArduPilot")
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
            "ArduPilot would not accept this calibration: "
            + "; ".join(problems)
            + f" (ArduPilot's ranges, {ARDUPILOT_RANGE_SOURCE}). Check the log's unit (g read as m/s² or the "
            "reverse gives such values) and that the axes are the IMU's; otherwise use the json or c export"
        )
    comments = (
        describe(body, p["source"])
        + [
            f"ArduPilot applies, per axis in the sensor frame ({ARDUPILOT_SOURCE}):",
            "  a_i = INS_ACCSCAL_i * (m_i - INS_ACCOFFS_i), m and INS_ACCOFFS in m/s/s",
        ]
        + _fit_lines(p, "ArduPilot", "INS_ACCSCAL_i * (m_i - INS_ACCOFFS_i)")
    )
    gyro = body.get("gyroscope_bias")
    if gyro:
        half = ", ".join(f"{a} {v:.3g}" for a, v in zip("XYZ", gyro["half_width_rad_s"]))
        comments += [
            f"Gyroscope bias over {counted(gyro['count'], 'still capture')}, 95 % half-widths {half} rad/s "
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
    if result_class(body).EXACT_PARAMETERS:
        return _exact(body, "PX4")
    if only_compass(body):
        return to_px4_compass(body)
    p = offset_scale(body, "PX4")
    lo, hi = PX4_SCALE_RANGE
    bad = [f"CAL_ACC0_{a}SCALE = {v:.4g}" for a, v in zip("XYZ", p["scale"]) if not lo <= v <= hi]
    if bad:
        raise ExportError(
            f"PX4 would not accept this calibration: {', '.join(bad)} outside its parameter range {lo:g}…{hi:g}"
            + (
                " (a negative scale means an axis of the log is inverted relative to the sensor)"
                if np.any(p["scale"] < 0)
                else ""
            )
            + ": check the log's unit and axes, or use the json export"
        )
    comments = (
        describe(body, p["source"])
        + [
            f"PX4 applies, per axis in the sensor frame ({PX4_SOURCE}):",
            "  a_i = CAL_ACC0_iSCALE * (m_i - CAL_ACC0_iOFF), m and CAL_ACC0_iOFF in m/s^2",
            "Set CAL_ACC0_ID to the accelerometer's device id: PX4 uses the calibration slot whose id matches.",
        ]
        + _fit_lines(p, "PX4", "CAL_ACC0_iSCALE * (m_i - CAL_ACC0_iOFF)")
    )
    lines = [f"# {c}" for c in comments]
    lines += [f"param set CAL_ACC0_{a}OFF {_number(v)}" for a, v in zip("XYZ", p["offset_mps2"])]
    lines += [f"param set CAL_ACC0_{a}SCALE {_number(v)}" for a, v in zip("XYZ", p["scale"])]
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_px4.txt")


def exact_parameters(body: dict, target: str) -> dict[str, float]:
    """A calibration whose corrections are a firmware's own numbers (an imported one: ``EXACT_PARAMETERS``) as
    ``target``'s parameters, every sensor it holds, each the exact inverse of the importer's reading
    (app.io.imports.ardupilot, app.io.imports.px4): the accelerometer's offset and the diagonal of its ``M``, the
    gyroscope's bias, the compass's ``M`` and hard iron.

    Raises
    ------
    ExportError
        An accelerometer's ``M`` with cross-axis terms, which neither firmware holds.
    """
    params: dict[str, float] = {}
    for c in sensor_corrections(body):
        M, o = np.asarray(c.M, dtype=float), np.asarray(c.o, dtype=float)
        if c.sensor != "mag" and np.any(np.abs(M - np.diag(np.diag(M))) > 0):
            raise ExportError(f"{target} holds no cross-axis terms of the {c.sensor} correction: use the json export")
        if c.sensor == "acc":
            names = (
                ("INS_ACCOFFS_", "INS_ACCSCAL_") if target == "ArduPilot" else ("CAL_ACC0_{}OFF", "CAL_ACC0_{}SCALE")
            )
            for template, values in zip(names, (o, np.diag(M))):
                params.update({_name(template, a): float(v) for a, v in zip("XYZ", values)})
        elif c.sensor == "gyr":
            template = "INS_GYROFFS_" if target == "ArduPilot" else "CAL_GYRO0_{}OFF"
            params.update({_name(template, a): float(v) for a, v in zip("XYZ", o)})
        else:
            off = np.array([M[0, 1], M[0, 2], M[1, 2]])
            if target == "ArduPilot":  # COMPASS_OFS = -10 b (mGauss), DIA/ODI = M (app.io.exports.compass)
                groups: dict[str, np.ndarray] = {
                    "COMPASS_OFS_": -MGAUSS_PER_UT * o,
                    "COMPASS_DIA_": np.diag(M),
                    "COMPASS_ODI_": off,
                }
                params.update({f"{g}{a}": float(v) for g, vs in groups.items() for a, v in zip("XYZ", vs)})
                params["COMPASS_SCALE"] = 1.0
            else:  # CAL_MAG0_xOFF = b / 100 (gauss), xSCALE/xODIAG = M
                groups = {"OFF": GAUSS_PER_UT * o, "SCALE": np.diag(M), "ODIAG": off}
                params.update({f"CAL_MAG0_{a}{g}": float(v) for g, vs in groups.items() for a, v in zip("XYZ", vs)})
    return params


def _name(template: str, axis: str) -> str:
    return template.format(axis) if "{}" in template else template + axis


def _exact(body: dict, target: str) -> Export:
    params = exact_parameters(body, target)
    imported = body.get("read_from") or {}
    comments = describe(body, sensor_corrections(body)[0].source) + [
        f"The numbers {imported.get('firmware') or 'the device'} held ({imported.get('file_kind') or 'imported'}), "
        f"written for {target} as they are: nothing fitted, nothing dropped.",
        f"Frame: {imported.get('frame') or 'as imported'}.",
        "Written as the first instance (INS_ACCOFFS, COMPASS_OFS; CAL_ACC0, CAL_MAG0): rename them for another.",
    ]
    lines = [f"# {c}" for c in comments]
    if target == "ArduPilot":
        lines += [f"{n} {_number(v)}" for n, v in params.items()]
        return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_ardupilot.parm")
    lines += [f"param set {n} {_number(v)}" for n, v in params.items()]
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_px4.txt")
