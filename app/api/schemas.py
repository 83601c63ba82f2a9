"""Request and response models of the REST API (v1). Pydantic lives here and nowhere else."""

from __future__ import annotations

from typing import Annotated, Any, ClassVar, Literal, Union

from pydantic import BaseModel, ConfigDict, Field, FiniteFloat, model_validator

from app.sessions import CAPTURE_S_DEFAULT, CAPTURE_S_RANGE

Label = Literal["+x", "-x", "+y", "-y", "+z", "-z"]
Vec3 = Annotated[list[FiniteFloat], Field(min_length=3, max_length=3)]
AccUnit = Literal["m/s^2", "g", "raw"]


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class ReadingIn(Strict):
    """An averaged still reading in a known orientation."""

    mean: Vec3 = Field(description="Mean specific force [x, y, z] in `unit`.")
    up: Label | None = Field(None, description="The device axis that points up (`+x` reads +g on x).")
    expected: Vec3 | None = Field(None, description="Explicit true specific force, instead of `up`.")
    std: Annotated[list[Annotated[float, Field(ge=0, allow_inf_nan=False)]], Field(min_length=3, max_length=3)] | None = None
    count: int | None = Field(None, ge=1)

    @model_validator(mode="after")
    def _orientation_given(self):
        if self.up is None and self.expected is None:
            raise ValueError("each reading needs `up` (e.g. \"+z\") or an explicit `expected` vector")
        return self


class CommonIn(Strict):
    unit: AccUnit = Field("m/s^2", description="Unit of the readings; `g` calibrates into g.")
    gravity: Annotated[float, Field(gt=0, le=100, allow_inf_nan=False)] | None = Field(
        None, description="Reference gravity in m/s² (default 9.80665, or local gravity from latitude_deg)."
    )
    latitude_deg: Annotated[float, Field(ge=-90, le=90)] | None = None
    height_m: Annotated[float, Field(ge=-12000, le=100000)] | None = None
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None
    holdout: Annotated[list[Vec3], Field(max_length=100_000)] | None = Field(
        None, description="Further still readings of unknown orientation, used only to report norm errors."
    )


class FromRecordingIn(CommonIn):
    """Readings given inline (the field named by ``INLINE``) or taken from a recording."""

    INLINE: ClassVar[str]
    recording_id: str | None = Field(None, description="Use the static segments of an uploaded recording.")
    segments: list[int] | None = Field(None, description="Segment indices to use from the recording.")

    @model_validator(mode="after")
    def _one_source(self):
        if (getattr(self, self.INLINE) is None) == (self.recording_id is None):
            raise ValueError(f"give either `{self.INLINE}` or `recording_id` (exactly one of them)")
        if self.segments is not None and self.recording_id is None:
            raise ValueError("`segments` selects segments of a recording: give `recording_id` too")
        return self


class KnownOrientationIn(FromRecordingIn):
    INLINE: ClassVar[str] = "readings"
    readings: Annotated[list[ReadingIn], Field(min_length=1, max_length=10_000)] | None = None


class SixPositionIn(KnownOrientationIn):
    method: Literal["six_position"]


class OrientationsIn(KnownOrientationIn):
    method: Literal["orientations"]


class UnknownOrientationIn(FromRecordingIn):
    """Still readings whose orientations are unknown: only the magnitude of gravity is known."""

    INLINE: ClassVar[str] = "means"
    means: Annotated[list[Vec3], Field(min_length=1, max_length=100_000)] | None = Field(
        None, description="N×3 still readings in `unit`, in arbitrary orientations (N ≥ 9)."
    )


class NonOrthogonalIn(UnknownOrientationIn):
    method: Literal["nonorthogonal"]


class TriangularIn(UnknownOrientationIn):
    method: Literal["triangular"]
    solver: Literal["lm", "gradient", "fixed16", "fixed32"] = Field(
        "lm", description="lm (optimal), or 002's finite-difference descent in float, 16- or 32-bit fixed point."
    )


