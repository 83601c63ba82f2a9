"""Rebuild any stored calibration result from its plain-dict form, by its model type."""

from __future__ import annotations

from .affine import MODEL_TYPE as AFFINE, AffineCalibration
from .errors import CalibrationError

RESULT_TYPES: dict[str, type] = {AFFINE: AffineCalibration}


def result_from_dict(data: dict):
    """Return the result object whose ``to_dict()`` produced ``data``.

    Raises
    ------
    CalibrationError
        If the model type is unknown.
    """
    kind = (data.get("model") or {}).get("type")
    try:
        cls = RESULT_TYPES[kind]
    except KeyError:
        raise CalibrationError(f"unknown model type {kind!r}; known: {', '.join(RESULT_TYPES)}") from None
    return cls.from_dict(data)
