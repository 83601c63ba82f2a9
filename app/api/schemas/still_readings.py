"""The response models of the fits of still readings: six_position and orientations (affine), nonorthogonal and
triangular, with the poses to add next and how a free wizard session ended."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from app.api.schemas.common import CalibrationCommon, ChoiceOut, CrossValidatedMetrics, Mat3Out, Out, Vec3Out
from app.calibration_requests import Label, Solver


class OutOfSampleMetrics(CrossValidatedMetrics):
    """Figures of readings the fit did not see: each left out in turn (cv_*), and the request's `holdout`."""

    holdout_count: int | None = Field(None, description="Held-out readings (`holdout` of the request).")
    holdout_norm_error_max: float | None = Field(
        None, description="Largest relative norm error of the held-out readings, calibrated."
    )
    holdout_norm_error_max_raw: float | None = Field(None, description="The same, raw.")
    holdout_error_before_mg: float | None = Field(
        None, description="Mean | |m| − g | of the held-out readings, raw, in mg of g."
    )
    holdout_error_after_mg: float | None = Field(None, description="The same, calibrated.")
    holdout_improvement: float | None = Field(None, description="before / after (triangular only).")


class SessionRates(Out):
    """Figures of a wizard session's captures."""

    sampling_rate_hz_min: float | None = Field(None, description="A wizard session's slowest capture rate.")
    sampling_rate_hz_max: float | None = Field(None, description="Its fastest.")


class AffineModel(Out):
    type: Literal["affine"]
    X: Mat3Out = Field(
        description=(
            "m = X a + y (Georgieva et al., ESGI'95, section 3.2), in the readings' unit per unit of the reference."
        )
    )
    y: Vec3Out = Field(description="Offset, in the readings' unit.")


class AffineUncertainty(Out):
    confidence: float = Field(description="0.95.")
    dof: int = Field(description="Residual degrees of freedom per axis, N − 4.")
    X: Mat3Out | None = Field(description="95 % half-width of each element of X; null without degrees of freedom.")
    y: Vec3Out | None
    note: str | None = None


class StillReadingsMetrics(OutOfSampleMetrics, SessionRates):
    """What every fit of still readings reports: the error on poses left out (above) and on its own
    readings (in-sample). Every figure may be null where it cannot be computed (a ratio over a zero error)."""

    count: int | None = None
    dof: int | None = None
    condition_number: float | None = None
    error_before_mg: float | None = Field(
        None, description="Mean | |m| − g | of the fitted readings, raw, in mg of g (in-sample)."
    )
    error_after_mg: float | None = Field(None, description="The same, calibrated (in-sample).")
    norm_error_max: float | None = Field(None, description="max | |a_cal| − g | / g over the fitted readings.")
    norm_error_max_raw: float | None = None


class AffineMetrics(StillReadingsMetrics):
    condition_number: float | None = Field(None, description="Of the normalised design (rows (a/g, 1)).")
    fit_error_max: float | None = Field(
        None, description="max ‖X⁻¹(m − y) − a‖ / ‖a‖ over the readings (ESGI'95 section 3.5)."
    )
    fit_error_max_raw: float | None = Field(None, description="max ‖m − a‖ / ‖a‖.")
    fit_improvement: float | None = None
    norm_improvement: float | None = None
    rms_residual: float | None = None


class AffineReading(Out):
    index: int
    up: Label | None
    mean: Vec3Out
    expected: Vec3Out
    residual: Vec3Out
    fit_error: float
    fit_error_raw: float
    norm_error: float
    norm_error_raw: float
    source: str | None = Field(
        None, description=("A recording made of several files (one per pose): the file this reading came from.")
    )


class MagnitudeReading(Out):
    index: int
    mean: Vec3Out
    calibrated: Vec3Out
    norm_error: float
    norm_error_raw: float
    source: str | None = Field(
        None, description=("A recording made of several files (one per pose): the file this reading came from.")
    )


class GyroscopeBiasOut(Out):
    """The gyroscope's bias over a wizard session's still captures (app.calibration.still.gyro_bias)."""

    rad_s: Vec3Out = Field(description="Mean of the captures' gyroscope means, per axis, rad/s.")
    half_width_rad_s: Vec3Out = Field(description="Half-width of its 95 % interval, rad/s.")
    deg_s: Vec3Out = Field(description="The bias in °/s.")
    half_width_deg_s: Vec3Out = Field(description="The half-width in °/s.")
    count: int = Field(description="Captures that carried gyroscope samples (K).")
    confidence: float = Field(description="0.95.")
    interval_from: Literal["captures", "samples"] = Field(
        description=(
            "`captures`: Student-t with K − 1 degrees of freedom on the spread of the capture means, which holds the "
            "bias's wander between captures; `samples`: a single capture, t with n − 1 on its standard error."
        )
    )
    formula: str = Field(description="The interval's formula in words.")


