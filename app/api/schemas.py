"""Response models of the REST API (v1), and the request models of its other resources.

The calibration request models live in :mod:`app.calibration_requests` (the CLI builds them too); the
responses here describe every field each method returns, so that ``/openapi.json`` documents them.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal, Union

from pydantic import BaseModel, ConfigDict, Field, FiniteFloat, model_validator

from app.methods import METHODS, TABLE, CalibrationIn  # noqa: F401  (re-exported: the routes name them here)
from app.calibration_requests import (  # noqa: F401  (re-exported: the routes and tests name them here)
    AccUnit,
    Solver,
    Gravity,
    AutocalIn,
    CubeIn,
    KnownOrientationIn,
    Label,
    OrientationsIn,
    ReadingIn,
    SixPositionIn,
    Strict,
    TriangularIn,
    NonOrthogonalIn,
    UnknownOrientationIn,
    Vec3,
)
from app.capture_rules import CAPTURE_S_DEFAULT, CAPTURE_S_RANGE, FREE_FIT_FROM, FREE_TARGET_MIN_POSES
from app.io.log import ACC_PHYSICAL_UNITS


# -- calibration responses -----------------------------------------------------------------------
# One model per method, in a union discriminated by `method` (OpenAPI's discriminator must be a
# top-level property). `method` fixes `model.type` one to one: six_position and orientations give
# `affine`, nonorthogonal and triangular their own type, cube `cube`, and autocal a `triangular`
# model with the fields of its pipeline.

Vec3Out = list[float]
Mat3Out = list[list[float]]


class Out(BaseModel):
    """Response models are tolerant at run time; the tests check that no field goes undescribed."""

    model_config = ConfigDict(extra="allow")


class CrossValidatedMetrics(Out):
    """What to expect on new orientations: each reading calibrated by the fit made without it."""

    cv_error_mg: float | None = Field(None, description=(
        "What to expect on new orientations: mean | |a_i| − g | in mg of g, each reading calibrated by the fit "
        "made without it (cv_scheme); null with cv_note where the fit has no redundancy."))
    cv_error_max_mg: float | None = Field(None, description="The largest of those errors.")
    cv_scheme: Literal["leave-one-out", "10-fold"] | None = None
    cv_note: str | None = None


class OutOfSampleMetrics(CrossValidatedMetrics):
    """Figures of readings the fit did not see: each left out in turn (cv_*), and the request's `holdout`."""

    holdout_count: int | None = Field(None, description="Held-out readings (`holdout` of the request).")
    holdout_norm_error_max: float | None = Field(None, description="Largest relative norm error of the held-out readings, calibrated.")
    holdout_norm_error_max_raw: float | None = Field(None, description="The same, raw.")
    holdout_error_before_mg: float | None = Field(None, description="Mean | |m| − g | of the held-out readings, raw, in mg of g.")
    holdout_error_after_mg: float | None = Field(None, description="The same, calibrated.")
    holdout_improvement: float | None = Field(None, description="before / after (triangular only).")


class SessionRates(Out):
    """Figures of a wizard session's captures."""

    sampling_rate_hz_min: float | None = Field(None, description="A wizard session's slowest capture rate.")
    sampling_rate_hz_max: float | None = Field(None, description="Its fastest.")


class AffineModel(Out):
    type: Literal["affine"]
    X: Mat3Out = Field(description="m = X a + y (Georgieva et al., ESGI'95, section 3.2), in the readings' unit per unit of the reference.")
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
    error_before_mg: float | None = Field(None, description="Mean | |m| − g | of the fitted readings, raw, in mg of g (in-sample).")
    error_after_mg: float | None = Field(None, description="The same, calibrated (in-sample).")
    norm_error_max: float | None = Field(None, description="max | |a_cal| − g | / g over the fitted readings.")
    norm_error_max_raw: float | None = None


class AffineMetrics(StillReadingsMetrics):
    condition_number: float | None = Field(None, description="Of the normalised design (rows (a/g, 1)).")
    fit_error_max: float | None = Field(None, description="max ‖X⁻¹(m − y) − a‖ / ‖a‖ over the readings (ESGI'95 section 3.5).")
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
    source: str | None = Field(None, description=(
        "A recording made of several files (one per pose): the file this reading came from."))


class MagnitudeReading(Out):
    index: int
    mean: Vec3Out
    calibrated: Vec3Out
    norm_error: float
    norm_error_raw: float
    source: str | None = Field(None, description=(
        "A recording made of several files (one per pose): the file this reading came from."))


class DegreesOut(Out):
    """A verdict's figure as the angle it can turn a level or a heading by, at worst: asin(e/r)."""

    kind: Literal["tilt", "heading"] = Field(description="`tilt`: asin(e/g) for a figure in mg; `heading`: "
                                                         "asin(e/H), H = F cos I, for µT or counts.")
    before_deg: float | None = Field(description="The raw figure's angle, degrees (null without a raw figure).")
    after_deg: float = Field(description="The calibrated figure's angle, degrees.")
    inclination_deg: float | None = Field(description="A heading's inclination I, degrees (null for a tilt).")
    inclination_source: Literal["model", "measured", "assumed"] | None = Field(description=(
        "Where I comes from: `model` (IGRF-14 at the place given), `measured` (in the turn), `assumed` (60°)."))
    words: str = Field(description="E.g. “a level off by 1.8° → 0.03°”.")


class VerdictOut(Out):
    """Whether to apply the calibration, in words (app.verdict): what a person reads first."""

    apply: bool = Field(description="Offer its files to a device: false for a calibration that must not be applied.")
    kind: Literal["apply", "no_gain", "worse", "failed", "figures"] = Field(description=(
        "`apply`; `no_gain`: passed but changes too little to matter; `worse`: its error grew; `failed`: a check "
        "failed; `figures`: a noise characterisation, which corrects nothing."))
    words: str = Field(description="E.g. “Apply it: error on new orientations 36.0 mg → 1.40 mg (a level off by 2.1° → "
                                   "0.08°).”")
    why: str = Field(description="One line more: the reason, or what the figure is.")
    before: float | None = Field(description="The figure's raw error (null where the readings are counts).")
    after: float | None = Field(description="The same, calibrated.")
    unit: Literal["mg", "µT", "counts", "°/s", "°"] | None = Field(description=(
        "mg of g, or µT for a compass (counts for a magnetometer left in counts); °/s for a temperature calibration "
        "of a gyroscope alone; ° (heading error) for a compass calibrated from a flight."))
    basis: str | None = Field(description="Which readings the figure is on, in words.")
    degrees: DegreesOut | None = Field(default=None, description=(
        "The figure as an angle (app.calibration.angles, docs/methods.md): a level's tilt for an accelerometer, a "
        "heading error for a compass; null for a figure that is no error of gravity or of the field."))


