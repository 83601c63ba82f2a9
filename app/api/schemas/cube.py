"""The response model of the cube calibration: accelerometer, gyroscope and magnetometer models, and the check
of every rotation of the protocol."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from app.api.schemas.common import CalibrationCommon, Mat3Out, Out, Vec3Out


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
    n_still_found: int | None = Field(
        None, description="Still segments detected before they were matched to the protocol."
    )
    n_handling: int | None = Field(
        None, description="Rests and moves left out as handling (pauses, re-placements, moves by hand)."
    )
    positions_from: Literal["detected", "sections"] | None = Field(
        None, description="`detected` from the gyroscope, or `sections` (an annotated section list)."
    )
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
    protocol: dict[str, Any] = Field(
        description="name, rotations, ups, attitudes, heading_known, reading_positions "
        "(for ferraris: the order the recording made it in)."
    )
    segments: dict[str, Any] | None = Field(
        description="Still intervals and rotations matched to the protocol (sample "
        "indices), source, n_still_found and the handling left out."
    )
    drift: dict[str, Any] = Field(description="Sensor → drift removed (return to position 1).")
    sampling_rate_hz: float
    field_ut: float | None
    details: dict[str, Any] = Field(description="Each sensor's full fit: covariance, positions, metrics.")
