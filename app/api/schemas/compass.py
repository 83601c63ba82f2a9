"""The response models of the compass calibrations: magnetometer (the readings of a turn in every direction)
and compass_flight (a flight controller's log)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from app.api.schemas.common import CalibrationCommon, ChoiceOut, Mat3Out, Out, Vec3Out


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
        description="field_ut as given, from the geomagnetic model at the place and date, or estimated (det M = 1)."
    )
    field_model: str | None = Field(None, description="The geomagnetic model used, e.g. IGRF-14.")
    field_date: str | None = Field(None, description="The day the model was evaluated for.")
    inclination_deg: float | None = Field(description="The model's dip below the horizontal (null without a place).")
    declination_deg: float | None = Field(description="The model's declination, east positive.")
    norm_spread_ut: float = Field(description="5–95 % range of |h| over the recording, calibrated.")
    norm_spread_raw_ut: float = Field(description="The same of the raw readings' magnitude.")
    coverage: float = Field(description="Share of the 20 icosahedron faces the calibrated directions reach.")
    missing_directions: list[str] = Field(description="Faces not reached, e.g. +z+y (mostly +z, towards +y).")
    thickness: float = Field(
        description=(
            "How far the readings leave their best plane: the third singular value of the centred readings over "
            "the first (0 for a turn kept flat, 0.65 or more through all directions; below 0.1 refused)."
        )
    )
    fit_stage: Literal["refined", "closed form", "sphere", "centre"] = Field(
        description=(
            "What M and b are: the refined fit, or, when its refinement ran away from the readings (no ellipsoid "
            "fits them), the closed-form ellipsoid, the sphere (hard iron only) or the readings' own centre, shown "
            "to draw them only (ok is then false)."
        )
    )
    structure: Literal["soft_iron", "scale", "sphere", "offsets"] = Field(
        "soft_iron",
        description=(
            "The model the readings determine (app.calibration.magnetometer.refine.STRUCTURES), richest first: M "
            "symmetric (hard and soft iron), M diagonal, M = s I (a sphere), M = I (the offsets alone, with the "
            "field given); a warning names a simpler one than soft_iron and why."
        ),
    )
    count: int
    fit_error_ut: float = Field(description="RMS of |h| − F on the readings fitted (in-sample).")
    raw_error_ut: float | None = Field(description="RMS of |m| − F of the readings as they are (null for raw counts).")
    cv_error_ut: float | None = Field(
        description=(
            "What to expect on new directions: RMS of |h| − F, each face's readings calibrated by the fit made "
            "without that face; null with cv_note when such a fit is undetermined."
        )
    )
    cv_error_max_ut: float | None = Field(description="RMS of the worst face.")
    cv_scheme: str
    cv_note: str | None = None
    noise_ut: float = Field(description="Residual standard deviation.")
    correlation_inflation: float = Field(description="Factor on the covariance for residuals correlated in time.")
    measured_inclination_deg: float | None = Field(
        description=(
            "The calibrated field's dip measured against gravity at the accelerometer's rests; null without them."
        )
    )
    rests: int = Field(description="Accelerometer rests used for measured_inclination_deg.")


class MagnetometerSamples(Out):
    raw_ut: list[Vec3Out] = Field(description="Up to 600 raw readings, evenly spaced in time, for drawing.")


class MagnetometerOut(CalibrationCommon):
    method: Literal["magnetometer"]
    gravity: float | None = Field(  # type: ignore[assignment]  # pydantic: this result has no gravity
        None, description="Not used by a compass calibration."
    )
    model: MagnetometerModel
    uncertainty: MagnetometerUncertainty
    metrics: MagnetometerMetrics
    covariance: list[list[float]] | None = Field(description="9×9, of (M_xx, M_yy, M_zz, M_xy, M_xz, M_yz, b).")
    samples: MagnetometerSamples
    choice: ChoiceOut | None = Field(
        None, description=("Present when the request's method was `auto` on a recording of the magnetometer alone.")
    )


class CompassFlightModel(Out):
    type: Literal["compass_flight"]
    M: Mat3Out = Field(
        description="Soft iron, symmetric (identity or diagonal for the simpler structures): h = M (Q m − b − k p)."
    )
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
        None, description="Rms heading error on flight segments left out, with the firmware's own calibration."
    )
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
    gravity: float | None = Field(  # type: ignore[assignment]  # pydantic: this result has no gravity
        None, description="Not used by a compass calibration."
    )
    model: CompassFlightModel
    uncertainty: CompassFlightUncertainty
    metrics: CompassFlightMetrics
    flight: dict[str, Any] = Field(
        description=(
            "The log and the fit: firmware, generation, instance, external (true for an external compass, false for "
            "the board's own, null where the log does not say), raw_how (how the raw readings were had), structure "
            "(offsets, scale, soft_iron), motor (current, throttle or null), rotation_found, rotation_nearest "
            "({ardupilot, px4, name}), angle_left_deg, orientation_agrees, frame_to_body, stored (the firmware's own "
            "calibration), attitude_source, power_source, place, models (each candidate's error on segments left out), "
            "intervals, updated (where the flight left numbers open: {b: [3 bools], M, k: [3 bools]}, true for those "
            "new from the flight, false for those held at the firmware's stored values; null otherwise); for a log of "
            "two compasses or more, compasses (each compass of the log fitted to the same "
            "flight: instance, measures, ok, before_deg, after_deg, orientation, orientation_left_deg, "
            "orientation_agrees, orientation_setting, pull {per_unit, at_top_ut, at_top_deg, unit, determined}, "
            "power_kind, motor_setting, switch, reason, consistent, action) and consistency (each compass's field "
            "against the first's: pair, xyz_angle_deg, xy_angle_deg, xy_length_diff_ut, consistent, ArduPilot's "
            "pre-arm limits 90°, 60°, 200 mG)."
        )
    )
    series: dict[str, Any] = Field(
        description=(
            "At most 600 samples over the flight for drawing: time_s, expected, corrected, firmware (µT, body frame), "
            "field_magnitude, power, heading_error_before, heading_error_after (degrees)."
        )
    )