class CalibrationCommon(Out):
    id: str
    created_at: str = Field(description="UTC, ISO 8601 with milliseconds.")
    schema_version: int = Field(1, description="Version of this stored form.")
    gravity: float = Field(description="Reference magnitude in the output unit (1 for g).")
    unit: str = Field(description="Unit of the readings: m/s^2, g or raw.")
    output_unit: str = Field(description="What the calibration calibrates into.")
    ok: bool = Field(description="False when a quality gate failed; `reasons` says which.")
    verdict: VerdictOut = Field(description="Whether to apply it, in words, and the figure it stands on.")
    headline: str | None = Field(None, description=(
        "What to expect on new orientations (the cross-validated error), then the in-sample figure, "
        "labelled; every fit of still readings has one."))
    warnings: list[str]
    reasons: list[str] = []
    device_id: str | None = None
    label: str | None = None
    recording_id: str | None = Field(None, description="The recording the readings came from.")
    session_id: str | None = Field(None, description="The wizard session that solved it.")
    superseded_by: str | None = Field(None, description=(
        "The later calibration of the same recording (the same upload's content) and method, read again with "
        "other options, that superseded this one; absent while none did. It is kept and still read by id."))
    earlier: int | None = Field(None, description=(
        "How many earlier calibrations of the same recording and method this one superseded "
        "(GET /api/v1/calibrations?superseded_by=ID lists them); absent when none."))
    source: Literal["board", "phone", "px4", "ardupilot"] | None = Field(None, description=(
        "Where its readings came from: a wizard session's source (a phone, or a board's printed lines), else the "
        "recording's format (a phone app's, a board's lines, a PX4 or ArduPilot log); absent for a plain CSV or "
        "JSON. The page offers the use of that source first (app/web/uses.py DEFAULT_USES)."))
    captures: list[dict[str, Any]] | None = Field(None, description=(
        "A wizard session's captures: position, mean, std, count, sampling_rate_hz (and up for cube24 and free); "
        "`trical capture`'s: position, rows (first, after last) of its log, up, mean, std, count."))


class CandidateOut(Out):
    ok: bool
    cv_error_mg: float | None


class ChoiceOut(Out):
    """What `method: auto` chose (app.workflow.choose_model)."""

    method: Literal["six_position", "orientations", "triangular", "magnetometer"]
    why: str
    candidates: dict[str, CandidateOut] = Field(description="Every model that applied: its ok and error on poses left out.")


class GyroscopeBiasOut(Out):
    """The gyroscope's bias over a wizard session's still captures (app.calibration.gyro_bias)."""

    rad_s: Vec3Out = Field(description="Mean of the captures' gyroscope means, per axis, rad/s.")
    half_width_rad_s: Vec3Out = Field(description="Half-width of its 95 % interval, rad/s.")
    deg_s: Vec3Out = Field(description="The bias in °/s.")
    half_width_deg_s: Vec3Out = Field(description="The half-width in °/s.")
    count: int = Field(description="Captures that carried gyroscope samples (K).")
    confidence: float = Field(description="0.95.")
    interval_from: Literal["captures", "samples"] = Field(description=(
        "`captures`: Student-t with K − 1 degrees of freedom on the spread of the capture means, which holds the "
        "bias's wander between captures; `samples`: a single capture, t with n − 1 on its standard error."))
    formula: str = Field(description="The interval's formula in words.")


class StillReadingsCommon(CalibrationCommon):
    choice: ChoiceOut | None = Field(None, description="Present when the request's method was `auto`.")
    gyroscope_bias: GyroscopeBiasOut | None = Field(None, description=(
        "A six or free wizard session whose captures carried gyroscope samples: the gyroscope's bias at rest; "
        "absent otherwise."))
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
    """One pose to add next (app.calibration.advice): D-optimal for the model's parameters."""

    up: Vec3Out = Field(description="Unit vector in the sensor frame that should point up (reads +g at rest).")
    words: str = Field(description="The pose in words, e.g. “+x up (on its left edge as you face the screen, right edge up), tilted 30° towards −z”.")
    gain: float | None = Field(description=(
        "Fraction by which adding this pose (after the advised ones before it) shrinks the generalized variance "
        "det C of the parameters; null when no model is fitted yet (a free wizard session before 10 poses)."))


ADVICE_DESCRIPTION = ("The three poses that would most shrink the parameters' uncertainty (D-optimal), best first; "
                      "null on calibrations stored before advice existed.")


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

    reason: Literal["target", "stopped"] = Field(description=(
        "`target`: the cross-validated error fell below the target with enough poses; `stopped`: the person finished first."))
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


class AutocalMetrics(CrossValidatedMetrics):
    """cv_* over the calibration points; error_*_mg over the control points, held out of the fit."""

    count: int | None = Field(None, description="Calibration points selected.")
    count_control: int | None = Field(None, description="Control points held out.")
    error_before_mg: float | None = Field(None, description="On the control points, raw (Farago et al., Table 3).")
    error_after_mg: float | None = Field(None, description="On the control points, calibrated.")
    improvement_pct: float | None = None
    fit_condition_number: float | None = None
    fit_converged: bool | None = None
    fit_error_before_mg: float | None = None
    fit_error_after_mg: float | None = None
    fit_iterations: int | None = None
    fit_noise_estimate: float | None = None
    fit_norm_error_max: float | None = None


class ComparisonRow(Out):
    K: Mat3Out | None
    o: Vec3Out | None
    ok: bool | None
    count: int | None
    count_control: int | None
    reasons: list[str]
    error_before_mg: float | None
    error_after_mg: float | None
    improvement_pct: float | None