class CubeIn(Strict):
    """A multi-position recording of a cube (acc, gyr, optional mag): 003's method."""

    method: Literal["cube"]
    recording_id: str = Field(description="An uploaded recording with accelerometer and gyroscope columns.")
    protocol: Literal["cube24", "ferraris"] | dict[str, Any] = Field(
        "cube24", description="`cube24`, `ferraris`, or {\"rotations\": [...], \"ups\": [...]}."
    )
    gravity: Annotated[float, Field(gt=0, le=100, allow_inf_nan=False)] | None = None
    latitude_deg: Annotated[float, Field(ge=-90, le=90)] | None = None
    height_m: Annotated[float, Field(ge=-12000, le=100000)] | None = None
    field_ut: Annotated[float, Field(gt=0, le=1000, allow_inf_nan=False)] | None = Field(
        None, description="Magnitude of the local magnetic field in µT; needed when the recording has a magnetometer."
    )
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None


class AutocalIn(Strict):
    """Auto-calibration of an uploaded long recording by the pipeline of 002 (issue 4)."""

    method: Literal["autocal"]
    recording_id: str = Field(description="An uploaded recording (POST /api/v1/recordings).")
    unit: Literal["m/s^2", "g"] | None = Field(None, description="Overrides the recording's accelerometer unit.")
    gravity: Annotated[float, Field(gt=0, le=100, allow_inf_nan=False)] | None = None
    latitude_deg: Annotated[float, Field(ge=-90, le=90)] | None = None
    height_m: Annotated[float, Field(ge=-12000, le=100000)] | None = None
    solver: Literal["lm", "gradient", "fixed16", "fixed32"] = "lm"
    all_axes: bool = Field(False, description="Every axis must pass the max − min test (002: one axis).")
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None


METHODS = ("six_position", "orientations", "nonorthogonal", "triangular", "cube", "autocal")
"""The values of `method` that POST /api/v1/calibrations accepts."""

CalibrationIn = Annotated[
    Union[SixPositionIn, OrientationsIn, NonOrthogonalIn, TriangularIn, CubeIn, AutocalIn],
    Field(discriminator="method"),
]


class CalibrationOut(BaseModel):
    """A stored calibration. `model`, `metrics` and `uncertainty` depend on the method."""

    model_config = ConfigDict(extra="allow")

    id: str
    method: str
    created_at: str
    model: dict[str, Any]
    metrics: dict[str, Any]
    uncertainty: dict[str, Any]
    ok: bool
    warnings: list[str]
    reasons: list[str] = []
    device_id: str | None = None
    label: str | None = None


class CalibrationList(BaseModel):
    items: list[CalibrationOut]


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


class RecordingOut(BaseModel):
    model_config = ConfigDict(extra="allow")

    id: str
    created_at: str
    format: str
    n_samples: int
    sampling_rate_hz: float
    channels: list[str]
    units: dict[str, str]
    segments: list[SegmentOut]


class SessionIn(Strict):
    """A guided wizard session (issue 6): the page captures each pose into it, then solves it."""

    protocol: Literal["six", "cube24"] = Field("six", description="`six` (any order) or `cube24` (fixed order).")
    capture_s: Annotated[float, Field(ge=CAPTURE_S_RANGE[0], le=CAPTURE_S_RANGE[1], allow_inf_nan=False)] = Field(
        CAPTURE_S_DEFAULT, description="Seconds captured per position.")
    unit: Literal["m/s^2", "g"] = Field("m/s^2", description="Unit of the samples the page sends.")
    gravity: Annotated[float, Field(gt=0, le=100, allow_inf_nan=False)] | None = None
    latitude_deg: Annotated[float, Field(ge=-90, le=90)] | None = None
    height_m: Annotated[float, Field(ge=-12000, le=100000)] | None = None
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None


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
    unit: Literal["m/s^2", "g"] | None = Field(None, description="Must be the session's unit when given.")
    sign: SignIn = Field(default_factory=SignIn)
    position: Label | CubePosition | None = Field(
        None, description="six: the pose the page recognised (checked against the data); cube24: the position number.")
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


class SessionCreated(SessionOut):
    token: str = Field(description="Send it as `Authorization: Bearer <token>` on every call of this session.")


class CaptureOut(BaseModel):
    capture: CaptureSummary
    session: SessionOut


class Health(BaseModel):
    status: Literal["ok"]
