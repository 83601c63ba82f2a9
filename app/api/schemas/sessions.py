"""The request and response models of /api/v1/sessions: a guided wizard session, its captures and a free
session's progress."""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Literal, Self, TypeAlias

from pydantic import BaseModel, ConfigDict, Field, FiniteFloat, model_validator

from app.api.schemas.still_readings import PoseAdviceOut
from app.calibration_requests import Gravity, Label, Strict, Vec3
from app.guided.capture_rules import (
    CAPTURE_S_DEFAULT,
    CAPTURE_S_RANGE,
    FREE_FIT_FROM,
    FREE_TARGET_MIN_POSES,
    SESSION_PROTOCOL_NAMES,
    WIZARD_PROTOCOLS,
)
from app.io.log import AccPhysicalUnit, GyrPhysicalUnit

if TYPE_CHECKING:  # the names the protocol table gives at run time: to the checker, a string
    SessionProtocolName: TypeAlias = str
else:
    SessionProtocolName = Literal[SESSION_PROTOCOL_NAMES]
"""A protocol a guided session runs, by name (app.guided.capture_rules.WIZARD_PROTOCOLS)."""


class SessionIn(Strict):
    """A guided wizard session (issue 6): the page captures each pose into it, then solves it."""

    protocol: SessionProtocolName = Field(
        SESSION_PROTOCOL_NAMES[0],
        description="; ".join(f"`{p.name}`: {p.words}" for p in WIZARD_PROTOCOLS if p.session) + ".",
    )
    capture_s: Annotated[float, Field(ge=CAPTURE_S_RANGE[0], le=CAPTURE_S_RANGE[1], allow_inf_nan=False)] = Field(
        CAPTURE_S_DEFAULT, description="Seconds captured per position."
    )
    unit: AccPhysicalUnit = Field("m/s^2", description="Unit of the samples the page sends.")
    gravity: Gravity | None = None
    latitude_deg: Annotated[float, Field(ge=-90, le=90)] | None = None
    height_m: Annotated[float, Field(ge=-12000, le=100000)] | None = None
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None
    target_mg: Annotated[float, Field(gt=0, le=1000, allow_inf_nan=False)] | None = Field(
        None,
        description=(
            "free: the cross-validated error in mg of g below which the session is done; default TRICAL_FREE_TARGET_MG."
        ),
    )
    source: Literal["phone", "board"] = Field(
        "phone",
        description=(
            "What the page reads: the phone's motion events (`phone`: the result notes the browser's rounding and the "
            "system's own calibration) or a board's printed lines (`board`: neither applies)."
        ),
    )


class SignIn(Strict):
    """How the page brought the samples to the W3C sign (at rest the up axis reads +g)."""

    convention: Literal["w3c", "ios"] = Field("w3c", description="The sign the browser reported in.")
    detected_from: Literal["orientation", "platform", "default"] = "default"


CubePosition = Literal[
    "1",
    "2",
    "3",
    "4",
    "5",
    "6",
    "7",
    "8",
    "9",
    "10",
    "11",
    "12",
    "13",
    "14",
    "15",
    "16",
    "17",
    "18",
    "19",
    "20",
    "21",
    "22",
    "23",
    "24",
]


class MotionIn(Strict):
    """The samples of the move that led to a cube position, since the previous capture ended."""

    t_ms: Annotated[list[FiniteFloat], Field(min_length=2, max_length=200_000)]
    gyr: Annotated[list[Vec3], Field(min_length=2, max_length=200_000)]
    acc: Annotated[list[Vec3], Field(max_length=200_000)] | None = None

    @model_validator(mode="after")
    def _same_lengths(self) -> Self:
        for name in ("gyr", "acc"):
            values = getattr(self, name)
            if values is not None and len(values) != len(self.t_ms):
                raise ValueError(f"motion.{name} has {len(values)} samples for {len(self.t_ms)} timestamps")
        return self


class CaptureIn(Strict):
    """The raw samples of one still pose, already in the W3C sign convention."""

    acc: Annotated[list[Vec3], Field(min_length=1, max_length=100_000)] = Field(
        description="accelerationIncludingGravity samples [x, y, z] in the session's unit."
    )
    t_ms: Annotated[list[FiniteFloat], Field(min_length=1, max_length=100_000)] = Field(
        description="Each sample's event timestamp in ms (DeviceMotionEvent.timeStamp)."
    )
    gyr: Annotated[list[Vec3], Field(max_length=100_000)] | None = Field(
        None, description="rotationRate samples [x, y, z], one per acc sample."
    )
    gyr_unit: GyrPhysicalUnit = "deg/s"
    unit: AccPhysicalUnit | None = Field(None, description="Must be the session's unit when given.")
    sign: SignIn = Field(default_factory=SignIn)
    position: Label | CubePosition | None = Field(
        None,
        description=(
            "six: the pose the page recognised (checked against the data); cube24: the position number; "
            "free: leave it out (poses are numbered in order)."
        ),
    )
    redo: bool = Field(False, description="Replace an earlier capture of the same pose (cube24: the last one).")
    motion: MotionIn | None = Field(None, description="cube24: the rates of the turn into this position.")

    @model_validator(mode="after")
    def _same_lengths(self) -> Self:
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
    gyr_unit: GyrPhysicalUnit | None = Field(None, description="The unit the gyroscope samples came in.")


class FreeProgress(BaseModel):
    """Where a free session stands, recomputed after each capture."""

    count: int = Field(description="Poses captured.")
    fit_from: int = Field(description=f"The triangular model is fitted from this many poses on ({FREE_FIT_FROM}).")
    target_poses: int = Field(
        description=f"The target counts only with at least this many poses ({FREE_TARGET_MIN_POSES})."
    )
    target_mg: float
    cv_error_mg: float | None = Field(description="Cross-validated error on new orientations (null before the fit).")
    cv_error_max_mg: float | None
    target_reached: bool
    advice: list[PoseAdviceOut] = Field(
        description=(
            "The next poses: D-optimal once fitted, before that the directions farthest from the poses taken (gain "
            "null)."
        )
    )
    message: str = Field(
        description=(
            "The state in words, e.g. “11 poses: 3.2 mg expected on new orientations (target 2 mg, at least 12 poses)”."
        )
    )


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