class RecordingSummary(Out):
    format: str | None
    n_samples: int | None
    sampling_rate_hz: float | None
    duration_s: float | None


class AutocalOut(CalibrationCommon):
    method: Literal["autocal"]
    solver: Solver
    model: TriangularModel
    uncertainty: TriangularUncertainty
    metrics: AutocalMetrics
    covariance: list[list[float]] | None
    readings: list[MagnitudeReading]
    comparison: dict[str, ComparisonRow] = Field(description="Method → its errors on the control points (Table 3).")
    selection: dict[str, int] = Field(description="Calibration points per subset C_ij (eq. (10)).")
    control_selection: dict[str, int]
    detection: dict[str, Any] = Field(description="Counts of the rest detection (segments, rest, moving, NaN, idle).")
    points: list[Vec3Out]
    control: list[Vec3Out]
    point_starts: list[int]
    control_starts: list[int]
    recording: RecordingSummary


class FieldSensorModel(Out):
    S: Mat3Out = Field(description="raw = S f + b (Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (1)).")
    b: Vec3Out
    D: Vec3Out = Field(description="Scale factors, S = D (D⁻¹S).")
    misalignment: Mat3Out = Field(description="D⁻¹S.")
    alpha_deg: float | None = Field(None, description="Reference direction angle α (eqs. (6)–(8)).")
    beta_deg: float | None = None


class GyroModel(Out):
    S: Mat3Out
    S_inv: Mat3Out
    b: Vec3Out = Field(description="Bias, in the recorded unit.")
    D: Vec3Out
    misalignment: Mat3Out
    lambda_: float | None = Field(None, alias="lambda", description="Tikhonov weight λ (section IV-A).")


class CubeModel(Out):
    type: Literal["cube"]
    acc: FieldSensorModel | None
    gyr: GyroModel | None
    mag: FieldSensorModel | None


class CubeUncertainty(Out):
    confidence: float
    acc: dict[str, Any] | None = Field(description="95 % half-widths mirroring model.acc (Appendix A).")
    gyr: dict[str, Any] | None = Field(description="Mirroring model.gyr (Appendix B).")
    mag: dict[str, Any] | None


class CubeMetrics(Out):
    duration_s: float | None = None
    n_samples: int | None = None
    n_positions_found: int | None = None
    n_still_found: int | None = Field(None, description="Still segments detected before they were matched to the protocol.")
    n_handling: int | None = Field(None, description="Rests and moves left out as handling (pauses, re-placements, moves by hand).")
    positions_from: Literal["detected", "sections"] | None = Field(
        None, description="`detected` from the gyroscope, or `sections` (an annotated section list).")
    n_positions_used: int | None = None
    returned_to_start: bool | None = None
    rotations_used: list[int] | None = None


class RotationCheck(Out):
    rotation: int
    label: str | None
    from_position: int
    to_position: int
    ok: bool
    message: str
    expected_up: str | None = None
    observed_up: str | None = None
    end_error_deg: float | None = None
    end_quaternion: list[float] | None = None
    expected_quaternion: list[float] | None = None
    max_element_difference: float | None = None
    tolerance: float | None = None
    saturated: bool | None = None


class CubeOut(CalibrationCommon):
    method: Literal["cube"]
    model: CubeModel
    uncertainty: CubeUncertainty
    metrics: CubeMetrics
    units: dict[str, str] = Field(description="Each sensor's recorded unit.")
    sequence: list[RotationCheck] = Field(description="The check of every rotation (section VII-A-1).")
    first_wrong_rotation: int | None
    protocol: dict[str, Any] = Field(description="name, rotations, ups, attitudes, heading_known, reading_positions "
                                                 "(for ferraris: the order the recording made it in).")
    segments: dict[str, Any] | None = Field(description="Still intervals and rotations matched to the protocol (sample "
                                                        "indices), source, n_still_found and the handling left out.")
    drift: dict[str, Any] = Field(description="Sensor → drift removed (return to position 1).")
    sampling_rate_hz: float
    field_ut: float | None
    details: dict[str, Any] = Field(description="Each sensor's full fit: covariance, positions, metrics.")


Figures3 = list[float | None]


class SensorNoiseModel(Out):
    unit: str = Field(description="The sensor's unit (gyroscope rad/s, accelerometer m/s^2, magnetometer uT).")
    bias: Vec3Out = Field(description="Mean of the still part, per axis.")
    noise_density: Figures3 = Field(description="N, white noise: the −½ line at τ = 1 s (IEEE Std 952, Annex C); "
                                                "null where not seen.")
    random_walk: Figures3 = Field(description="K, the +½ line at τ = 3 s; null where the recording is too short.")
    bias_instability: Figures3 = Field(description="B, the flat floor / 0.664; null where not seen.")
    noise_density_unit: str = Field(description="e.g. rad/s/√Hz (Kalibr's gyroscope_noise_density).")
    random_walk_unit: str = Field(description="e.g. rad/s²/√Hz (Kalibr's gyroscope_random_walk).")
    bias_instability_unit: str


class NoiseModel(Out):
    type: Literal["noise"]
    acc: SensorNoiseModel | None = None
    gyr: SensorNoiseModel | None = None
    mag: SensorNoiseModel | None = None


Intervals3 = list[list[float] | None]


class SensorNoiseUncertainty(Out):
    noise_density: Intervals3 = Field(description="95 % interval [lo, hi] per axis (χ², equivalent degrees of freedom).")
    random_walk: Intervals3
    bias_instability: Intervals3
    bias: Intervals3


class NoiseUncertainty(Out):
    confidence: float
    acc: SensorNoiseUncertainty | None = None
    gyr: SensorNoiseUncertainty | None = None
    mag: SensorNoiseUncertainty | None = None


class AllanTable(Out):
    tau_s: list[float] = Field(description="τ = m / fs, at least 10 per decade, up to the longest the recording supports.")
    value: list[Vec3Out] = Field(description="Overlapping Allan deviation (n_τ × 3), in the sensor's unit.")
    lo: list[Vec3Out] = Field(description="Lower end of each point's 95 % interval.")
    hi: list[Vec3Out] = Field(description="Upper end.")
    edf: list[Vec3Out] = Field(description="Equivalent degrees of freedom of each point (NIST SP 1065, Table 5).")
    n_terms: list[int] = Field(description="Second differences summed at each τ.")


