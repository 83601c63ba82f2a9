"""Rebuild any stored calibration result from its plain-dict form, by its type.

The registry itself lives in :class:`app.calibration.result.CalibrationResult`: every result class
registers on definition.  This module imports every model, so that all of them are known.
"""

from __future__ import annotations

from . import affine, autocal, nonorthogonal, triangular  # noqa: F401  (each registers its result)
from .cube import calibrate  # noqa: F401
from .result import CalibrationResult, registered_types


def result_from_dict(data: dict) -> CalibrationResult:
    """Return the result object whose ``to_dict()`` produced ``data``.

    Raises
    ------
    CalibrationError
        If the type is unknown or the schema version newer than this code reads.
    """
    return CalibrationResult.from_dict(data)


__all__ = ["CalibrationResult", "registered_types", "result_from_dict"]
