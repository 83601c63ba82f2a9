"""The response model of autocal: the triangular model fitted on the rests of a long recording, with its
calibration and control points."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from app.api.schemas.common import CalibrationCommon, CrossValidatedMetrics, Mat3Out, Out, Vec3Out
from app.api.schemas.still_readings import MagnitudeReading, TriangularModel, TriangularUncertainty
from app.calibration_requests import Solver


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