class SensorNoiseMetrics(Out):
    tau_noise_density_s: Figures3 = Field(description="The τ each axis's N was read at.")
    tau_bias_instability_s: Figures3
    tau_random_walk_s: Figures3
    adev_min: Vec3Out = Field(description="The curve's minimum (B ≥ it / 0.664 holds the other terms too).")
    tau_adev_min_s: Vec3Out
    bias_standard_error: Vec3Out = Field(description="Standard error of the bias: the fitted Allan deviation at the duration.")


class NoiseMetrics(Out):
    acc: SensorNoiseMetrics | None = None
    gyr: SensorNoiseMetrics | None = None
    mag: SensorNoiseMetrics | None = None


class StillPart(Out):
    start: int = Field(description="First sample used.")
    end: int = Field(description="The sample after the last one used.")
    n_samples: int
    fraction: float = Field(description="Of the recording.")
    detected_from: str = Field(description="The sensors whose stillness was tested, joined by \", \" (every sensor the recording holds: still on all of them).")


class NoiseOut(CalibrationCommon):
    method: Literal["noise"]
    gravity: float | None = Field(None, description="Not used by a noise characterisation.")
    model: NoiseModel
    uncertainty: NoiseUncertainty
    metrics: NoiseMetrics
    adev: dict[str, AllanTable] = Field(description="Sensor → its Allan deviation table.")
    sampling_rate_hz: float
    duration_s: float = Field(description="Of the still part used.")
    still: StillPart | None


class MagnetometerModel(Out):
    type: Literal["magnetometer"]
    M: Mat3Out = Field(description="Soft iron: symmetric 3×3, calibrated h = M (m − b).")
    b: Vec3Out = Field(description="Hard iron in the readings' unit (µT).")


class MagnetometerUncertainty(Out):
    confidence: float
    dof: int = Field(description="Residual degrees of freedom (readings − 9).")
    M: Mat3Out | None = Field(description="95 % half-widths of M's entries (symmetric); null when undetermined.")
    b: Vec3Out | None = Field(description="95 % half-widths of b.")


class MagnetometerMetrics(Out):
    field_ut: float = Field(description="The field's magnitude F the calibrated readings take.")
    field_source: Literal["given", "model", "estimated"] = Field(
        description="field_ut as given, from the geomagnetic model at the place and date, or estimated (det M = 1).")
    field_model: str | None = Field(None, description="The geomagnetic model used, e.g. IGRF-14.")
    field_date: str | None = Field(None, description="The day the model was evaluated for.")
    inclination_deg: float | None = Field(description="The model's dip below the horizontal (null without a place).")
    declination_deg: float | None = Field(description="The model's declination, east positive.")
    norm_spread_ut: float = Field(description="5–95 % range of |h| over the recording, calibrated.")
    norm_spread_raw_ut: float = Field(description="The same of the raw readings' magnitude.")
    coverage: float = Field(description="Share of the 20 icosahedron faces the calibrated directions reach.")
    missing_directions: list[str] = Field(description="Faces not reached, e.g. +z+y (mostly +z, towards +y).")
    thickness: float = Field(description=(
        "How far the readings leave their best plane: the third singular value of the centred readings over "
        "the first (0 for a turn kept flat, 0.65 or more through all directions; below 0.1 refused)."))
    fit_stage: Literal["refined", "closed form", "sphere", "centre"] = Field(description=(
        "What M and b are: the refined fit, or, when its refinement ran away from the readings (no ellipsoid "
        "fits them), the closed-form ellipsoid, the sphere (hard iron only) or the readings' own centre, shown "
        "to draw them only (ok is then false)."))
    count: int
    fit_error_ut: float = Field(description="RMS of |h| − F on the readings fitted (in-sample).")
    raw_error_ut: float | None = Field(description="RMS of |m| − F of the readings as they are (null for raw counts).")
    cv_error_ut: float | None = Field(description=(
        "What to expect on new directions: RMS of |h| − F, each face's readings calibrated by the fit made "
        "without that face; null with cv_note when such a fit is undetermined."))
    cv_error_max_ut: float | None = Field(description="RMS of the worst face.")
    cv_scheme: str
    cv_note: str | None = None
    noise_ut: float = Field(description="Residual standard deviation.")
    correlation_inflation: float = Field(description="Factor on the covariance for residuals correlated in time.")
    measured_inclination_deg: float | None = Field(description=(
        "The calibrated field's dip measured against gravity at the accelerometer's rests; null without them."))
    rests: int = Field(description="Accelerometer rests used for measured_inclination_deg.")


class MagnetometerSamples(Out):
    raw_ut: list[Vec3Out] = Field(description="Up to 600 raw readings, evenly spaced in time, for drawing.")


class MagnetometerOut(CalibrationCommon):
    method: Literal["magnetometer"]
    gravity: float | None = Field(None, description="Not used by a compass calibration.")
    model: MagnetometerModel
    uncertainty: MagnetometerUncertainty
    metrics: MagnetometerMetrics
    covariance: list[list[float]] | None = Field(description="9×9, of (M_xx, M_yy, M_zz, M_xy, M_xz, M_yz, b).")
    samples: MagnetometerSamples
    choice: ChoiceOut | None = Field(None, description=(
        "Present when the request's method was `auto` on a recording of the magnetometer alone."))


class SensorTemperatureModel(Out):
    unit: Literal["m/s^2", "rad/s"] = Field(description="The offsets' unit (PX4's and ArduPilot's).")
    t_ref_c: float = Field(description="T_ref: the middle of the recorded range (PX4's process_sensor_caldata.py).")
    t_min_c: float = Field(description="The coldest temperature recorded; the firmware clamps below it.")
    t_max_c: float = Field(description="The warmest.")
    relative: bool = Field(description="True for the accelerometer: X0 = 0, the drift relative to its reading at "
                                       "T_ref (gravity's projection is unknown without poses).")
    order: list[int] = Field(description="Per axis, the order (1–3) chosen on bands of temperature left out.")
    coefficients: list[list[float]] = Field(description="3×4: per axis X0…X3 of o(T) = Σ X_k dT^k, "
                                                        "dT = clamp(T, t_min_c, t_max_c) − t_ref_c; subtracted.")


