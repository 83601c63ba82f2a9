"""What every export shares: the file it returns and the correction ``a = M (m − o)`` of a calibration."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ExportError

CORRECTION_SOURCE = {
    "affine": "000_cb2cbc1c5eaccf1a.txt eq. (20): M = X^-1, o = y",
    "nonorthogonal": "000_cb2cbc1c5eaccf1a.txt eq. (16): M = T_orth T_bar T, o = s / b",
    "triangular": "002_7135f13639ec18ce.txt eq. (6): M = K, o = -o_model",
    "cube": "003_17911d0910b68c7e.txt eq. (1): raw = S f + b, so M = S^-1, o = b",
}

SENSORS = {"acc": "accelerometer", "gyr": "gyroscope", "mag": "magnetometer"}
CUBE_OUTPUT_UNITS = {"gyr": "rad/s", "mag": "uT"}
"""What a cube calibration's gyroscope and magnetometer corrections calibrate into (app.workflow)."""

JSON_SCHEMA = "https://trical.dev/schema/calibration/v1"
FRAME = "device frame of the data: x right, y up along the screen, z out of the screen (W3C DeviceMotion)"


@dataclass(frozen=True)
class Export:
    content: str
    media_type: str
    filename: str


AFFINE_MODELS = ("affine", "nonorthogonal", "triangular")
"""Models whose calibration is ``a = M (m − o)`` for one accelerometer."""


@dataclass(frozen=True)
class Correction:
    """One sensor's correction ``f = M (m − o)`` and the units it maps between."""

    sensor: str
    M: np.ndarray
    o: np.ndarray
    input_unit: str | None
    output_unit: str | None


def sensor_corrections(body: dict) -> list[Correction]:
    """Every sensor correction a calibration holds: the accelerometer's, and for the cube method
    (003) the gyroscope's and magnetometer's too, in that order."""
    kind = body["model"].get("type")
    if kind in AFFINE_MODELS:
        M, o = _affine_correction(body)
        return [Correction("acc", M, o, body.get("unit"), body.get("output_unit"))]
    if kind != "cube":
        raise ExportError(f"a {kind!r} calibration has no correction to export: use the json export")
    units = body.get("units") or {}
    out = []
    for sensor in SENSORS:
        model = body["model"].get(sensor)
        if not model or model.get("S") is None:
            continue
        S = np.asarray(model["S"], dtype=float)
        if sensor == "acc":
            input_unit, output_unit = body.get("unit"), body.get("output_unit")
        else:  # converted to rad/s and µT before the fit (app.workflow.calibrate_cube_log)
            raw = units.get(sensor) == "raw"
            input_unit, output_unit = ("raw" if raw else CUBE_OUTPUT_UNITS[sensor]), CUBE_OUTPUT_UNITS[sensor]
        out.append(Correction(sensor, np.linalg.inv(S), np.asarray(model["b"], dtype=float),  # 003 eq. (1)
                              input_unit, output_unit))
    if not out:
        raise ExportError("the cube calibration holds no sensor model to export: use the json export")
    return out


def _affine_correction(body: dict) -> tuple[np.ndarray, np.ndarray]:
    kind = body["model"].get("type")
    if kind == "cube":
        acc = [c for c in sensor_corrections(body) if c.sensor == "acc"]
        if not acc:
            raise ExportError("this cube calibration has no accelerometer model: use the json export")
        return acc[0].M, acc[0].o
    if kind not in AFFINE_MODELS:
        raise ExportError(
            f"this export holds one accelerometer correction a = M (m - o); a {kind!r} calibration "
            f"does not fit it: use the json export"
        )
    if kind == "affine":
        X = np.asarray(body["model"]["X"], dtype=float)
        return np.linalg.inv(X), np.asarray(body["model"]["y"], dtype=float)
    from app.calibration.registry import affine_correction, result_from_dict  # every model: see app/workflow.py

    return affine_correction(result_from_dict(body))


def describe(body: dict) -> list[str]:
    """Lines naming the calibration, for the comment header of a text export."""
    return [
        f"trical calibration {body['id']}",
        f"method: {body['method']}, created {body['created_at']}, device: {body.get('device_id') or '-'}",
        f"input unit: {body.get('unit')}, output unit: {body.get('output_unit')}, gravity: {body.get('gravity')}",
        f"calibrated a = M (m - o): {CORRECTION_SOURCE[body['model']['type']]}",
    ]
