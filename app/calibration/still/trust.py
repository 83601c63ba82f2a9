"""Gates that never pass a calibration that harms: the review every still-readings fit goes through.

A fit's own gates (``gates.py``) check that it converged to plausible numbers.  They cannot tell
whether the calibration is better than none on orientations it has not seen; this review can, from
the cross-validated error (:mod:`.cross_validation`) and the fit's own readings:

1. the error on readings left out of the fit is not below their raw error: the calibration would
   make new orientations worse;
2. the norm error over the fitted readings grows (the only evidence ``six_position`` has, whose six
   readings leave nothing out);
3. no reading can be left out without the model becoming undetermined (a fit with no residual
   degrees of freedom fails its own exact-fit gate; its ratios are made null here, not a division
   by zero);
4. a parameter is not determined: its 95 % half-width exceeds the range plausible for it
   (:data:`HALF_WIDTH_LIMITS`);
5. for labelled orientations, the same growth of the norm error says the poses are not on their
   axes: the known-orientation models (Georgieva et al., ESGI'95, section 3.3) take a label as the
   exact specific force, so a tilt of a degree becomes a cross-axis term of 1.7 %.  (The readings'
   directions cannot tell: a real sensor's own cross-axis terms reach a few per cent, as in
   Georgieva et al.'s Dataset 1.)

Each failure is a reason (``ok`` false) that says what to do.
"""

from __future__ import annotations

import dataclasses

from ..shared.gates import Gates
from ..shared.norm_metrics import norm_errors
from ..shared.uncertainty import half_widths

NORM_GROWTH_TOLERANCE_MG = 0.1
"""The in-sample norm error may exceed the raw one by this much (mg of g) before it counts as grown:
the averaging noise of a few-second still reading of a phone."""

HALF_WIDTH_LIMITS = {"scale": 0.05, "cross": 0.05, "offset": 0.1}
"""Largest plausible 95 % half-width of a parameter: the range a MEMS accelerometer's datasheet allows
for it (scale within 5 % of 1, cross-axis terms within 0.05 (3°), zero-g offset within 100 mg of g).
An interval wider than that says the poses told nothing the datasheet did not."""

RATIO_METRICS = ("improvement", "norm_improvement", "fit_improvement")
"""Ratios of raw to calibrated errors: undefined (null) when the fit has no residual freedom."""


def review(result, cv: dict, *, raw_unit: bool = False):
    """The result with the trust gates' reasons added and its metrics completed.

    Parameters
    ----------
    result : StillReadingsResult
        A fit of still readings (``means``, ``apply``, ``covariance``, ``dof``, ``PARAMETERS``).
    cv : dict
        Its cross-validated error (:func:`~app.calibration.still.cross_validation.cross_validated_error`),
        or the six-position's null figures.
    raw_unit : bool
        Readings in raw counts: the raw norm error is not comparable to g, so the gates that compare
        with it are skipped.

    Returns
    -------
    StillReadingsResult
        A copy whose metrics hold ``cv`` and the in-sample ``error_before_mg`` / ``error_after_mg``,
        whose ratios are null without residual degrees of freedom, and whose reasons end with the
        failed trust gates.
    """
    inside = norm_errors(result.means, result.apply, result.gravity)
    metrics = {
        **result.metrics,
        **cv,
        "error_before_mg": inside["error_before_mg"],
        "error_after_mg": inside["error_after_mg"],
    }
    gates = Gates().merge(result)  # the fit's own reasons first
    if not raw_unit:
        gates.fail(
            worse_than_raw(
                metrics.get("cv_error_mg"),
                metrics["error_before_mg"],
                inside["count"],
                metrics.get("cv_scheme", "cross-validated"),
            )
        )
        gates.fail(_norm_grows(metrics, labelled=hasattr(result, "labels")))
    gates.fail(_no_figure(result, cv))
    if result.dof == 0:
        for key in RATIO_METRICS:
            if key in metrics:
                metrics[key] = None
    else:
        gates.fail(_undetermined(result))
    return dataclasses.replace(result, metrics=metrics, **gates.fields())


def worse_than_raw(cv_mg: float | None, raw_mg: float, count: int, scheme: str) -> list[str]:
    """The reason when the error on readings left out of the fit, ``cv_mg``, is not below their raw
    error ``raw_mg`` (both mean | |a| − g | in mg of g over ``count`` readings)."""
    if cv_mg is None or cv_mg < raw_mg:
        return []
    return [
        f"on poses left out of the fit this calibration gives {cv_mg:.2f} mg against {raw_mg:.2f} mg without it "
        f"({scheme} over {count} poses): it would make new orientations worse; add poses in other directions, "
        "or keep the sensor as it is"
    ]


def _norm_grows(metrics: dict, *, labelled: bool) -> list[str]:
    before, after = metrics["error_before_mg"], metrics["error_after_mg"]
    if after <= before + NORM_GROWTH_TOLERANCE_MG:
        return []
    what = (
        f"the calibration makes the norms of its own readings worse ({before:.2f} mg of g raw, {after:.2f} mg after): "
    )
    if labelled:
        return [
            what + "the poses are not on the axes their labels say (a tilt of a degree reads as a cross-axis "
            "term of 1.7 %), or not still; use free poses with a magnitude model (method auto or method triangular), "
            "or a jig that holds each axis vertical"
        ]
    return [what + "the readings do not fit the model (not still, or from another sensor); record the poses again"]


def _no_figure(result, cv: dict) -> list[str]:
    if result.dof == 0:  # the fit's own exact-fit gate says so
        return []
    if cv.get("cv_error_mg") is None and "cv_scheme" in cv:
        return [
            "no reading can be left out without the model becoming undetermined, so its error on new "
            "orientations is unknown; add poses in other directions"
        ]
    return []


def _undetermined(result) -> list[str]:
    """The reason naming the parameters whose 95 % half-width exceeds :data:`HALF_WIDTH_LIMITS`, and
    the poses that determine them."""
    if result.covariance is None:
        return []
    hw = half_widths(result.covariance, result.dof)
    named, poses = [], []
    for (name, kind, axes), w in zip(result.PARAMETERS, hw):
        value = w / result.gravity if kind == "offset" else w
        if value > HALF_WIDTH_LIMITS[kind]:
            named.append(f"{name} ± {1000 * value:.0f} mg of g" if kind == "offset" else f"{name} ± {value:.3f}")
            if _pose_for(kind, axes) not in poses:
                poses.append(_pose_for(kind, axes))
    if not named:
        return []
    return [
        f"not determined by these poses (95 % half-widths beyond what a datasheet allows: scales and "
        f"cross-axis terms 0.05, offsets 100 mg of g): {', '.join(named)}; add {'; '.join(poses)}"
    ]


def _pose_for(kind: str, axes: str) -> str:
    """The pose that determines a parameter of this kind on these axes."""
    if kind == "cross":
        i, j = axes[0], axes[1]
        return f"a pose tilted 45° between +{i} up and +{j} up, and its opposite"
    return f"poses with +{axes} up and −{axes} up"
