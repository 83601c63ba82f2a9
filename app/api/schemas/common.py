"""The shared bases of the response models: `Out`, the array aliases, the cross-validated metrics several fits
share, and what every stored calibration holds whatever its method (its common fields, its verdict and, for
`method: auto`, the choice)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from app.methods import AUTO_CHOICES

Vec3Out = list[float]
Mat3Out = list[list[float]]


class Out(BaseModel):
    """Response models are tolerant at run time; the tests check that no field goes undescribed."""

    model_config = ConfigDict(extra="allow")


class CrossValidatedMetrics(Out):
    """What to expect on new orientations: each reading calibrated by the fit made without it."""

    cv_error_mg: float | None = Field(
        None,
        description=(
            "What to expect on new orientations: mean | |a_i| − g | in mg of g, each reading calibrated by the fit "
            "made without it (cv_scheme); null with cv_note where the fit has no redundancy."
        ),
    )
    cv_error_max_mg: float | None = Field(None, description="The largest of those errors.")
    cv_scheme: Literal["leave-one-out", "10-fold"] | None = None
    cv_note: str | None = None


class DegreesOut(Out):
    """A verdict's figure as the angle it can turn a level or a heading by, at worst: asin(e/r)."""

    kind: Literal["tilt", "heading"] = Field(
        description="`tilt`: asin(e/g) for a figure in mg; `heading`: asin(e/H), H = F cos I, for µT or counts."
    )
    before_deg: float | None = Field(description="The raw figure's angle, degrees (null without a raw figure).")
    after_deg: float = Field(description="The calibrated figure's angle, degrees.")
    inclination_deg: float | None = Field(description="A heading's inclination I, degrees (null for a tilt).")
    inclination_source: Literal["model", "measured", "assumed"] | None = Field(
        description=(
            "Where I comes from: `model` (IGRF-14 at the place given), `measured` (in the turn), `assumed` (60°)."
        )
    )
    words: str = Field(description="E.g. “a level off by 1.8° → 0.03°”.")


class VerdictOut(Out):
    """Whether to apply the calibration, in words (app.verdict): what a person reads first."""

    apply: bool = Field(description="Offer its files to a device: false for a calibration that must not be applied.")
    kind: Literal["apply", "no_gain", "worse", "failed", "figures"] = Field(
        description=(
            "`apply`; `no_gain`: passed but changes too little to matter; `worse`: its error grew; `failed`: a check "
            "failed; `figures`: a noise characterisation, which corrects nothing."
        )
    )
    words: str = Field(
        description="E.g. “Apply it: error on new orientations 36.0 mg → 1.40 mg (a level off by 2.1° → 0.08°).”"
    )
    why: str = Field(description="One line more: the reason, or what the figure is.")
    before: float | None = Field(description="The figure's raw error (null where the readings are counts).")
    after: float | None = Field(description="The same, calibrated.")
    unit: Literal["mg", "µT", "counts", "°/s", "°"] | None = Field(
        description=(
            "mg of g, or µT for a compass (counts for a magnetometer left in counts); °/s for a temperature "
            "calibration of a gyroscope alone; ° (heading error) for a compass calibrated from a flight."
        )
    )
    basis: str | None = Field(description="Which readings the figure is on, in words.")
    degrees: DegreesOut | None = Field(
        default=None,
        description=(
            "The figure as an angle (app.calibration.shared.angles, docs/methods.md): a level's tilt for an "
            "accelerometer, a heading error for a compass; null for a figure that is no error of gravity or of the "
            "field."
        ),
    )


class CalibrationCommon(Out):
    id: str
    created_at: str = Field(description="UTC, ISO 8601 with milliseconds.")
    schema_version: int = Field(1, description="Version of this stored form.")
    gravity: float = Field(description="Reference magnitude in the output unit (1 for g).")
    unit: str = Field(description="Unit of the readings: m/s^2, g or raw.")
    output_unit: str = Field(description="What the calibration calibrates into.")
    ok: bool = Field(description="False when a quality gate failed; `reasons` says which.")
    verdict: VerdictOut = Field(description="Whether to apply it, in words, and the figure it stands on.")
    headline: str | None = Field(
        None,
        description=(
            "What to expect on new orientations (the cross-validated error), then the in-sample figure, "
            "labelled; every fit of still readings has one."
        ),
    )
    warnings: list[str]
    reasons: list[str] = []
    device_id: str | None = None
    label: str | None = None
    recording_id: str | None = Field(None, description="The recording the readings came from.")
    session_id: str | None = Field(None, description="The wizard session that solved it.")
    superseded_by: str | None = Field(
        None,
        description=(
            "The later calibration of the same recording (the same upload's content) and method, read again with "
            "other options, that superseded this one; absent while none did. It is kept and still read by id."
        ),
    )
    earlier: int | None = Field(
        None,
        description=(
            "How many earlier calibrations of the same recording and method this one superseded "
            "(GET /api/v1/calibrations?superseded_by=ID lists them); absent when none."
        ),
    )
    source: Literal["board", "phone", "px4", "ardupilot"] | None = Field(
        None,
        description=(
            "Where its readings came from: a wizard session's source (a phone, or a board's printed lines), else the "
            "recording's format (a phone app's, a board's lines, a PX4 or ArduPilot log); absent for a plain CSV or "
            "JSON. The page offers the use of that source first (app/web/uses.py DEFAULT_USES)."
        ),
    )
    captures: list[dict[str, Any]] | None = Field(
        None,
        description=(
            "A wizard session's captures: position, mean, std, count, sampling_rate_hz (and up for cube24 and free); "
            "`trical capture`'s: position, rows (first, after last) of its log, up, mean, std, count."
        ),
    )


class CandidateOut(Out):
    ok: bool
    cv_error_mg: float | None


class ChoiceOut(Out):
    """What `method: auto` chose (app.workflows.still.choose_model)."""

    method: Literal[AUTO_CHOICES]  # type: ignore[valid-type]
    why: str
    candidates: dict[str, CandidateOut] = Field(
        description="Every model that applied: its ok and error on poses left out."
    )
