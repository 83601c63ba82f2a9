"""Rebuild any stored calibration result from its plain-dict form, by its type.

The registry itself lives in :class:`app.calibration.result.CalibrationResult`: every result class
registers on definition, and :meth:`~app.calibration.result.CalibrationResult.from_dict` loads the
models before it looks one up.
"""

from __future__ import annotations

from .result import CalibrationResult, registered_types

result_from_dict = CalibrationResult.from_dict
"""The result object whose ``to_dict()`` produced the data (CalibrationError when the type is
unknown or the schema version newer than this code reads)."""

__all__ = ["CalibrationResult", "registered_types", "result_from_dict"]
