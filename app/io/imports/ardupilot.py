"""ArduPilot's stored calibration: ``INS_ACC*``, ``INS_GYR*``, ``COMPASS_*`` from a parameter file or a
DataFlash log's ``PARM`` messages.

The exact inverse of trical's ArduPilot exports (app.io.exports.params ``to_ardupilot``, app.io.exports.compass
``to_ardupilot_compass``), which cite ArduPilot's source:

* accelerometer, ``AP_InertialSensor_Backend::_rotate_and_correct_accel``: ``a_i = INS_ACCSCAL_i (m_i −
  INS_ACCOFFS_i)`` in m/s², so ``M = diag(INS_ACCSCAL)``, ``o = INS_ACCOFFS`` (instances 2 and 3:
  ``INS_ACC2OFFS_*``, ``INS_ACC3SCAL_*``; a scale of 0, never calibrated, is 1);
* gyroscope, ``_rotate_and_correct_gyro``: ``w_i = m_i − INS_GYROFFS_i`` in rad/s, so ``M = I``, ``o =
  INS_GYROFFS`` (``INS_GYR2OFFS_*``, ``INS_GYR3OFFS_*``);
* compass, ``AP_Compass_Backend::correct_field``, in milligauss: ``mag += COMPASS_OFS; mag *= COMPASS_SCALE;
  mag = [[DIA_X, ODI_X, ODI_Y], [ODI_X, DIA_Y, ODI_Z], [ODI_Y, ODI_Z, DIA_Z]] mag``, so in µT (1 µT = 10 mGauss)
  ``M = COMPASS_SCALE · [DIA/ODI]``, ``o = −COMPASS_OFS / 10`` (diagonals of 0, never calibrated, are 1; a
  scale of 0 is 1). The compass is corrected after its rotation into the body frame (``COMPASS_ORIENT``).
"""

from __future__ import annotations

import numpy as np

from app.calibration.imported import ImportedCalibration, ImportedSensor, offset_scale_sensor, symmetric

from ..exports.compass import (
    ARDUPILOT_DIAGONAL_RANGE,
    ARDUPILOT_OFFDIAGONAL_MAX,
    ARDUPILOT_OFFSET_MAX_MGAUSS,
    MGAUSS_PER_UT,
    ardupilot_name,
)
from ..exports.params import ARDUPILOT_OFFSET_RANGE, ARDUPILOT_RANGE_SOURCE, ARDUPILOT_SCALE_RANGE

FIRMWARE = "ArduPilot"
FRAME = (
    "the sensor's frame for the accelerometer and the gyroscope (before AHRS_ORIENTATION); the body frame for "
    "the compass (after COMPASS_ORIENT)"
)
XYZ = "XYZ"


def acc_names(instance: int) -> tuple[str, str]:
    """The offset's and the scale's parameter of accelerometer ``instance`` (0, 1, 2)."""
    n = "" if instance == 0 else str(instance + 1)
    return f"INS_ACC{n}OFFS_", f"INS_ACC{n}SCAL_"


def id_name(kind: str, instance: int) -> str:
    """The device id of IMU or compass ``instance``: ``INS_ACC_ID``, ``INS_ACC2_ID``; ``COMPASS_DEV_ID``,
    ``COMPASS_DEV_ID2`` (what a calibration belongs to: ArduPilot matches it at boot)."""
    n = "" if instance == 0 else str(instance + 1)
    return f"COMPASS_DEV_ID{n}" if kind == "MAG" else f"INS_{kind}{n}_ID"


def gyro_name(instance: int) -> str:
    n = "" if instance == 0 else str(instance + 1)
    return f"INS_GYR{n}OFFS_"


def _vector(params: dict[str, float], prefix: str, default: float) -> np.ndarray | None:
    if not any(prefix + a in params for a in XYZ):
        return None
    return np.array([params.get(prefix + a, default) for a in XYZ], dtype=float)


def _read(params: dict[str, float], names: list[str]) -> dict[str, float]:
    return {n: params[n] for n in names if n in params}


