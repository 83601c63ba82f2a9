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
* PX4, ``src/lib/sensor_calibration/Magnetometer.hpp``, ``Magnetometer::Correct`` (the matrix built in
  ``Magnetometer.cpp``, ``ParametersUpdate``):
  ``_rotation * (_scale * (data − _offset))`` with ``_scale = [[XSCALE, XODIAG, YODIAG], [XODIAG,
  YSCALE, ZODIAG], [YODIAG, ZODIAG, ZSCALE]]``, the field in gauss (1 G = 100 µT). Hence
  ``CAL_MAG0_xOFF = b / 100`` (G), ``CAL_MAG0_xSCALE = diag M``, ``CAL_MAG0_xODIAG = (M_xy, M_xz, M_yz)``.

Both correct the field after the board's rotation (ArduPilot's ``rotate_field``; PX4's ``_rotation``
is applied last, so its parameters are in the sensor frame): the numbers fit when the logged axes are
the ones the firmware sees (ArduPilot's ``COMPASS_ORIENT`` / ``AHRS_ORIENTATION`` at none).

A compass calibrated from a flight log (method ``compass_flight``, :func:`export_flight_compass`) has its own
exports: its model ``h_body = M (Q m_L − b − k p)`` adds the rotation Q and the motors' term, which each
firmware holds in its own frame and unit (:func:`ardupilot_flight_parameters`, :func:`px4_flight_parameters`).
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass

import numpy as np

from app.calibration.shared.rotations import angle_between, euler_matrix, firmware_matrix, nearest_number, rotation_name

from ..errors import ExportError
from .common import JSON_SCHEMA, Export, describe, sensor_corrections, unit_label
from .flight_compass_plot import to_flight_compass_svg

MGAUSS_PER_UT = 10.0
GAUSS_PER_UT = 0.01
ARDUPILOT_OFFSET_MAX_MGAUSS = 1800.0
ARDUPILOT_DIAGONAL_RANGE = (0.2, 5.0)
ARDUPILOT_OFFDIAGONAL_MAX = 1.0
ARDUPILOT_SOURCE = "libraries/AP_Compass/AP_Compass_Backend.cpp (AP_Compass_Backend::correct_field)"
ARDUPILOT_ACCEPT_SOURCE = "libraries/AP_Compass/CompassCalibrator.cpp (CompassCalibrator::fit_acceptable)"
PX4_SOURCE = (
    "src/lib/sensor_calibration/Magnetometer.hpp (Magnetometer::Correct) and Magnetometer.cpp (ParametersUpdate)"
)
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
        raise ExportError(
            f"{target} applies its compass parameters to readings its drivers give in physical units; "
            f"this calibration maps readings in {unit_label(body.get('unit'))}, whose scale is unknown: "
            "upload the log again with chip (the magnetometer's part and range, e.g. ak8963-16bit, "
            "qmc5883l-2g, hmc5883l-1090, lis3mdl-4g) or mag_unit (uT, nT, gauss), and calibrate that"
        )
    if not body.get("ok", False):
        raise ExportError(
            f"this calibration failed its checks ({'; '.join(body.get('reasons') or [])}): it must not "
            f"be written to {target}; fix what the reasons say and calibrate again"
        )
    M = np.asarray(c.M, dtype=float)
    return {
        "M": M,
        "b": np.asarray(c.o, dtype=float),
        "diagonal": np.diag(M).copy(),
        "offdiagonal": np.array([M[0, 1], M[0, 2], M[1, 2]]),
        "source": c.source,
    }


def _header(body: dict, p: dict, lines: list[str]) -> list[str]:
    field = (body.get("metrics") or {}).get("field_ut")
    comments = (
        describe(body, p["source"])
        + lines
        + [
            f"calibrated field magnitude {field:.2f} uT" if field else "calibrated field magnitude: estimated",
            "Axes are those of the logged data: the numbers fit the firmware only if they are the compass's axes "
            "as the firmware sees them (no extra orientation).",
        ]
    )
    return [f"# {c}" for c in comments]


def to_ardupilot_compass(body: dict) -> Export:
    """ArduPilot parameter file: ``COMPASS_OFS_X/Y/Z`` (mG), ``COMPASS_DIA_*``, ``COMPASS_ODI_*``, ``COMPASS_SCALE``."""
    p = compass_parameters(body, "ArduPilot")
    offsets = -MGAUSS_PER_UT * p["b"]
    problems = [
        f"COMPASS_OFS_{a} = {v:.0f} mGauss is beyond ±{ARDUPILOT_OFFSET_MAX_MGAUSS:g}"
        for a, v in zip("XYZ", offsets)
        if abs(v) >= ARDUPILOT_OFFSET_MAX_MGAUSS
    ]
    lo, hi = ARDUPILOT_DIAGONAL_RANGE
    problems += [
        f"COMPASS_DIA_{a} = {v:.4g} is outside {lo:g}…{hi:g}" for a, v in zip("XYZ", p["diagonal"]) if not lo < v < hi
    ]
    problems += [
        f"COMPASS_ODI_{a} = {v:.4g} is beyond ±1"
        for a, v in zip("XYZ", p["offdiagonal"])
        if abs(v) >= ARDUPILOT_OFFDIAGONAL_MAX
    ]
    if problems:
        raise ExportError(
            "ArduPilot would not accept this compass calibration: "
            + "; ".join(problems)
            + f" ({ARDUPILOT_ACCEPT_SOURCE}); use the json or c export"
        )
    lines = _header(
        body,
        p,
        [
            f"ArduPilot applies, in milligauss ({ARDUPILOT_SOURCE}):",
            "  mag += COMPASS_OFS; mag = [[DIA_X, ODI_X, ODI_Y], [ODI_X, DIA_Y, ODI_Z], [ODI_Y, ODI_Z, DIA_Z]] * mag",
            "  so COMPASS_OFS = -b (in mGauss, 1 uT = 10 mGauss) and DIA/ODI = M; COMPASS_SCALE 1 leaves M as it is.",
        ],
    )
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
        raise ExportError(
            f"this compass calibration is not a magnetometer's: {', '.join(bad)} outside {lo:g}…{hi:g}: "
            "check the log's unit, or use the json export"
        )
    lines = _header(
        body,
        p,
        [
            f"PX4 applies, in gauss ({PX4_SOURCE}):",
            "  corrected = R * (S * (data - CAL_MAG0_OFF)), S = [[XSCALE, XODIAG, YODIAG], [XODIAG, YSCALE, ZODIAG], "
            "[YODIAG, ZODIAG, ZSCALE]]",
            "  so CAL_MAG0_xOFF = b (in gauss, 1 uT = 0.01 G) and S = M.",
            "Set CAL_MAG0_ID to the magnetometer's device id: PX4 uses the calibration slot whose id matches.",
        ],
    )
    lines += [f"param set CAL_MAG0_{a}OFF {_number(v)}" for a, v in zip("XYZ", GAUSS_PER_UT * p["b"])]
    lines += [f"param set CAL_MAG0_{a}SCALE {_number(v)}" for a, v in zip("XYZ", p["diagonal"])]
    lines += [f"param set CAL_MAG0_{a}ODIAG {_number(v)}" for a, v in zip("XYZ", p["offdiagonal"])]
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_px4.txt")


# -- the compass calibrated from a flight (method compass_flight) ---------------------------------------------------
#
# trical's flight model, in the frame L the log gives the raw readings in (ArduPilot: the body frame under the
# rotation the firmware applied; PX4: sensor_mag's own frame), is h_body = M (Q m_L − b − k p), µT, with Q a
# firmware rotation L → body, p the current (A) or throttle (0…1). Each firmware's formula below, applied with
# the exported numbers to the raw reading, gives the same h_body (tests/io/test_export_flight_compass.py).

FLIGHT_COMPASS_METHOD = "compass_flight"

FIRMWARE_NAMES = {"ardupilot": "ArduPilot", "px4": "PX4"}
ROTATION_TOLERANCE_DEG = 0.5
"""Largest angle between the rotation found and a firmware's listed rotation for the two to be one: distinct
entries of one table are 7° apart or more (ArduPilot's PITCH_7 and NONE); ArduPilot's and PX4's number 38 differ
by 0.85°, but each export reads its own table."""

ARDUPILOT_MOT_MAX_MGAUSS = 1000.0
ARDUPILOT_INSTANCES = 3
ARDUPILOT_FLIGHT_SOURCE = (
    "libraries/AP_Compass/AP_Compass_Backend.cpp (AP_Compass_Backend::rotate_field, AP_Compass_Backend::correct_field)"
)
ARDUPILOT_RANGE_SOURCE = (
    "COMPASS_OFFS_MAX: libraries/AP_Arming/AP_Arming.cpp (compass checks, 'Compass offsets "
    "too high'); DIA 0.2-5 and |ODI| < 1: libraries/AP_Compass/CompassCalibrator.cpp "
    "(fit_acceptable); MOT -1000..1000 mGauss/A: @Range in libraries/AP_Compass/AP_Compass.cpp"
)
ARDUPILOT_MOTCT = {"throttle": 1, "current": 2}
"""COMPASS_MOTCT: 0 Disabled, 1 Use Throttle, 2 Use Current (@Values in libraries/AP_Compass/AP_Compass.cpp)."""
PX4_FLIGHT_SOURCE = (
    "src/lib/sensor_calibration/Magnetometer.hpp (Magnetometer::Correct), Magnetometer.cpp "
    "(ParametersUpdate), src/modules/sensors/vehicle_magnetometer/VehicleMagnetometer.cpp "
    "(UpdatePowerCompensation)"
)
PX4_COMP_TYPE = {"throttle": 1, "current": 2}
"""CAL_MAG_COMP_TYP: 0 Disabled, 1 Throttle, 2 Current of battery_status instance 0, 3 of instance 1
(MagCompensationType in src/modules/sensors/vehicle_magnetometer/VehicleMagnetometer.hpp)."""
PX4_KILOAMPERE_PER_AMPERE = 1e-3  # VehicleMagnetometer::UpdatePowerCompensation: power = current_a * 0.001 (kA)


@dataclass(frozen=True)
class FlightCompass:
    """The parts of a flight-compass calibration an export needs, checked: ``Q`` (L → body), ``M``, ``b``
    (µT), ``k`` (µT per A or per unit throttle; zeros without a motor model), ``motor`` (None, ``current``,
    ``throttle``), the firmware and instance, ``frame_to_body`` (the rotation the firmware applied) and
    ``stored`` (what the firmware stored; its ``params`` the log's parameters)."""

    firmware: str
    instance: int
    Q: np.ndarray
    M: np.ndarray
    b: np.ndarray
    k: np.ndarray
    motor: str | None
    frame_to_body: np.ndarray
    stored: dict
    params: dict


def _matrix(body: dict, key: str, shape: tuple, default=None) -> np.ndarray:
    value = body.get(key, default)
    try:
        out = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        out = None
    if out is None or out.shape != shape or not np.all(np.isfinite(out)):
        raise ExportError(
            f"this compass calibration's {key} is not {'×'.join(map(str, shape))} finite numbers "
            f"({value!r}): it cannot be exported; calibrate the flight log again"
        )
    return out


def flight_compass(body: dict, target: str | None = None) -> FlightCompass:
    """The checked model of a ``compass_flight`` calibration, for ``target``'s export (None: the JSON).

    Raises
    ------
    ExportError
        A calibration that failed its checks, of another unit, of another firmware than ``target``, or
        with its numbers missing.
    """
    flight, model = body.get("flight") or {}, body.get("model") or {}
    firmware = flight.get("firmware")
    if firmware not in FIRMWARE_NAMES:
        raise ExportError(
            f"this compass calibration names no firmware (firmware {firmware!r}, known "
            f"{', '.join(FIRMWARE_NAMES)}): calibrate the flight log again"
        )
    if target is not None:
        name = FIRMWARE_NAMES[target]
        if firmware != target:
            raise ExportError(
                f"this compass was calibrated from {'an' if firmware == 'ardupilot' else 'a'} "
                f"{FIRMWARE_NAMES[firmware]} log: its numbers are in the frames {FIRMWARE_NAMES[firmware]} reads the "
                f"compass in, which {name} does not share; use the {FIRMWARE_NAMES[firmware]} or JSON file"
            )
        if body.get("unit") != "uT":
            raise ExportError(
                f"{name} takes its compass parameters in gauss or milligauss, but this calibration maps "
                f"readings in {unit_label(body.get('unit'))}: calibrate the flight log again"
            )
        if not body.get("ok", False):
            raise ExportError(
                f"this calibration failed its checks ({'; '.join(body.get('reasons') or [])}): it must "
                f"not be written to {name}; fix what the reasons say and calibrate again"
            )
    motor = flight.get("motor")
    if motor not in (None, "current", "throttle"):
        raise ExportError(f"this compass calibration's motor model {motor!r} is none of current, throttle or null")
    k = _matrix(model, "k", (3,), [0.0, 0.0, 0.0]) if motor else np.zeros(3)
    Q, M = _matrix(model, "Q", (3, 3)), _matrix(model, "M", (3, 3))
    if np.abs(Q.T @ Q - np.eye(3)).max() > 1e-6 or np.linalg.det(Q) <= 0:
        raise ExportError(
            "this compass calibration's rotation is not a rotation (orthonormal, determinant +1): it "
            "cannot be exported; calibrate the flight log again"
        )
    if np.abs(M - M.T).max() > 1e-6 * max(1.0, np.abs(M).max()):
        raise ExportError(
            "this compass calibration's matrix is not symmetric, and both firmwares hold a symmetric "
            "one (diagonal and off-diagonal terms): calibrate the flight log again"
        )
    stored = flight.get("stored") or {}
    return FlightCompass(
        firmware=firmware,
        instance=int(flight.get("instance") or 0),
        Q=Q,
        M=M,
        b=_matrix(model, "b", (3,)),
        k=k,
        motor=motor,
        frame_to_body=_matrix(flight, "frame_to_body", (3, 3), np.eye(3).tolist()),
        stored=stored,
        params=dict(stored.get("params") or {}),
    )


def _rotation_number(firmware: str, R: np.ndarray, what: str) -> int:
    number, angle = nearest_number(firmware, R)
    if angle > ROTATION_TOLERANCE_DEG:
        raise ExportError(
            f"{what} is {angle:.1f}° from the nearest rotation {FIRMWARE_NAMES[firmware]} lists "
            f"({number}, {rotation_name(firmware, number)}): the firmware cannot hold it; mount the "
            "compass square to the vehicle (or use the json export)"
        )
    return number


def _param_int(params: dict, name: str) -> int | None:
    value = params.get(name)
    try:
        return None if value is None else int(round(float(value)))
    except (TypeError, ValueError):
        return None


def ardupilot_name(group: str, instance: int) -> str:
    """ArduPilot's parameter of a compass instance: ``COMPASS_OFS`` (0), ``COMPASS_OFS2``, ``COMPASS_OFS3``;
    ``EXTERNAL`` is ``EXTERN2``, ``EXTERN3`` beyond the first (var_info in libraries/AP_Compass/AP_Compass.cpp)."""
    if instance == 0:
        return f"COMPASS_{group}"
    return f"COMPASS_{'EXTERN' if group == 'EXTERNAL' else group}{instance + 1}"


def ardupilot_flight_parameters(body: dict) -> tuple[dict[str, float], list[str]]:
    """ArduPilot's parameters that make its correction of a compass equal to trical's ``h_body``, and the
    comment lines that go with them.

    ArduPilot (``AP_Compass_Backend::rotate_field``, then ``correct_field``) turns the sensor's field ``s`` into
    the body frame by the driver's rotation and then ``COMPASS_ORIENTn`` (an external compass;
    ``AHRS_ORIENTATION`` for an internal one), then in milligauss ``mag += COMPASS_OFS; mag *= COMPASS_SCALE;
    mag = [[DIA_X, ODI_X, ODI_Y], [ODI_X, DIA_Y, ODI_Z], [ODI_Y, ODI_Z, DIA_Z]] mag; mag += COMPASS_MOT p``
    (the motor offset after the matrix). The log's raw ``m_L`` is the field rotated by the orientation the
    firmware applied, ``R_now``; the new orientation is the listed rotation equal to ``Q R_now``, which turns
    the same ``s`` into ``Q m_L``. Hence ``COMPASS_OFS = −10 b``, ``DIA/ODI = M``, ``COMPASS_MOT = −10 M k``
    (mG per A or per unit throttle) and ``COMPASS_SCALE = 1``.

    Raises
    ------
    ExportError
        What ArduPilot would refuse (its ranges), an internal compass whose orientation is wrong (ArduPilot
        rotates it with the board), or an instance beyond the third.
    """
    f = flight_compass(body, "ardupilot")
    n = f.instance
    if not 0 <= n < ARDUPILOT_INSTANCES:
        raise ExportError(
            f"ArduPilot stores a calibration for compasses 0-{ARDUPILOT_INSTANCES - 1}, not {n}: use the json export"
        )
    external, orient_name, now, new, changes = _ardupilot_orientation(f, n)
    offsets = -MGAUSS_PER_UT * f.b
    mot = -MGAUSS_PER_UT * (f.M @ f.k)
    diagonal = np.diag(f.M)
    offdiagonal = np.array([f.M[0, 1], f.M[0, 2], f.M[1, 2]])
    _refuse_beyond_ardupilot_ranges(f, n, offsets, diagonal, offdiagonal, mot)
    params: dict[str, float] = {}
    for group, values in (("OFS", offsets), ("DIA", diagonal), ("ODI", offdiagonal), ("MOT", mot)):
        params.update({f"{ardupilot_name(group, n)}_{a}": float(v) for a, v in zip("XYZ", values)})
    params[ardupilot_name("SCALE", n)] = 1.0
    notes = [
        f"ArduPilot turns compass {n}'s field into the body frame, then corrects it in milligauss "
        f"({ARDUPILOT_FLIGHT_SOURCE}):",
        "  mag += OFS; mag *= SCALE; mag = [[DIA_X, ODI_X, ODI_Y], [ODI_X, DIA_Y, ODI_Z], [ODI_Y, ODI_Z, DIA_Z]] "
        "* mag; mag += MOT * p",
        "trical's h = M (Q m - b - k p) in uT, so OFS = -10 b, DIA/ODI = M, MOT = -10 M k, SCALE = 1 "
        "(1 uT = 10 mGauss).",
    ]
    _ardupilot_motor(f, n, params, notes)
    if changes:
        params[orient_name] = float(new)
        notes.append(
            f"{orient_name} {new} ({rotation_name('ardupilot', new)}) replaces {now} "
            f"({rotation_name('ardupilot', now)}): the flight shows the compass turned from the axes that "
            "orientation gives"
            + (
                "."
                if external
                else "; it takes effect for an external compass only "
                f"({ardupilot_name('EXTERNAL', n)} 1 or 2): an internal one turns with AHRS_ORIENTATION."
            )
        )
    notes.append("Older ArduPilot (e.g. Copter 3.3) added COMPASS_MOT before the matrix; there MOT = -10 k.")
    return params, notes


def _ardupilot_orientation(f: FlightCompass, n: int) -> tuple[int | None, str, int, int, bool]:
    """Whether compass ``n`` is external (its ``COMPASS_EXTERNALn``), the name of its orientation parameter,
    the orientation applied now (``COMPASS_ORIENTn``, or ``AHRS_ORIENTATION`` for an internal compass), the
    listed rotation equal to ``Q R_now``, and whether that changes it. Refuses a custom rotation, and an
    internal compass whose orientation the flight would change."""
    external = _param_int(f.params, ardupilot_name("EXTERNAL", n))
    orient_name = ardupilot_name("ORIENT", n)
    if external == 0:  # internal: rotate_field applies the board's orientation, not COMPASS_ORIENTn
        now, now_name = _param_int(f.params, "AHRS_ORIENTATION") or 0, "AHRS_ORIENTATION"
    else:
        stored = f.stored.get("orientation")
        stored = _param_int(f.params, orient_name) if stored is None else int(stored)
        now, now_name = (stored if stored is not None else 0), orient_name
    try:
        R_now = firmware_matrix("ardupilot", now)
    except ValueError:
        raise ExportError(
            f"{now_name} is {now}, a custom rotation whose angles the export does not read: set it to "
            "a listed rotation, fly again and calibrate that log"
        ) from None
    new = _rotation_number(
        "ardupilot",
        f.Q @ R_now,
        f"the compass's orientation found ({now_name} {now} turned by the rotation the flight shows)",
    )
    changes = angle_between(firmware_matrix("ardupilot", new), R_now) > ROTATION_TOLERANCE_DEG
    if changes and external == 0:
        raise ExportError(
            f"the flight shows compass {n} turned from the vehicle's axes (the nearest listed orientation is {new}, "
            f"{rotation_name('ardupilot', new)}, where AHRS_ORIENTATION {now} is applied), but it is an internal "
            f"compass ({ardupilot_name('EXTERNAL', n)} 0): ArduPilot turns it with the board's AHRS_ORIENTATION, "
            "not COMPASS_ORIENT, and its own calibration never changes an internal compass's orientation "
            "(CompassCalibrator::calculate_orientation). Check AHRS_ORIENTATION; if the compass is in fact "
            f"external, set {ardupilot_name('EXTERNAL', n)} 2 and {orient_name} {new}, fly again and calibrate "
            "that log"
        )
    return external, orient_name, now, new, changes


def _refuse_beyond_ardupilot_ranges(f: FlightCompass, n: int, offsets, diagonal, offdiagonal, mot) -> None:
    """Refuse parameters ArduPilot would not accept (its ranges), naming each."""
    offs_max = float(f.params.get("COMPASS_OFFS_MAX") or ARDUPILOT_OFFSET_MAX_MGAUSS)
    problems = []
    if np.linalg.norm(offsets) > offs_max:
        problems.append(
            f"|{ardupilot_name('OFS', n)}| = {np.linalg.norm(offsets):.0f} mGauss is beyond "
            "COMPASS_OFFS_MAX "
            f"{offs_max:g}"
        )
    lo, hi = ARDUPILOT_DIAGONAL_RANGE
    problems += [
        f"{ardupilot_name('DIA', n)}_{a} = {v:.4g} is outside {lo:g}…{hi:g}"
        for a, v in zip("XYZ", diagonal)
        if not lo < v < hi
    ]
    problems += [
        f"{ardupilot_name('ODI', n)}_{a} = {v:.4g} is beyond ±1"
        for a, v in zip("XYZ", offdiagonal)
        if abs(v) >= ARDUPILOT_OFFDIAGONAL_MAX
    ]
    problems += [
        f"{ardupilot_name('MOT', n)}_{a} = {v:.0f} mGauss is beyond ±{ARDUPILOT_MOT_MAX_MGAUSS:g}"
        for a, v in zip("XYZ", mot)
        if abs(v) > ARDUPILOT_MOT_MAX_MGAUSS
    ]
    if problems:
        raise ExportError(
            "ArduPilot would not accept this compass calibration: "
            + "; ".join(problems)
            + f" ({ARDUPILOT_RANGE_SOURCE}); move the compass away from the power wires and metal, "
            "or use the json export"
        )


def _ardupilot_motor(f: FlightCompass, n: int, params: dict, notes: list) -> None:
    """``COMPASS_MOTCT`` for the motor model's input (and ``COMPASS_PMOT_EN`` 0 for the first compass when the
    per-motor compensation is on), with the notes saying so; without a motor model, a note that ``COMPASS_MOT``
    is 0."""
    unit = {"current": "mGauss per A", "throttle": "mGauss at full throttle"}
    motor = f.motor or ""  # "": no motor model
    motct = ARDUPILOT_MOTCT.get(motor)
    stored_motct = _param_int(f.params, "COMPASS_MOTCT")
    if motct is not None:
        params["COMPASS_MOTCT"] = float(motct)
        notes.append(
            f"COMPASS_MOT is in {unit[motor]}; COMPASS_MOTCT {motct} ({f.motor}) is one setting for every "
            "compass"
            + (
                f": it was {stored_motct}, so the other compasses' COMPASS_MOT values were "
                "fitted against the other input - check them"
                if stored_motct not in (None, 0, motct)
                else "."
            )
        )
        if n == 0 and _param_int(f.params, "COMPASS_PMOT_EN") == 1:
            params["COMPASS_PMOT_EN"] = 0.0
            notes.append(
                "COMPASS_PMOT_EN 0: the per-motor compensation replaces COMPASS_MOT for the first compass "
                "(correct_field)."
            )
    else:
        notes.append(
            "No motor model: COMPASS_MOT is 0 for this compass; COMPASS_MOTCT (every compass's) is left as it is."
        )


def px4_slot(f: FlightCompass) -> int:
    """The ``CAL_MAGn`` slot that holds this compass. PX4 applies the slot whose ``CAL_MAGn_ID`` is the
    compass's device id (``FindCalibrationIndex``, src/lib/sensor_calibration/Utilities.cpp); the stored
    calibration names it: its ``slot``, else the one slot its parameters hold, else the one whose
    ``CAL_MAGn_xOFF`` (×100 µT) are the stored offsets.

    Raises
    ------
    ExportError
        When none of these names exactly one slot.
    """
    if f.stored.get("slot") is not None:
        return int(f.stored["slot"])
    slots = sorted({int(m.group(1)) for name in f.params if (m := re.match(r"CAL_MAG(\d)_", str(name)))})
    if len(slots) > 1:
        stored = np.asarray(f.stored.get("offsets_ut") or [np.nan] * 3, dtype=float)
        slots = [
            s
            for s in slots
            if np.allclose(
                [100.0 * float(f.params.get(f"CAL_MAG{s}_{a}OFF", np.nan)) for a in "XYZ"], stored, rtol=1e-6, atol=1e-9
            )
        ]
    if len(slots) != 1:
        raise ExportError(
            f"the log's parameters do not say which CAL_MAGn slot holds compass {f.instance}: PX4 "
            "applies the slot whose CAL_MAGn_ID is the compass's device id; calibrate a log that holds "
            "its parameters, or use the json export"
        )
    return slots[0]


def _level_adjustment(params: dict) -> np.ndarray:
    """PX4's ``GetSensorLevelAdjustment``: Euler(SENS_BOARD_X_OFF, Y_OFF, Z_OFF) in degrees, applied before the
    rotation (Magnetometer::set_rotation)."""
    return euler_matrix(*(float(params.get(f"SENS_BOARD_{a}_OFF") or 0.0) for a in "XYZ"))


def px4_flight_parameters(body: dict) -> tuple[dict[str, float], list[str]]:
    """PX4's ``CAL_MAGn_*`` parameters that make its correction of a compass equal to trical's ``h_body``,
    and the comment lines that go with them.

    PX4 (``Magnetometer::Correct``) applies ``R (S ((data + power · COMP) − OFF))`` in gauss to sensor_mag's
    sensor-frame field, ``R`` the level adjustment times ``CAL_MAGn_ROT``'s rotation (the board's
    ``SENS_BOARD_ROT`` for an internal compass), ``S`` the symmetric matrix of ``xSCALE`` and ``xODIAG``, power
    the throttle (0…1) or the battery current in kA. From ``h = M (Q m − b − k p)``: ``R = Q``, ``S = Qᵀ M Q``,
    ``OFF = Qᵀ b / 100`` (G), ``COMP = −Qᵀ k / 100`` G per unit throttle or ``−10 Qᵀ k`` G/kA.

    Raises
    ------
    ExportError
        A scale PX4 would not take, an internal compass whose rotation is wrong (PX4 turns it with the
        board), or a slot the log's parameters do not name.
    """
    f = flight_compass(body, "px4")
    slot = px4_slot(f)
    p = f"CAL_MAG{slot}_"
    stored_rot = _param_int(f.params, p + "ROT")
    if stored_rot is None and f.stored.get("orientation") is not None:
        stored_rot = int(f.stored["orientation"])
    level = _level_adjustment(f.params)
    changes = angle_between(f.Q, f.frame_to_body) > ROTATION_TOLERANCE_DEG
    new = _rotation_number("px4", level.T @ f.Q, "the compass's rotation found") if changes else stored_rot
    if changes and stored_rot == -1:
        assert new is not None, "a rotation found is a number"
        raise ExportError(
            f"the flight shows compass {f.instance} turned from the vehicle's axes (the nearest listed rotation is "
            f"{new}, {rotation_name('px4', new)}), but it is an internal compass ({p}ROT -1): PX4 turns it with the "
            "board's SENS_BOARD_ROT and resets its CAL_MAGn_ROT to -1 (Magnetometer::ParametersUpdate). Check "
            "SENS_BOARD_ROT; an external compass's rotation is set in its own CAL_MAGn_ROT"
        )
    S = f.Q.T @ f.M @ f.Q
    diagonal = np.diag(S)
    lo, hi = PX4_SCALE_RANGE
    bad = [f"{p}{a}SCALE = {v:.4g}" for a, v in zip("XYZ", diagonal) if not lo <= v <= hi]
    if bad:
        raise ExportError(
            f"PX4 would not take this compass calibration: {', '.join(bad)} outside {lo:g}…{hi:g} (its "
            "parameter range; Magnetometer::set_scale keeps the old scale for one not above 0): check "
            "the log's unit, or use the json export"
        )
    to_comp = GAUSS_PER_UT / PX4_KILOAMPERE_PER_AMPERE if f.motor == "current" else GAUSS_PER_UT
    values = {
        "OFF": GAUSS_PER_UT * (f.Q.T @ f.b),
        "SCALE": diagonal,
        "ODIAG": np.array([S[0, 1], S[0, 2], S[1, 2]]),
        "COMP": -to_comp * (f.Q.T @ f.k),
    }
    params = {f"{p}{a}{group}": float(v) for group, vs in values.items() for a, v in zip("XYZ", vs)}
    notes = [
        f"PX4 corrects the sensor-frame field in gauss ({PX4_FLIGHT_SOURCE}):",
        "  h = R * (S * ((data + power * COMP) - OFF)), S = [[XSCALE, XODIAG, YODIAG], [XODIAG, YSCALE, ZODIAG], "
        "[YODIAG, ZODIAG, ZSCALE]]",
        "trical's h = M (Q m - b - k p) in uT, so R = Q, S = Q^T M Q, OFF = Q^T b / 100, COMP = -Q^T k / 100 "
        "(per unit throttle) or -10 Q^T k (G/kA: PX4's power is the current in kA).",
        f"CAL_MAG{slot} is the slot whose CAL_MAG{slot}_ID is this compass's device id in the log.",
    ]
    comp = PX4_COMP_TYPE.get(f.motor or "")
    stored_comp = _param_int(f.params, "CAL_MAG_COMP_TYP")
    if comp is not None:
        if comp == 2 and stored_comp == 3:
            comp = 3  # current of battery_status instance 1, as the log's setting chose
        params["CAL_MAG_COMP_TYP"] = float(comp)
        notes.append(
            f"CAL_MAG_COMP_TYP {comp} ({f.motor}"
            + (f", battery_status instance {comp - 2}" if f.motor == "current" else "")
            + ") is one setting for every compass"
            + ("; PX4 applies the throttle's compensation only while armed." if f.motor == "throttle" else ".")
        )
    else:
        notes.append(
            "No motor model: the COMP values are 0 for this compass; CAL_MAG_COMP_TYP (every compass's) is "
            "left as it is."
        )
    if changes:
        assert new is not None, "a rotation found is a number"
        params[p + "ROT"] = float(new)
        notes.append(
            f"{p}ROT {new} ({rotation_name('px4', new)}) replaces {stored_rot}: the flight shows the compass "
            "turned from the axes that rotation gives"
            + ("." if stored_rot is not None else "; it takes effect for an external compass only.")
        )
    return params, notes


def heading_errors(body: dict) -> dict:
    """``{"before": {"rms", "p95"}, "after": {…}}``: the heading errors on flight segments left out, in degrees,
    from the calibration's metrics."""
    m = body.get("metrics") or {}
    return {
        when: {"rms": m.get(f"heading_error_{when}_deg"), "p95": m.get(f"heading_error_{when}_p95_deg")}
        for when in ("before", "after")
    }


def _flight_header(body: dict, target: str, notes: list[str]) -> list[str]:
    flight, errors = body.get("flight") or {}, heading_errors(body)

    def figure(e):
        return (
            f"rms {e['rms']:.2f} deg, 95th percentile {e['p95']:.2f} deg"
            if e.get("rms") is not None and e.get("p95") is not None
            else "not measured"
        )

    before, after = errors["before"], errors["after"]
    lines = [
        f"trical calibration {body.get('id', '-')}",
        f"method: {body.get('method')}, created {body.get('created_at', '-')}, device: {body.get('device_id') or '-'}",
        f"compass {flight.get('instance', 0)} of {'an' if target[0] in 'AEIOU' else 'a'} {target} flight log: model "
        f"{flight.get('structure')}, motor "
        f"{flight.get('motor') or 'none'}",
        f"heading error on flight segments left out: before {figure(before)}; after {figure(after)}",
    ]
    lines += _updated_lines(flight.get("updated")) + notes
    return [f"# {line}" for line in lines]


def _updated_lines(updated: dict | None) -> list[str]:
    """Which numbers are new from the flight and which are the firmware's own, written again as they were
    (app.calibration.magnetometer.flight_partial), where the flight did not determine them all."""
    if not updated:
        return []
    from app.calibration.magnetometer.flight_partial import HELD_WORDS, OFFSET_WORDS, held_words, motor_words

    k = [updated["k"]] * 3 if isinstance(updated["k"], bool) else updated["k"]  # one bool in results stored before
    held = {"b": [not u for u in updated["b"]], "M": not updated["M"], "k": [not u for u in k]}
    new = [w for w, u in zip(OFFSET_WORDS, updated["b"]) if u]
    new += ([HELD_WORDS["M"]] if updated["M"] else []) + motor_words(k)
    return [
        f"new from this flight: {', '.join(new) or 'nothing'}",
        f"kept at the values stored before (the flight does not determine them): {', '.join(held_words(held))}",
    ]


def to_ardupilot_flight_compass(body: dict) -> Export:
    """ArduPilot parameter file of a compass calibrated from a flight: ``COMPASS_OFSn_*`` (mG),
    ``COMPASS_DIAn_*``, ``COMPASS_ODIn_*``, ``COMPASS_MOTn_*``, ``COMPASS_SCALEn``, ``COMPASS_MOTCT`` and
    ``COMPASS_ORIENTn`` where the orientation changes (:func:`ardupilot_flight_parameters`)."""
    params, notes = ardupilot_flight_parameters(body)
    lines = _flight_header(body, "ArduPilot", notes) + [f"{name} {_number(v)}" for name, v in params.items()]
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body.get('id', 'compass')}_ardupilot.parm")


