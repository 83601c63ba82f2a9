"""The calibration a device already holds, brought in from its firmware's file (method ``imported``)."""

from __future__ import annotations

import base64
import binascii

from app.io.errors import LogFormatError
from app.io.imports import CODE, read_calibration
from app.workflows.calibration import Calibration
from app.workflows.recordings import RecordingSource
from app.workflows.requests import ImportRequest


def imported(request: ImportRequest, recording: RecordingSource | None = None) -> Calibration:
    """The calibration ``request.file_base64`` holds (app.io.imports), with the device and label it is stored with:
    an :class:`~app.calibration.imported.ImportedCalibration`, or the model trical's own JSON export was written
    from."""
    try:
        data = base64.b64decode(request.file_base64, validate=True)
    except (binascii.Error, ValueError):
        raise LogFormatError("`file_base64` is not base64: send the file's bytes base64-encoded", code=CODE) from None
    found = read_calibration(data, firmware=request.firmware, instance=request.instance)
    result = found.result
    return Calibration.of(
        result,
        {},
        unit=result.unit,
        notes=[f"read as {found.recognised}"],
        device_id=request.device_id,
        label=request.label,
        **found.fields,
    )
