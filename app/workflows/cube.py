"""The cube: Särkkä et al.'s multi-position calibration of the accelerometer, the gyroscope and the
magnetometer (IEEE Sensors Journal 17(11) 2017)."""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any

from app.calibration import CalibrationError
from app.io.log import GYR_TO_RAD_S, MAG_TO_UT, LogData
from app.workflows.calibration import Calibration
from app.workflows.gravity import reference_gravity
from app.workflows.recordings import RecordingSource, require_accelerometer, require_rate
from app.workflows.requests import CubeRequest

if TYPE_CHECKING:
    from app.calibration.cube import CubeCalibration


def calibrate_cube_log(
    log: LogData,
    *,
    protocol: str | dict[str, Any],
    gravity: float,
    field_ut: float | None,
    sections: dict[str, dict[str, Any]] | None = None,
) -> CubeCalibration:
    """Särkkä et al.'s multi-position calibration of a recording's acc, gyr and optional mag.

    Gyroscope samples in deg/s are converted to rad/s and magnetometer samples in nT to µT first, so
    that the gyroscope model maps rad/s (and the magnetometer µT) to the recorded values.
    """
    from app.calibration.cube import calibrate_cube  # scipy.stats: see still.calibrate_unknown

    if log.gyr is None:
        raise CalibrationError(
            f"the recording has no gyroscope columns (found {', '.join(log.columns)}): the cube method needs "
            "gyr_x, gyr_y, gyr_z beside the accelerometer"
        )
    rate = require_rate(log.sampling_rate_hz, "cube")
    gyr = log.gyr * GYR_TO_RAD_S[log.units["gyr"]]
    mag = None if log.mag is None else log.mag * MAG_TO_UT[log.units["mag"]]
    if mag is not None and field_ut is None:
        raise CalibrationError("the recording has a magnetometer: give field_ut, the local field magnitude in µT")
    return calibrate_cube(
        log.acc,
        gyr,
        mag,
        sampling_rate_hz=rate,
        protocol=protocol,
        gravity=gravity,
        field_ut=field_ut,
        sections=sections,
    )


def cube(request: CubeRequest, recording: RecordingSource) -> Calibration:
    """Method ``cube``: a recording of the cube's positions and the turns between them, in one file."""
    if recording.meta.get("parts"):
        raise CalibrationError(
            f"the cube method follows the turns between its positions in one recording; this one is made of "
            f"{len(recording.meta['parts'])} files (one per pose), which hold no turns: calibrate the accelerometer "
            "from them with method six_position or orientations, or record the cube session in one file"
        )
    log = recording.read()
    require_accelerometer(log.channels, "cube")
    unit = log.units["acc"]
    gravity, notes = reference_gravity(unit, request.gravity, request.latitude_deg, request.height_m)
    sections = (
        None if request.sections is None else {k: {"start": v.start, "end": v.end} for k, v in request.sections.items()}
    )
    result = calibrate_cube_log(
        log, protocol=request.protocol, gravity=gravity, field_ut=request.field_ut, sections=sections
    )
    result = dataclasses.replace(result, units=dict(log.units))
    return Calibration.of(
        result, {}, unit=unit, notes=notes, device_id=request.device_id, label=request.label, **recording.source_fields
    )