def to_px4_flight_compass(body: dict) -> Export:
    """PX4 ``param set`` lines of a compass calibrated from a flight: ``CAL_MAGn_xOFF`` (G), ``xSCALE``,
    ``xODIAG``, ``xCOMP``, ``CAL_MAG_COMP_TYP`` and ``CAL_MAGn_ROT`` where the rotation changes
    (:func:`px4_flight_parameters`)."""
    params, notes = px4_flight_parameters(body)
    integer = ("_ROT", "COMP_TYP")  # integer parameters
    lines = _flight_header(body, "PX4", notes) + [
        f"param set {name} {int(v) if name.endswith(integer) else _number(v)}" for name, v in params.items()
    ]
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body.get('id', 'compass')}_px4.txt")


def to_json_flight_compass(body: dict) -> Export:
    """Versioned JSON of a compass calibrated from a flight: trical's correction ``h = M (Q m − b − k p)``,
    what the firmware stored, the heading errors, and the firmware's parameters (or why they are refused).
    A calibration that failed its checks, or whose numbers are missing, is written as it is."""
    flight, model = body.get("flight") or {}, body.get("model") or {}
    firmware = flight.get("firmware")
    to_params = {"ardupilot": ardupilot_flight_parameters, "px4": px4_flight_parameters}.get(firmware or "")
    try:
        if to_params is None:
            flight_compass(body)  # raises, naming the firmware missing
            raise AssertionError("flight_compass refuses a flight of no known firmware")
        params, _ = to_params(body)
        refused = None
    except ExportError as exc:
        params, refused = None, str(exc)
    motor = flight.get("motor")
    doc = {
        "$schema": JSON_SCHEMA,
        "schema_version": 1,
        "id": body.get("id"),
        "method": body.get("method"),
        "created_at": body.get("created_at"),
        "device_id": body.get("device_id"),
        "label": body.get("label"),
        "sensor": "magnetometer",
        "firmware": firmware,
        "instance": flight.get("instance"),
        "unit": body.get("unit"),
        "structure": flight.get("structure"),
        "motor": motor,
        "correction": {
            "formula": "h_body = M (Q m - b - k p)",
            "frame": "m raw in the frame the log gives it in: "
            + {
                "ardupilot": "the body frame under the orientation ArduPilot applied",
                "px4": "sensor_mag's sensor frame",
            }.get(firmware or "", "unknown"),
            "Q": model.get("Q"),
            "M": model.get("M"),
            "b": model.get("b"),
            "k": model.get("k") if motor else [0.0, 0.0, 0.0],
            "p": {"current": "battery current, A", "throttle": "throttle, 0..1"}.get(motor or "", "none"),
        },
        "rotation_nearest": flight.get("rotation_nearest"),
        "orientation_agrees": flight.get("orientation_agrees"),
        "stored": flight.get("stored"),
        "heading_error_deg": heading_errors(body),
        "firmware_parameters": params,
        "firmware_parameters_refused": refused,
        "ok": body.get("ok"),
        "warnings": body.get("warnings", []),
        "reasons": body.get("reasons", []),
    }
    return Export(json.dumps(doc, indent=2), "application/json", f"{body.get('id', 'compass')}.json")


