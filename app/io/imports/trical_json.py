"""trical's own JSON export (app.io.exports.exporters ``to_json``), read back as the result that wrote it."""

from __future__ import annotations

from typing import Any

from app.calibration import registry
from app.calibration.shared.errors import CalibrationError
from app.calibration.shared.result import CalibrationResult

from ..exports.common import JSON_SCHEMA


def is_export(doc: Any) -> bool:
    """Whether a parsed JSON document is trical's export (its ``$schema``)."""
    return isinstance(doc, dict) and doc.get("$schema") == JSON_SCHEMA


def body_of(doc: dict) -> dict:
    """The stored form an export was written from, as far as the export carries it (the model, units, metrics,
    intervals, warnings; a wizard's gyroscope bias)."""
    ok = doc.get("ok", True)
    body: dict = {
        "schema_version": doc.get("schema_version", 1),
        "method": doc.get("method"),
        "model": doc.get("model") or {},
        "metrics": doc.get("metrics") or {},
        "uncertainty": doc.get("uncertainty") or {},
        "gravity": doc.get("gravity"),
        "unit": doc.get("input_unit"),
        "output_unit": doc.get("output_unit"),
        "warnings": list(doc.get("warnings") or []),
        "reasons": [] if ok is not False else ["it was exported not ok (the JSON export does not carry its reasons)"],
    }
    for key in ("read_from",):
        if key in doc:
            body[key] = doc[key]
    return body


def from_export(doc: dict) -> tuple[CalibrationResult, dict]:
    """The result an export rebuilds, and the caller's fields it carries (``gyroscope_bias``).

    Raises
    ------
    CalibrationError
        A model this trical does not know, or a document cut short.
    """
    body = body_of(doc)
    try:
        result = registry.from_dict(body)
    except (AttributeError, IndexError, KeyError, TypeError, ValueError) as exc:
        if isinstance(exc, CalibrationError):
            raise
        raise CalibrationError(f"the JSON export lacks part of its model ({type(exc).__name__}: {exc})") from None
    fields: dict = {}
    gyro = doc.get("gyroscope")
    if isinstance(gyro, dict) and gyro:
        fields["gyroscope_bias"] = {
            "rad_s": gyro["bias"],
            "half_width_rad_s": gyro["half_width"],
            "confidence": gyro["confidence"],
            "count": gyro["count"],
            "interval_from": gyro["interval_from"],
        }
    return result, fields