def from_parameters(
    params: dict[str, float], *, file_kind: str, version: str | None = None, instance: int = 0
) -> ImportedCalibration:
    """ArduPilot's calibration of IMU and compass ``instance`` among ``params``.

    Raises
    ------
    LookupError
        When none of the calibration's parameters is among them.
    """
    sensors: list[ImportedSensor] = []
    reasons: list[str] = []
    warnings: list[str] = []
    off_name, scale_name = acc_names(instance)
    offset = _vector(params, off_name, 0.0)
    if offset is not None:
        scale = _vector(params, scale_name, 1.0)
        scale = np.ones(3) if scale is None else np.where(scale == 0.0, 1.0, scale)
        names = [p + a for p in (off_name, scale_name) for a in XYZ] + [id_name("ACC", instance)]
        sensors.append(offset_scale_sensor("acc", offset, scale, "m/s^2", _read(params, names)))
        lo, hi = ARDUPILOT_OFFSET_RANGE
        reasons += [
            f"{off_name}{a} = {v:.4g} m/s/s is outside ArduPilot's {lo:g}…{hi:g} m/s/s ({ARDUPILOT_RANGE_SOURCE})"
            for a, v in zip(XYZ, offset)
            if not lo <= v <= hi
        ]
        lo, hi = ARDUPILOT_SCALE_RANGE
        reasons += [
            f"{scale_name}{a} = {v:.4g} is outside ArduPilot's {lo:g}…{hi:g} ({ARDUPILOT_RANGE_SOURCE})"
            for a, v in zip(XYZ, scale)
            if not lo <= v <= hi
        ]
    gyro = _vector(params, gyro_name(instance), 0.0)
    if gyro is not None:
        names = [gyro_name(instance) + a for a in XYZ] + [id_name("GYR", instance)]
        sensors.append(offset_scale_sensor("gyr", gyro, np.ones(3), "rad/s", _read(params, names)))
    ofs = _vector(params, ardupilot_name("OFS", instance) + "_", 0.0)
    if ofs is not None:
        dia = _vector(params, ardupilot_name("DIA", instance) + "_", 0.0)
        dia = np.ones(3) if dia is None or not np.any(dia) else dia
        odi = _vector(params, ardupilot_name("ODI", instance) + "_", 0.0)
        odi = np.zeros(3) if odi is None else odi
        scale_param = ardupilot_name("SCALE", instance)
        factor = params.get(scale_param, 0.0) or 1.0
        names = [ardupilot_name(g, instance) + "_" + a for g in ("OFS", "DIA", "ODI") for a in XYZ]
        names += [scale_param, ardupilot_name("ORIENT", instance), "COMPASS_OFFS_MAX", id_name("MAG", instance)]
        M = factor * symmetric(dia, odi)
        sensors.append(ImportedSensor("mag", M, -ofs / MGAUSS_PER_UT, "mGauss", _read(params, names)))
        limit = params.get("COMPASS_OFFS_MAX") or ARDUPILOT_OFFSET_MAX_MGAUSS
        reasons += [
            f"{ardupilot_name('OFS', instance)}_{a} = {v:.0f} mGauss is beyond ArduPilot's ±{limit:g} "
            "(COMPASS_OFFS_MAX)"
            for a, v in zip(XYZ, ofs)
            if abs(v) >= limit
        ]
        lo, hi = ARDUPILOT_DIAGONAL_RANGE
        reasons += [
            f"{ardupilot_name('DIA', instance)}_{a} = {v:.4g} is outside ArduPilot's {lo:g}…{hi:g}"
            for a, v in zip(XYZ, dia)
            if not lo < v < hi
        ]
        reasons += [
            f"{ardupilot_name('ODI', instance)}_{a} = {v:.4g} is beyond ArduPilot's ±{ARDUPILOT_OFFDIAGONAL_MAX:g}"
            for a, v in zip(XYZ, odi)
            if abs(v) >= ARDUPILOT_OFFDIAGONAL_MAX
        ]
    if not sensors:
        raise LookupError(
            f"no calibration of instance {instance}: none of {off_name}X, {gyro_name(instance)}X, "
            f"{ardupilot_name('OFS', instance)}_X"
        )
    others = [n for n in (0, 1, 2) if n != instance and acc_names(n)[0] + "X" in params]
    if others:
        warnings.append(
            f"imported: IMU and compass {instance + 1} ({off_name}*); the file also holds the calibration of IMU "
            + ", ".join(str(n + 1) for n in others)
            + " (`instance` "
            + ", ".join(str(n) for n in others)
            + ")"
        )
    if params.get("AHRS_ORIENTATION"):
        warnings.append(
            f"AHRS_ORIENTATION is {params['AHRS_ORIENTATION']:g}: the accelerometer's numbers are in the sensor's "
            "frame, before that rotation"
        )
    return ImportedCalibration(
        tuple(sensors),
        FIRMWARE,
        version,
        file_kind,
        FRAME,
        warnings=tuple(reasons) + tuple(warnings),
        reasons=tuple(reasons),
    )