class TemperatureModel(Out):
    type: Literal["temperature"]
    acc: SensorTemperatureModel | None = None
    gyr: SensorTemperatureModel | None = None


class SensorTemperatureUncertainty(Out):
    coefficients: list[list[float]] = Field(description="95 % half-widths of the coefficients (0 where not fitted).")
    dof: list[float] = Field(description="Per axis, the effective residual degrees of freedom of the Student-t.")
    autocorrelation: list[float] = Field(description="Per axis, the lag-1 autocorrelation of the bins' residuals "
                                                     "the covariance was inflated by (0 when negative).")
    covariance: list[list[list[float]]] = Field(description="Per axis, the 4×4 covariance of X0…X3.")
    random_walk: list[float] = Field(description="Per axis, the bias's random walk in time estimated beside the bins' "
                                                 "scatter (REML), in the unit per √s: 0 when none is seen.")


class TemperatureUncertainty(Out):
    confidence: float
    acc: SensorTemperatureUncertainty | None = None
    gyr: SensorTemperatureUncertainty | None = None


class SensorTemperatureMetrics(Out):
    unit: Literal["mg", "deg/s"] = Field(description="The unit of the figures below (mg of 9.80665 m/s², °/s).")
    span_c: float
    drift_raw: Vec3Out = Field(description="Peak-to-peak of the bins' offsets over the range, raw, per axis.")
    drift_after: Vec3Out = Field(description="The same after the fit's correction (in-sample).")
    drift_cv: Vec3Out = Field(description="The same, each bin corrected by the fit made without its band.")
    cv_error: Vec3Out = Field(description="RMS error on bands left out, per axis, of the chosen order.")
    cv_error_raw: Vec3Out = Field(description="The same with no correction (a constant offset).")
    cv_error_by_order: list[Vec3Out] = Field(description="Per axis, orders 1, 2, 3.")
    drift_raw_max: float
    drift_cv_max: float
    n_samples: int
    n_bins: int
    samples_per_band: list[int]
    bins_per_band: list[int]


class TemperatureMetrics(Out):
    acc: SensorTemperatureMetrics | None = None
    gyr: SensorTemperatureMetrics | None = None


class TemperatureBins(Out):
    t_c: list[float] = Field(description="Mean temperature of each bin.")
    offset: list[Vec3Out] = Field(description="Mean offset of each bin (the accelerometer's relative to T_ref).")
    count: list[int]


class TemperatureCurve(Out):
    t_c: list[float]
    offset: list[Vec3Out] = Field(description="The fitted offset at each temperature.")
    half_width: list[Vec3Out] = Field(description="Its 95 % half-width.")


class TemperatureOut(CalibrationCommon):
    method: Literal["temperature"]
    gravity: float | None = Field(None, description="Not used by a temperature calibration.")
    model: TemperatureModel
    uncertainty: TemperatureUncertainty
    metrics: TemperatureMetrics
    bins: dict[str, TemperatureBins] = Field(description="Sensor → the binned readings the fit saw.")
    curve: dict[str, TemperatureCurve] = Field(description="Sensor → the fit and its band over the range.")
    sensor_ids: dict[str, int] | None = Field(
        None, description="Sensor → the firmware's device id of the sensor a flight log's IMU was read from (PX4's "
                          "TC_A0_ID, TC_G0_ID in the px4 export); absent for other recordings.")


class CompassFlightModel(Out):
    type: Literal["compass_flight"]
    M: Mat3Out = Field(description="Soft iron, symmetric (identity or diagonal for the simpler structures): "
                                   "h = M (Q m − b − k p).")
    b: Vec3Out = Field(description="Offsets in µT, in the body frame.")
    k: Vec3Out = Field(description="Motor interference, µT per A (current) or per unit throttle 0–1; zeros without.")
    Q: Mat3Out = Field(description="The rotation from the axes the log gives the raw readings in onto the body frame.")


class CompassFlightUncertainty(Out):
    confidence: float
    M: Mat3Out | None = Field(None, description="95 % half-widths of M's entries; null where not fitted.")
    b: Vec3Out | None = Field(None, description="95 % half-widths of b, µT.")
    k: Vec3Out | None = Field(None, description="95 % half-widths of k; null without a motor term.")


class CompassFlightMetrics(Out):
    heading_error_before_deg: float | None = Field(
        None, description="Rms heading error on flight segments left out, with the firmware's own calibration.")
    heading_error_after_deg: float | None = Field(None, description="The same with this calibration.")
    heading_error_before_p95_deg: float | None = Field(None, description="95th percentile of |error| before.")
    heading_error_after_p95_deg: float | None = Field(None, description="95th percentile of |error| after.")
    coverage: float = Field(description="Share of the 20 directions the expected field reached in the body frame.")
    n_samples: int = Field(description="Compass samples fitted (inside the attitude's and the power's spans).")
    field_ut: float = Field(description="The geomagnetic model's field at the place and date, µT.")
    inclination_deg: float
    declination_deg: float
    field_model: str
    field_date: str


class CompassFlightOut(CalibrationCommon):
    method: Literal["compass_flight"]
    gravity: float | None = Field(None, description="Not used by a compass calibration.")
    model: CompassFlightModel
    uncertainty: CompassFlightUncertainty
    metrics: CompassFlightMetrics
    flight: dict[str, Any] = Field(description=(
        "The log and the fit: firmware, generation, instance, raw_how (how the raw readings were had), structure "
        "(offsets, scale, soft_iron), motor (current, throttle or null), rotation_found, rotation_nearest "
        "({ardupilot, px4, name}), angle_left_deg, orientation_agrees, frame_to_body, stored (the firmware's own "
        "calibration), attitude_source, power_source, place, models (each candidate's error on segments left out), "
        "intervals."))
    series: dict[str, Any] = Field(description=(
        "At most 600 samples over the flight for drawing: time_s, expected, corrected, firmware (µT, body frame), "
        "field_magnitude, power, heading_error_before, heading_error_after (degrees)."))