class StillReadingsCommon(CalibrationCommon):
    choice: ChoiceOut | None = Field(None, description="Present when the request's method was `auto`.")
    gyroscope_bias: GyroscopeBiasOut | None = Field(
        None,
        description=(
            "A six or free wizard session whose captures carried gyroscope samples: the gyroscope's bias at rest; "
            "absent otherwise."
        ),
    )
    covariance: list[list[float]] | None = Field(description="Covariance of the parameters (least squares).")
    segments_used: list[int] | None = Field(None, description="Still segments of the recording that were used.")


class AffineOut(StillReadingsCommon):
    model: AffineModel
    uncertainty: AffineUncertainty
    metrics: AffineMetrics
    readings: list[AffineReading]


class SixPositionOut(AffineOut):
    method: Literal["six_position"]


class OrientationsOut(AffineOut):
    method: Literal["orientations"]


class NonOrthogonalModel(Out):
    type: Literal["nonorthogonal"]
    s: Vec3Out = Field(description="Shifts (ESGI'95 eq. (1)), in the readings' unit.")
    b: Vec3Out = Field(description="Scales (positive).")
    phi: float = Field(description="Angles between the sensor axes, radians (ESGI'95 section 2.1).")
    psi: float
    theta: float


class NonOrthogonalUncertainty(Out):
    confidence: float
    dof: int
    s: Vec3Out | None
    b: Vec3Out | None
    phi: float | None
    psi: float | None
    theta: float | None
    note: str | None = None


class MagnitudeMetrics(StillReadingsMetrics):
    converged: bool | None = None


class NonOrthogonalMetrics(MagnitudeMetrics):
    angle_deviation_max_deg: float | None = None
    cost_17: float | None = Field(None, description="The cost of ESGI'95 eq. (17) at the solution.")
    norm_improvement: float | None = None
    rms_norm_residual: float | None = None
    rough_s: Vec3Out | None = Field(None, description="Shifts of the rough orthogonal fit (step 2 of section 2.2).")
    rough_b: Vec3Out | None = None


class PoseAdviceOut(Out):
    """One pose to add next (app.calibration.still.advice): D-optimal for the model's parameters."""

    up: Vec3Out = Field(description="Unit vector in the sensor frame that should point up (reads +g at rest).")
    words: str = Field(
        description=(
            "The pose in words, e.g. “+x up (on its left edge as you face the screen, right edge up), "
            "tilted 30° towards −z”."
        )
    )
    gain: float | None = Field(
        description=(
            "Fraction by which adding this pose (after the advised ones before it) shrinks the generalized variance "
            "det C of the parameters; null when no model is fitted yet (a free wizard session before 10 poses)."
        )
    )


ADVICE_DESCRIPTION = (
    "The three poses that would most shrink the parameters' uncertainty (D-optimal), best first; "
    "null on calibrations stored before advice existed."
)


class NonOrthogonalOut(StillReadingsCommon):
    method: Literal["nonorthogonal"]
    model: NonOrthogonalModel
    uncertainty: NonOrthogonalUncertainty
    metrics: NonOrthogonalMetrics
    readings: list[MagnitudeReading]
    advice: list[PoseAdviceOut] | None = Field(None, description=ADVICE_DESCRIPTION)


class TriangularModel(Out):
    type: Literal["triangular"]
    K: Mat3Out = Field(description="Lower-triangular, a = K (v + o) (Farago, Maczak and Gingl, IEEE Access, eq. (6)).")
    o: Vec3Out = Field(description="Offsets, in the readings' unit.")


class TriangularUncertainty(Out):
    confidence: float | None = None
    dof: int | None = None
    K: Mat3Out | None
    o: Vec3Out | None
    note: str | None = None


class TriangularMetrics(MagnitudeMetrics):
    solver: Solver
    cost_12: float | None = Field(None, description="The cost of IEEE Access eq. (12) at the solution.")
    improvement: float | None = Field(None, description="error_before_mg / error_after_mg (eq. (21)).")
    iterations: int | None = None
    noise_estimate: float | None = None
    h: float | None = Field(None, description="Finite-difference step of the descent solvers.")
    distance_to_lm: float | None = Field(None, description="Descent solvers: distance of p to the lm solution.")
    p_raw: list[int] | None = Field(None, description="fixed16/fixed32: the parameters as the integers the MCU holds.")
    q_format: str | None = None
    saturated: bool | None = None


class FreeFinish(Out):
    """How a free wizard session ended."""

    reason: Literal["target", "stopped"] = Field(
        description=(
            "`target`: the cross-validated error fell below the target with enough poses; `stopped`: the person "
            "finished first."
        )
    )
    text: str = Field(description="E.g. “target reached: 1.4 mg on new orientations”.")
    poses: int
    cv_error_mg: float | None = Field(description="metrics.cv_error_mg when the session ended.")
    target_mg: float


class TriangularOut(StillReadingsCommon):
    method: Literal["triangular"]
    solver: Solver
    model: TriangularModel
    uncertainty: TriangularUncertainty
    metrics: TriangularMetrics
    readings: list[MagnitudeReading]
    advice: list[PoseAdviceOut] | None = Field(None, description=ADVICE_DESCRIPTION)
    finish: FreeFinish | None = Field(None, description="A free wizard session's calibration: how it ended.")