FLIGHT_COMPASS_EXPORTERS = {
    "json": to_json_flight_compass,
    "ardupilot": to_ardupilot_flight_compass,
    "px4": to_px4_flight_compass,
    "flight_svg": to_flight_compass_svg,
}
FLIGHT_COMPASS_FORMATS = {
    "ardupilot": "ArduPilot (.parm)",
    "px4": "PX4 (param set lines)",
    "json": "JSON",
    "flight_svg": "The flight's compass (SVG)",
}
"""The page's download links of a compass calibrated from a flight."""
FLIGHT_COMPASS_EXPORTS = tuple(FLIGHT_COMPASS_EXPORTERS)
"""The export formats of a compass calibrated from a flight (method ``compass_flight``): the method table's
``formats``."""


def export_flight_compass(body: dict, fmt: str) -> Export:
    """A compass calibrated from a flight (method ``compass_flight``) in ``fmt`` (:data:`FLIGHT_COMPASS_EXPORTS`).

    Raises
    ------
    ExportError
        A format it does not offer, or one its firmware would refuse (the message says why and what to do).
    """
    if fmt not in FLIGHT_COMPASS_EXPORTERS:
        raise ExportError(
            f"format {fmt!r} does not fit this calibration, a compass calibrated from a flight: use one "
            f"of {', '.join(FLIGHT_COMPASS_EXPORTS)}"
        )
    return FLIGHT_COMPASS_EXPORTERS[fmt](body)