RESPONSE_MODELS = {method.name: globals()[method.response] for method in TABLE if method.response is not None}
"""Each method's response model, named by the method table (app.methods); ``auto`` answers as the method it chose."""

CalibrationOut = Annotated[Union[tuple(RESPONSE_MODELS.values())], Field(discriminator="method")]
"""A stored calibration, by method."""


class CalibrationList(BaseModel):
    items: list[CalibrationOut]


class ScaleOut(BaseModel):
    op: Literal["/", "*"] = Field(description="Counts `op` value gives the calibration's input unit.")
    value: float
    words: str = Field(description="What the figure is, and where it comes from.")
    known: bool = Field(description="True when the upload named the part (chip, lsb_per_g); false for a common "
                                    "part's figure the person should check against the datasheet.")


class CorrectionOut(BaseModel):
    M: Mat3Out = Field(description="f = M (m − o): what a reading is multiplied by after the offset is taken off.")
    o: Vec3Out = Field(description="The offset taken off each reading, in the input unit.")
    input_unit: str | None
    output_unit: str | None
    source: str = Field(description="How M and o come from the model's own parameters (e.g. M = X⁻¹, o = y).")


class FirmwareFiguresOut(BaseModel):
    target: str = Field(description="ArduPilot or PX4.")
    count: int = Field(description="Still readings the offsets and scales were fitted on (14 directions of trical's "
                                   "model when the calibration holds fewer than 6).")
    from_readings: bool = Field(description="True when fitted on the calibration's own still readings.")
    firmware_max_mg: float = Field(description="Largest | |a| − g | of those readings with the exported offsets and "
                                               "scales, applied by the firmware's formula, in mg.")
    firmware_mean_mg: float
    raw_max_mg: float = Field(description="The same readings raw.")
    raw_mean_mg: float
    full_max_mg: float = Field(description="The same readings with trical's full correction M (m − o).")
    full_mean_mg: float
    any_direction_max_mg: float = Field(description="The exported model's largest norm error over every direction, on "
                                                    "readings trical's full model puts at magnitude g.")
    rotation_deg: float = Field(description="The rotation of M = R P: the table's tilt or the board's mounting, which "
                                            "the firmware's level calibration takes.")
    nonorthogonality_mg: float = Field(description="g ‖I − D P⁻¹‖₂: what the axes' non-orthogonality makes of a "
                                                   "reading, which no offset or scale holds.")
    improves: bool = Field(description="Whether firmware_max_mg is below raw_max_mg: the page offers the firmware's "
                                       "file only then.")
    words: str = Field(description="One sentence for the page.")


class SnippetsOut(BaseModel):
    corrections: dict[str, CorrectionOut] = Field(description="Each sensor's correction, by acc, gyr, mag.")
    c: str = Field(description="Lines at file scope over the C header (C89 and later): its #include, then per sensor "
                               "a function trical_<sensor>_calibrate that scales a driver's reading to the header's "
                               "unit and passes it through trical_<sensor>_apply, the call for one reading in a "
                               "comment.")
    python: str = Field(description="numpy over the JSON export.")
    javascript: str = Field(description="JavaScript over the JSON export, for a phone app.")
    functions: dict[str, str] = Field(description="The C header's apply function of each sensor.")
    calibrate: dict[str, str] = Field(default_factory=dict,
                                      description="The C lines' function of each sensor, taking a driver's reading.")
    scales: dict[str, ScaleOut | None] = Field(description="How a sensor's int16 counts become the input unit; "
                                                           "null when the calibration takes them as they are.")
    firmware: dict[str, FirmwareFiguresOut] = Field(
        default_factory=dict, description="By export format (ardupilot, px4): what the firmware reaches with the "
                                          "exported offsets and scales; absent where that export is refused.")


class LinkOut(BaseModel):
    code: str = Field(description="Ten letters and digits, typed or scanned on the other device.")
    calibration_id: str
    created_at: str
    expires_at: str = Field(description="After this (TRICAL_LINK_TTL_MIN from its making) the link reads nothing.")
    url: str = Field(description="The link's page, /s/CODE, on this server.")
    qr: str = Field(description="The QR code of url, an SVG data: URI.")


class LinkOpened(BaseModel):
    code: str
    calibration_id: str
    expires_at: str
    token: str = Field(description="`Authorization: Bearer` value that reads this calibration (and no other) "
                                   "until expires_at.")


class ApplyIn(Strict):
    samples: Annotated[list[Vec3], Field(min_length=1, max_length=1_000_000)]
    sensor: Literal["acc", "gyr", "mag"] = Field("acc", description="Which sensor's model to apply (cube).")


class ApplyOut(BaseModel):
    samples: list[list[float]]
    unit: str


class SegmentOut(BaseModel):
    index: int
    start: int
    end: int
    acc_mean: list[float]
    acc_std: list[float]
    up: str | None
    count: int
    source: str | None = Field(None, description="A recording made of several files: the file the segment is in.")
    part: int | None = Field(None, description="The index of that file in `parts`.")
    pose_from_name: str | None = Field(None, description=(
        "The up axis the file's name gives (x_axis_pos → +x, z_down → -z), when it gives one; the data decide `up`, "
        "and a note names a file whose name they contradict."))


class PartOut(BaseModel):
    """One file of a recording made of several files (one per pose), in the order given."""

    index: int
    filename: str = Field(description="The file's name as uploaded (in a zip: its name without folders).")
    start: int = Field(description="Its first sample in the recording.")
    end: int = Field(description="The sample after its last.")
    n_samples: int
    sampling_rate_hz: float
    pose_from_name: str | None = Field(None, description="The up axis its name gives, if any.")


class ReadWithOut(BaseModel):
    """What the upload told the reader, kept so that the stored file is read again the same way."""

    format: str
    units: dict[str, str]
    lsb_per_g: float | None
    columns: str | None
    chip: str | None = Field(None, description="The parts the upload named (app.io.formats.chips).")
    sampling_rate_hz: float | None = Field(None, description="The rate the upload gave (null: the file's own).")
    sign: Literal[1, -1] = Field(description="The factor applied to the file's accelerations.")
    instance: int | None = Field(None, description="A flight controller's log: the IMU instance asked (null: the default).")
    mag_instance: int | None = Field(None, description="A flight controller's log: the compass instance asked.")


