"""The one entry the API and the CLI both reach, through the method table (:mod:`app.methods`): the
steps every method shares around its handler."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from app.calibration import CalibrationError
from app.workflows.calibration import Calibration
from app.workflows.recordings import RecordingSource

Handler = Callable[..., Calibration]
"""A method's handler: ``handler(request, recording)`` returns the typed calibration."""


def calibrate(handler: Handler, request: Any, recording: RecordingSource | None = None) -> Calibration:
    """Compute the calibration a request asks for with its method's handler (unstored, typed: its plain form,
    headline and verdict come from :meth:`Calibration.body`, once).

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
    Calibration
        The calibration with ``device_id``, ``label`` and the recording's fields; of a recording, the reader's
        warnings first and the questions it left open among its reasons.

    Raises
    ------
    CalibrationError
        Input that cannot be calibrated (InsufficientDataError: too little of it).
    LogFormatError
        A recording that cannot be read.
    """
    if getattr(request, "recording_id", None) is not None and recording is None:
        raise CalibrationError(f"recording {request.recording_id!r} was not given to the workflow")
    calibration = handler(request, recording)
    if recording is None:
        return calibration
    # What the reader decided against the header or the caller (units) comes first; what it left open (a
    # gyroscope's unit) is a reason of a result whose figures hang on it.
    return calibration.read_from(recording.meta.get("warnings") or [], recording.meta.get("questions") or [])
