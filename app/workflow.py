"""The steps the API and the CLI share: logs into recordings, requests into calibrations.

Data flows one way (docs/architecture.md): the callers parse a request into the models of
:mod:`app.calibration_requests`, find its recording and hand it, through the method table of :mod:`app.methods`, to
its method's handler in :mod:`app.workflows` (one module per method family), which calls ``io`` to turn
files into arrays and one function of ``calibration``, and returns the plain form that the callers store,
export and serialise.  Nothing here knows HTTP, pydantic or the database.

This module is the workflow's one address: it names the steps of every family
(``workflow.load_log``, ``workflow.calibration_body``), so that callers need not know the family a step
belongs to.  It defines nothing itself; the families import one another, never this module.
"""

from __future__ import annotations

from app.io.log import GYR_TO_RAD_S, MAG_TO_UT
from app.workflows.autocal import AUTOCAL_UNITS, autocalibrate_file
from app.workflows.compass import compass_rests, magnetometer_reference
from app.workflows.cube import calibrate_cube_log
from app.workflows.entry import calibrate
from app.workflows.gravity import reference_gravity
from app.workflows.noise import characterise_log, one_still_file
from app.workflows.recordings import (RecordingSource, add_recording, describe_log, load_log, overview,
                                      quantization_step, require_accelerometer, require_rate, still_segments,
                                      NOMINAL_RATE_HZ)
from app.workflows.results import apply_calibration, calibration_body, holdout_metrics, pose_advice
from app.workflows.still import (Reading, calibrate_known, calibrate_unknown, choose_model, inline_unit,
                                 means_from_segments, readings_from_segments)
from app.workflows.temperature import temperature_log

__all__ = [
    "apply_calibration", "calibration_body", "holdout_metrics", "pose_advice", "RecordingSource", "add_recording",
    "describe_log", "load_log", "overview", "quantization_step", "require_accelerometer", "require_rate",
    "still_segments", "NOMINAL_RATE_HZ", "reference_gravity", "calibrate", "Reading", "calibrate_known",
    "calibrate_unknown", "choose_model", "inline_unit", "means_from_segments", "readings_from_segments",
    "calibrate_cube_log", "AUTOCAL_UNITS", "autocalibrate_file", "characterise_log", "one_still_file",
    "compass_rests", "magnetometer_reference", "temperature_log", "GYR_TO_RAD_S", "MAG_TO_UT",
]