class DeviceOut(BaseModel):
    """A flight controller's device id decoded (PX4 and ArduPilot pack it alike)."""

    bus_type: str
    bus: int
    address: int
    devtype: int


class InstanceOut(BaseModel):
    """One sensor instance of a flight controller's log."""

    sensor: Literal["acc", "gyr", "mag"]
    instance: int = Field(description="PX4's multi_id, ArduPilot's I (or the 2 of IMU2, less one).")
    source: str = Field(description="The message: sensor_accel, sensor_gyro, sensor_mag, sensor_combined; IMU, ACC, "
                                    "GYR, MAG.")
    device_id: int | None = Field(None, description="The firmware's device id (ArduPilot: from INS_ACC_ID … parameters).")
    device: DeviceOut | None = None
    n_samples: int
    sampling_rate_hz: float | None = Field(None, description="From the span: (N − 1)/(t_last − t_first).")
    temperature_min_c: float | None = None
    temperature_max_c: float | None = None


class FlightOut(BaseModel):
    """What a flight controller's log holds, and what was read of it (app.io.formats.flight_log)."""

    instances: list[InstanceOut]
    imu: dict = Field(description="The IMU read: instance, source, gyr_source.")
    mag: dict | None = Field(None, description="The compass the compass methods read: instance, source.")
    clock: Literal["imu", "mag"] = Field("imu", description="The samples are on the IMU's times; the compass methods "
                                                            "read the log again on the compass's.")


class TemperatureRangeOut(BaseModel):
    min: float
    max: float


class GapOut(BaseModel):
    index: int = Field(description="The first sample after the gap.")
    t_s: float = Field(description="Where the gap starts, seconds from the first sample.")
    missing_s: float = Field(description="Time lost: the step less one sampling interval.")


class TimingOut(BaseModel):
    """How the sampling rate was decided (app.io.formats.timing), and what the time column showed."""

    source: Literal["sampling_rate_hz", "file", "time column", "none"] = Field(description=(
        "The upload's sampling_rate_hz, the file's metadata, the time column's span, or none (no rate)."))
    sampling_rate_hz: float | None
    jitter: float | None = Field(None, description=(
        "Standard deviation of the time column's steps (gaps left out) over the sampling interval; above 0.2 "
        "the timestamps are a host's arrival times and a note says so."))
    median_step_s: float | None = None
    gaps: list[GapOut] = Field([], description="Where samples were lost; still segments do not span them.")
    missing_s: float = Field(0.0, description="Time lost in all gaps.")


class LogOverview(BaseModel):
    """The log's norm in at most 300 bins (app.workflow.overview), for a plot with the still segments."""

    sensor: Literal["acc", "mag", "gyr"] = Field(description=(
        "The accelerometer's norm; in a log without it the magnetometer's, else the gyroscope's."))
    unit: str | None
    t_s: list[float] | None = Field(description="Start of each bin, seconds from the first sample; null in a log "
                                                "without a sampling rate.")
    start: list[int] | None = Field(None, description="Start of each bin, in samples.")
    low: list[float | None] = Field(description="Smallest norm in the bin (null: no finite sample).")
    high: list[float | None] = Field(description="Largest.")
    temperature_c: list[float | None] | None = Field(None, description=(
        "A log that records the sensor's temperature (a flight controller's IMU, a temp_c column): each bin's "
        "mean temperature, °C."))


class RecordingOut(BaseModel):
    model_config = ConfigDict(extra="allow")

    id: str
    created_at: str
    format: str
    filename: str | None = None
    n_samples: int
    sampling_rate_hz: float | None = Field(description=(
        "The sensor's rate (timing says how it was decided); null when the file has no time column and none was "
        "given: the still poses and the compass need none, noise, cube and autocal ask for it."))
    duration_s: float | None = None
    timing: TimingOut | None = Field(None, description="Absent from recordings stored before it existed.")
    channels: list[str]
    units: dict[str, str]
    columns: list[str] = Field([], description="The file's column names (or those `columns` gave).")
    notes: list[str] = Field([], description="What the reader decided: sign negated, unit inferred, no header row.")
    warnings: list[str] = Field([], description="What the reader decided against the header or the upload's fields "
                                                "(a unit the data contradict), and sensors left in counts; every "
                                                "calibration of the recording repeats them.")
    questions: list[dict[str, str]] = Field([], description="What the data leave open and a figure hangs on "
                                            "(`sensor`, `detail`: a gyroscope's unit neither its data nor the "
                                            "upload say): a calibration of that sensor is not ok, its reasons ask.")
    quantization_step: float | None = None
    sign: Literal[1, -1] = Field(1, description="-1 when the accelerations were negated (iOS Core Motion's sign).")
    read_with: ReadWithOut | None = Field(None, description="Absent from recordings stored before it existed.")
    content_sha256: str | None = Field(None, description=(
        "SHA-256 of the upload (of several files, their names and contents in order): the same upload read again "
        "with other options has the same one, and its calibrations by one method supersede each other. Absent "
        "from recordings stored before it existed."))
    segments: list[SegmentOut]
    parts: list[PartOut] | None = Field(None, description=(
        "A recording made of several files (several `file` parts, or a zip of log files): each file, in order; "
        "absent for one file."))
    overview: LogOverview | None = Field(None, description="For a plot of the log; absent from recordings stored "
                                                           "before it existed.")
    flight: FlightOut | None = Field(None, description="A flight controller's log (PX4 ULog, ArduPilot DataFlash): "
                                                       "its sensor instances; absent for other logs.")
    temperature_c: TemperatureRangeOut | None = Field(None, description=(
        "The read IMU's temperature range in °C, when the log records it."))


