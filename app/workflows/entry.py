"""The one entry the API and the CLI both reach, through the method table (:mod:`app.methods`): the
steps every method shares around its handler."""

from __future__ import annotations

from collections.abc import Callable

from app.calibration import CalibrationError
from app.workflows.recordings import RecordingSource

Handler = Callable[..., dict]
"""A method's handler: ``handler(request, recording)`` returns the calibration's plain form."""


def calibrate(handler: Handler, request, recording: RecordingSource | None = None) -> dict:
    """Compute the calibration a request asks for with its method's handler, and return its stored form
    (unstored).

    Parameters
    ----------
    handler : callable
        The handler the method table (:mod:`app.methods`) names for ``request.method``.
    request : app.calibration_requests request model
        One of the request models (read by attribute: nothing here knows pydantic).
    recording : RecordingSource, optional
        The recording ``request.recording_id`` names, found by the caller (the API in the store
        of the calling owner, the CLI on disk).

    Returns
    -------
    dict
        The calibration's plain form with ``device_id``, ``label`` and the recording's fields.

    Raises
    ------
    CalibrationError
        Input that cannot be calibrated (InsufficientDataError: too little of it).
    LogFormatError
        A recording that cannot be read.
    """
    if getattr(request, "recording_id", None) is not None and recording is None:
        raise CalibrationError(f"recording {request.recording_id!r} was not given to the workflow")
    body = handler(request, recording)
    if recording is not None:  # what the reader decided against the header or the caller (units) comes first
        said = [w for w in recording.meta.get("warnings") or [] if w not in body["warnings"]]
        body["warnings"] = said + list(body["warnings"])
        # What the reading left open (a gyroscope's unit): a figure of that sensor hangs on it, so not ok.
        asked = [q["detail"] for q in recording.meta.get("questions") or [] if _uses(body, q["sensor"])]
        if asked and "ok" in body:
            body["ok"] = False
            body["reasons"] = asked + [r for r in body.get("reasons") or [] if r not in asked]
    return body


def _uses(body: dict, sensor: str) -> bool:
    """Whether a calibration's figures are of ``sensor`` (its model holds them, or its type names it)."""
    model = body.get("model") or {}
    return sensor in model or sensor in str(model.get("type", "")) or body.get("sensor") == sensor
