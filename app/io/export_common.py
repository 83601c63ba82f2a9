"""What every export shares: the file it returns and the correction ``a = M (m − o)`` of a calibration."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ExportError

CORRECTION_SOURCE = {
    "affine": "000_cb2cbc1c5eaccf1a.txt eq. (20): M = X^-1, o = y",
    "nonorthogonal": "000_cb2cbc1c5eaccf1a.txt eq. (16): M = T_orth T_bar T, o = s / b",
    "triangular": "002_7135f13639ec18ce.txt eq. (6): M = K, o = -o_model",
}

JSON_SCHEMA = "https://trical.dev/schema/calibration/v1"
FRAME = "device frame of the data: x right, y up along the screen, z out of the screen (W3C DeviceMotion)"


@dataclass(frozen=True)
class Export:
    content: str
    media_type: str
    filename: str


AFFINE_MODELS = ("affine", "nonorthogonal", "triangular")
"""Models whose calibration is ``a = M (m − o)`` for one accelerometer."""


def _affine_correction(body: dict) -> tuple[np.ndarray, np.ndarray]:
    kind = body["model"].get("type")
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
