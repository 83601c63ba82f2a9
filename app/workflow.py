"""The steps the API and the CLI share: logs into recordings, requests into calibrations.

Data flows one way (docs/architecture.md): the callers parse a request into the models of
:mod:`app.requests`, find its recording and hand it, through the method table of :mod:`app.methods`, to
its method's handler in :mod:`app.workflows` (one module per method family), which calls ``io`` to turn
files into arrays and one function of ``calibration``, and returns the plain form that the callers store,
export and serialise.  Nothing here knows HTTP, pydantic or the database.

This module keeps what every family shares about a result (its stored form, its holdout figures, the
poses to add, applying it); the names that moved to :mod:`app.workflows` are still read here
(``workflow.load_log``), so that callers need not know the family a step belongs to.
"""

from __future__ import annotations

import dataclasses
import importlib

from app.verdict import verdict


def holdout_metrics(result, holdout) -> dict:
    """Norm errors of further still readings, prefixed ``holdout_`` (Georgieva et al. section 3.5, Farago et al. Table 3)."""
    if not holdout:
        return {}
    return {f"holdout_{k}": v for k, v in result.evaluate(holdout).items()}


def pose_advice(result) -> list[dict]:
    """The next poses a magnitude model's fit is advised (app.calibration.advice, D-optimal), plain."""
    from app.calibration.advice import next_poses

    return [a.to_dict() for a in next_poses(result)]


def apply_calibration(body: dict, samples, sensor: str = "acc"):
    """Calibrate samples of one sensor with a stored calibration: the result it rebuilds applies its
    correction of that sensor, or says which sensors it has (a noise characterisation corrects nothing)."""
    from app.calibration.registry import result_from_dict  # the registry imports every model

    return result_from_dict(body).apply(samples, sensor)


def calibration_body(result, extra_metrics: dict, *, unit: str, notes: list[str], **fields) -> dict:
    """The stored and returned form of a calibration: the result's plain form with the metrics and
    notes of the request and the caller's fields (device_id, label, the recording's id…); its headline
    and verdict come from the result the body rebuilds, which sees the request's metrics too."""
    if result.unit != unit:  # the core fits numbers; the caller knows their unit (the cube's is in its units)
        result = dataclasses.replace(result, unit=unit)
    body = result.to_dict()
    body["metrics"].update(extra_metrics)
    stored = type(result).from_dict(body)
    line = stored.headline()  # the line a person reads first
    if line is not None:
        body["headline"] = line
    body["warnings"] = list(body["warnings"]) + notes
    body.update(fields)
    body["verdict"] = verdict(body, stored)
    return body


_FAMILIES = {
    "app.workflows.recordings": ("RecordingSource", "add_recording", "describe_log", "load_log", "overview",
                                 "quantization_step", "require_accelerometer", "require_rate", "still_segments",
                                 "NOMINAL_RATE_HZ"),
    "app.workflows.gravity": ("reference_gravity",),
    "app.workflows.entry": ("calibrate",),
    "app.workflows.still": ("Reading", "calibrate_known", "calibrate_unknown", "choose_model", "inline_unit",
                            "means_from_segments", "readings_from_segments"),
    "app.workflows.cube": ("calibrate_cube_log",),
    "app.workflows.autocal": ("AUTOCAL_UNITS", "autocalibrate_file"),
    "app.workflows.noise": ("characterise_log", "one_still_file"),
    "app.workflows.compass": ("compass_rests", "magnetometer_reference"),
    "app.workflows.temperature": ("temperature_log",),
    "app.io.log": ("GYR_TO_RAD_S", "MAG_TO_UT"),
}
_MOVED = {name: module for module, names in _FAMILIES.items() for name in names}


def __getattr__(name: str):
    """A step that moved to its family's module (:mod:`app.workflows`), read where callers knew it: imported
    when first asked for (PEP 562), since the families import this module's four functions."""
    if name not in _MOVED:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(_MOVED[name]), name)
