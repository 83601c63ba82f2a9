"""PX4's stored calibration: ``CAL_ACCn_*``, ``CAL_GYROn_*``, ``CAL_MAGn_*`` from QGroundControl's ``.params``,
``param set`` lines or a ULog's parameters.

The exact inverse of trical's PX4 exports (app.io.exports.params ``to_px4``, app.io.exports.compass
``to_px4_compass``), which cite PX4's source:

* accelerometer, ``Accelerometer::Correct``: ``R ((m − CAL_ACC0_OFF) ∘ CAL_ACC0_SCALE)`` in m/s², so ``M =
  diag(xSCALE)``, ``o = xOFF``;
* gyroscope, ``Gyroscope::Correct``: ``R (m − CAL_GYRO0_OFF)`` in rad/s, so ``M = I``, ``o = xOFF``;
* compass, ``Magnetometer::Correct``: ``R (S (m − CAL_MAG0_OFF))`` in gauss, ``S`` the symmetric matrix of
  ``xSCALE`` and ``xODIAG``: in µT (1 G = 100 µT) ``M = S``, ``o = 100 · xOFF``.

Each is in the sensor's frame: PX4 rotates last (``CAL_*_ROT``; −1 for an internal sensor, which turns with
``SENS_BOARD_ROT``).
"""

from __future__ import annotations

import numpy as np

from app.calibration.imported import ImportedCalibration, ImportedSensor, offset_scale_sensor, symmetric

from ..exports.compass import GAUSS_PER_UT
from ..exports.compass import PX4_SCALE_RANGE as MAG_SCALE_RANGE
from ..exports.params import PX4_SCALE_RANGE

FIRMWARE = "PX4"
FRAME = "the sensor's frame (PX4 rotates last, by CAL_*_ROT or SENS_BOARD_ROT)"
XYZ = "XYZ"


def _vector(params: dict[str, float], prefix: str, suffix: str, default: float) -> np.ndarray | None:
    if not any(f"{prefix}{a}{suffix}" in params for a in XYZ):
        return None
    return np.array([params.get(f"{prefix}{a}{suffix}", default) for a in XYZ], dtype=float)


def _read(params: dict[str, float], prefix: str) -> dict[str, float]:
    return {n: v for n, v in params.items() if n.startswith(prefix) and not n.endswith("COMP")}


def _scales(prefix: str, values: np.ndarray, limits: tuple[float, float]) -> list[str]:
    lo, hi = limits
    return [
        f"{prefix}{a}SCALE = {v:.4g} is outside PX4's {lo:g}…{hi:g}" for a, v in zip(XYZ, values) if not lo <= v <= hi
    ]


def from_parameters(
    params: dict[str, float], *, file_kind: str, version: str | None = None, instance: int = 0
) -> ImportedCalibration:
    """PX4's calibration of slot ``instance`` (``CAL_ACC0``, ``CAL_GYRO0``, ``CAL_MAG0``) among ``params``.

    Raises
    ------
    LookupError
        When none of the slot's calibration parameters is among them.
    """
    sensors: list[ImportedSensor] = []
    reasons: list[str] = []
    acc = f"CAL_ACC{instance}_"
    offset = _vector(params, acc, "OFF", 0.0)
    if offset is not None:
        scale = _vector(params, acc, "SCALE", 1.0)
        scale = np.ones(3) if scale is None else scale
        sensors.append(offset_scale_sensor("acc", offset, scale, "m/s^2", _read(params, acc)))
        reasons += _scales(acc, scale, PX4_SCALE_RANGE)
    gyro = f"CAL_GYRO{instance}_"
    bias = _vector(params, gyro, "OFF", 0.0)
    if bias is not None:
        sensors.append(offset_scale_sensor("gyr", bias, np.ones(3), "rad/s", _read(params, gyro)))
    mag = f"CAL_MAG{instance}_"
    mag_off = _vector(params, mag, "OFF", 0.0)
    if mag_off is not None:
        diagonal = _vector(params, mag, "SCALE", 1.0)
        diagonal = np.ones(3) if diagonal is None else diagonal
        off = _vector(params, mag, "ODIAG", 0.0)
        off = np.zeros(3) if off is None else off
        sensors.append(
            ImportedSensor("mag", symmetric(diagonal, off), mag_off / GAUSS_PER_UT, "gauss", _read(params, mag))
        )
        reasons += _scales(mag, diagonal, MAG_SCALE_RANGE)
    if not sensors:
        raise LookupError(f"no calibration of slot {instance}: none of {acc}XOFF, {gyro}XOFF, {mag}XOFF")
    warnings = list(reasons)
    others = [
        n
        for n in range(4)
        if n != instance
        and any(params.get(f"CAL_{kind}{n}_ID") and f"CAL_{kind}{n}_XOFF" in params for kind in ("ACC", "GYRO", "MAG"))
    ]
    if others:
        warnings.append(
            f"imported: slot {instance} (CAL_ACC{instance}, CAL_GYRO{instance}, CAL_MAG{instance}); the file also "
            "holds the calibration of slot "
            + ", ".join(map(str, others))
            + " (`instance` "
            + ", ".join(map(str, others))
            + ")"
        )
    unused = [f"CAL_{k}{instance}_ID" for k in ("ACC", "GYRO", "MAG") if params.get(f"CAL_{k}{instance}_ID") == 0]
    if unused:
        warnings.append(
            f"{', '.join(unused)} 0: PX4 applies a slot's calibration to the sensor whose device id it holds, so "
            "none of this slot's is in use"
        )
    comp = _vector(params, mag, "COMP", 0.0)
    if comp is not None and np.any(comp):
        warnings.append(f"{mag}XCOMP… (the motors' compensation) is not part of the correction imported")
    return ImportedCalibration(
        tuple(sensors), FIRMWARE, version, file_kind, FRAME, warnings=tuple(warnings), reasons=tuple(reasons)
    )
