"""What every method family shares about a result: the figures of readings held out, the poses to add next,
and applying a stored calibration (its typed form and plain body: app.workflows.calibration)."""

from __future__ import annotations


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