class SessionIn(Strict):
    """A guided wizard session (issue 6): the page captures each pose into it, then solves it."""

    protocol: Literal["six", "cube24", "free"] = Field("six", description=(
        "`six` (any order), `cube24` (fixed order) or `free` (still poses in any direction, 12 or more)."))
    capture_s: Annotated[float, Field(ge=CAPTURE_S_RANGE[0], le=CAPTURE_S_RANGE[1], allow_inf_nan=False)] = Field(
        CAPTURE_S_DEFAULT, description="Seconds captured per position.")
    unit: Literal[ACC_PHYSICAL_UNITS] = Field("m/s^2", description="Unit of the samples the page sends.")
    gravity: Gravity | None = None
    latitude_deg: Annotated[float, Field(ge=-90, le=90)] | None = None
    height_m: Annotated[float, Field(ge=-12000, le=100000)] | None = None
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None
    target_mg: Annotated[float, Field(gt=0, le=1000, allow_inf_nan=False)] | None = Field(None, description=(
        "free: the cross-validated error in mg of g below which the session is done; default TRICAL_FREE_TARGET_MG."))
    source: Literal["phone", "board"] = Field("phone", description=(
        "What the page reads: the phone's motion events (`phone`: the result notes the browser's rounding and the "
        "system's own calibration) or a board's printed lines (`board`: neither applies)."))


class SignIn(Strict):
    """How the page brought the samples to the W3C sign (at rest the up axis reads +g)."""

    convention: Literal["w3c", "ios"] = Field("w3c", description="The sign the browser reported in.")
    detected_from: Literal["orientation", "platform", "default"] = "default"


CubePosition = Literal["1", "2", "3", "4", "5", "6", "7", "8", "9", "10", "11", "12",
                       "13", "14", "15", "16", "17", "18", "19", "20", "21", "22", "23", "24"]


class MotionIn(Strict):
    """The samples of the move that led to a cube position, since the previous capture ended."""

    t_ms: Annotated[list[FiniteFloat], Field(min_length=2, max_length=200_000)]
    gyr: Annotated[list[Vec3], Field(min_length=2, max_length=200_000)]
    acc: Annotated[list[Vec3], Field(max_length=200_000)] | None = None

    @model_validator(mode="after")
    def _same_lengths(self):
        for name in ("gyr", "acc"):
            values = getattr(self, name)
            if values is not None and len(values) != len(self.t_ms):
                raise ValueError(f"motion.{name} has {len(values)} samples for {len(self.t_ms)} timestamps")
        return self


class CaptureIn(Strict):
    """The raw samples of one still pose, already in the W3C sign convention."""

    acc: Annotated[list[Vec3], Field(min_length=1, max_length=100_000)] = Field(
        description="accelerationIncludingGravity samples [x, y, z] in the session's unit.")
    t_ms: Annotated[list[FiniteFloat], Field(min_length=1, max_length=100_000)] = Field(
        description="Each sample's event timestamp in ms (DeviceMotionEvent.timeStamp).")
    gyr: Annotated[list[Vec3], Field(max_length=100_000)] | None = Field(
        None, description="rotationRate samples [x, y, z], one per acc sample.")
    gyr_unit: Literal["deg/s", "rad/s"] = "deg/s"
    unit: Literal[ACC_PHYSICAL_UNITS] | None = Field(None, description="Must be the session's unit when given.")
    sign: SignIn = Field(default_factory=SignIn)
    position: Label | CubePosition | None = Field(
        None, description=("six: the pose the page recognised (checked against the data); cube24: the position number; "
                           "free: leave it out (poses are numbered in order)."))
    redo: bool = Field(False, description="Replace an earlier capture of the same pose (cube24: the last one).")
    motion: MotionIn | None = Field(None, description="cube24: the rates of the turn into this position.")

    @model_validator(mode="after")
    def _same_lengths(self):
        if self.gyr is not None and len(self.gyr) != len(self.acc):
            raise ValueError(f"gyr has {len(self.gyr)} samples for {len(self.acc)} acc samples: send one per event")
        return self


class CaptureSummary(BaseModel):
    """One stored capture; the cube flow adds `up`, `expected_up`, `turn` and `gyr_to_rad_s`."""

    model_config = ConfigDict(extra="allow")

    position: str
    mean: list[float]
    std: list[float]
    count: int
    sampling_rate_hz: float
    duration_s: float
    created_at: str
    gyr_mean: list[float] | None = Field(None, description="Mean of the capture's gyroscope samples, in gyr_unit.")
    gyr_std: list[float] | None = Field(None, description="six, free: their standard deviation (ddof 1), in gyr_unit.")
    gyr_count: int | None = Field(None, description="six, free: how many gyroscope samples.")
    gyr_unit: Literal["deg/s", "rad/s"] | None = Field(None, description="The unit the gyroscope samples came in.")


class FreeProgress(BaseModel):
    """Where a free session stands, recomputed after each capture."""

    count: int = Field(description="Poses captured.")
    fit_from: int = Field(description=f"The triangular model is fitted from this many poses on ({FREE_FIT_FROM}).")
    target_poses: int = Field(description=f"The target counts only with at least this many poses ({FREE_TARGET_MIN_POSES}).")
    target_mg: float
    cv_error_mg: float | None = Field(description="Cross-validated error on new orientations (null before the fit).")
    cv_error_max_mg: float | None
    target_reached: bool
    advice: list[PoseAdviceOut] = Field(description=(
        "The next poses: D-optimal once fitted, before that the directions farthest from the poses taken (gain null)."))
    message: str = Field(description="The state in words, e.g. “11 poses: 3.2 mg expected on new orientations (target 2 mg, at least 12 poses)”.")


class SessionOut(BaseModel):
    model_config = ConfigDict(extra="allow")

    id: str
    protocol: str
    capture_s: float
    unit: str
    positions: list[str]
    captures: list[CaptureSummary]
    remaining: list[str]
    calibration_id: str | None
    created_at: str
    target_mg: float | None = Field(None, description="free: the target of the cross-validated error, mg.")
    progress: FreeProgress | None = Field(None, description="free: the fit so far, the advice, the target.")


class SessionCreated(SessionOut):
    token: str = Field(description="Send it as `Authorization: Bearer <token>` on every call of this session.")


class CaptureOut(BaseModel):
    capture: CaptureSummary
    session: SessionOut


class Health(BaseModel):
    status: Literal["ok"]
