"""What every method family shares about a result: its stored form (headline and verdict from the result
the body rebuilds), the figures of readings held out, the poses to add next, and applying a stored
calibration."""

from __future__ import annotations

import dataclasses

from app.verdict import verdict


def holdout_metrics(result, holdout) -> dict:
    """Norm errors of further still readings, prefixed ``holdout_``
    (Georgieva et al. section 3.5, Farago et al. Table 3)."""
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
    from app.calibration.result import CalibrationResult  # from_dict imports every model

    return CalibrationResult.from_dict(body).apply(samples, sensor)


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
