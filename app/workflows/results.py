"""What every method family shares about a result: the figures of readings held out, the poses to add next,
and applying a stored calibration (its typed form and plain body: app.workflows.calibration)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from app.calibration.shared.result import StillReadingsResult


def holdout_metrics(result: StillReadingsResult, holdout: Sequence[Sequence[float]] | None) -> dict[str, Any]:
    """Norm errors of further still readings, prefixed ``holdout_``
    (Georgieva et al. section 3.5, Farago et al. Table 3)."""
    if not holdout:
        return {}
    return {f"holdout_{k}": v for k, v in result.evaluate(holdout).items()}


def pose_advice(result: StillReadingsResult) -> list[dict[str, Any]]:
    """The next poses a magnitude model's fit is advised (app.calibration.still.advice, D-optimal), plain."""
    from app.calibration.still.advice import next_poses

    return [a.to_dict() for a in next_poses(result)]


def apply_calibration(body: dict[str, Any], samples: ArrayLike, sensor: str = "acc") -> np.ndarray:
    """Calibrate samples of one sensor with a stored calibration: the result it rebuilds applies its
    correction of that sensor, or says which sensors it has (a noise characterisation corrects nothing)."""
    from app.calibration import registry  # from_dict imports every model

    return registry.from_dict(body).apply(samples, sensor)
