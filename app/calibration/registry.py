"""Rebuild any stored calibration result from its plain-dict form, by its model type."""

from __future__ import annotations

import numpy as np

from .affine import MODEL_TYPE as AFFINE, AffineCalibration
from .cube.calibrate import MODEL_TYPE as CUBE, CubeCalibration
from .errors import CalibrationError
from .nonorthogonal import NonOrthogonalCalibration
from .triangular import TriangularCalibration

RESULT_TYPES: dict[str, type] = {
    AFFINE: AffineCalibration,
    "nonorthogonal": NonOrthogonalCalibration,
    "triangular": TriangularCalibration,
    CUBE: CubeCalibration,
}


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


def affine_correction(result) -> tuple[np.ndarray, np.ndarray]:
    """``(M, o)`` such that the result calibrates as ``a = M (m − o)``.

    Every accelerometer model of the seeds is affine in the reading (000 eqs. (16), (20);
    002 eq. (6)), so M and o follow from applying the model to the origin and the unit vectors.
    """
    origin = result.apply(np.zeros((1, 3)))[0]
    M = (result.apply(np.eye(3)) - origin).T
    o = -np.linalg.solve(M, origin)
    return M, o
