"""What a calibration is asked to do: the request models the API, the CLI and the workflow share.

POST /api/v1/calibrations validates its body against their union, :data:`app.methods.CalibrationIn` (made
from the method table), and ``trical calibrate`` builds the same models from its options, so both refuse
the same input with the same words.
"""

from __future__ import annotations

import datetime
from typing import Annotated, Any, ClassVar, Literal, get_args

from pydantic import BaseModel, ConfigDict, Field, FiniteFloat, model_validator

from app.calibration.still.solvers import Solver
from app.io.log import AccPhysicalUnit, AccUnit

Label = Literal["+x", "-x", "+y", "-y", "+z", "-z"]
Vec3 = Annotated[list[FiniteFloat], Field(min_length=3, max_length=3)]
Gravity = Annotated[float, Field(ge=0.1, le=100, allow_inf_nan=False)]
"""A reference gravity in m/s²: from the Moon's 1.6 to well above the Earth's 9.8."""


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class ReadingIn(Strict):
    """An averaged still reading in a known orientation."""

    mean: Vec3 = Field(description="Mean specific force [x, y, z] in `unit`.")
    up: Label | None = Field(None, description="The device axis that points up (`+x` reads +g on x).")
    expected: Vec3 | None = Field(None, description="Explicit true specific force, instead of `up`.")
    std: (
        Annotated[list[Annotated[float, Field(ge=0, allow_inf_nan=False)]], Field(min_length=3, max_length=3)] | None
    ) = None
    count: int | None = Field(None, ge=1)

    @model_validator(mode="after")
    def _orientation_given(self):
        if self.up is None and self.expected is None:
            raise ValueError('each reading needs `up` (e.g. "+z") or an explicit `expected` vector')
        return self


class CommonIn(Strict):
    unit: AccUnit = Field("m/s^2", description="Unit of the readings; `g` calibrates into g.")
    gravity: Gravity | None = Field(
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
    solver: Solver = Field(
        "lm",
        description="lm (optimal), or Farago et al.'s finite-difference descent in float, 16- or 32-bit fixed point.",
    )


class AutoIn(UnknownOrientationIn):
    """Still readings, axis-aligned or free: the workflow picks the model (app.workflows.still, ``auto``); a recording
    of the magnetometer alone is the compass's, referenced to the Earth's field at the place and date given."""

    method: Literal["auto"]
    date: datetime.date | None = Field(
        None, description="A recording of the magnetometer alone: the day of the turn, for the Earth's field."
    )
    longitude_deg: Annotated[float, Field(ge=-180, le=180)] | None = Field(
        None, description="A recording of the magnetometer alone: with latitude_deg, the place of the turn."
    )
    field_ut: Annotated[float, Field(gt=0, le=1000, allow_inf_nan=False)] | None = Field(
        None, description="A recording of the magnetometer alone: the local field's magnitude in µT."
    )


SectionKey = Literal["x_p", "x_a", "y_p", "y_a", "z_p", "z_a", "x_rot", "y_rot", "z_rot"]


class SectionIn(Strict):
    """One annotated region of a Ferraris recording (imucal's section list)."""

    start: int = Field(ge=0, description="First sample of the region.")
    end: int = Field(ge=1, description="The sample after the last one (imucal slices data.iloc[start:end]).")


CubeProtocol = Literal["cube24", "ferraris"]
CUBE_PROTOCOLS: tuple[str, ...] = get_args(CubeProtocol)
"""The cube's named protocols: Särkkä et al.'s 24 positions, and imucal's Ferraris sections (a recording's
protocol may also be given as its rotations and ups)."""


class CubeIn(Strict):
    """A multi-position recording of a cube (acc, gyr, optional mag): Särkkä et al.'s method."""

    method: Literal["cube"]
    recording_id: str = Field(description="An uploaded recording with accelerometer and gyroscope columns.")
    protocol: CubeProtocol | dict[str, Any] = Field(
        "cube24", description='`cube24`, `ferraris`, or {"rotations": [...], "ups": [...]}.'
    )
    gravity: Gravity | None = None
    latitude_deg: Annotated[float, Field(ge=-90, le=90)] | None = None
    height_m: Annotated[float, Field(ge=-12000, le=100000)] | None = None
    field_ut: Annotated[float, Field(gt=0, le=1000, allow_inf_nan=False)] | None = Field(
        None, description="Magnitude of the local magnetic field in µT; needed when the recording has a magnetometer."
    )
    sections: dict[SectionKey, SectionIn] | None = Field(
        None,
        description='protocol ferraris: imucal\'s annotated section list, {"x_p": {"start", "end"}, …, '
        '"z_rot"} in sample indices (end exclusive), instead of the detected rests and turns.',
    )
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None


class AutocalIn(Strict):
    """Auto-calibration of an uploaded long recording by the pipeline of Farago et al. (issue 4)."""

    method: Literal["autocal"]
    recording_id: str = Field(description="An uploaded recording (POST /api/v1/recordings).")
    unit: AccPhysicalUnit | None = Field(None, description="Overrides the recording's accelerometer unit.")
    gravity: Gravity | None = None
    latitude_deg: Annotated[float, Field(ge=-90, le=90)] | None = None
    height_m: Annotated[float, Field(ge=-12000, le=100000)] | None = None
    solver: Solver = "lm"
    all_axes: bool = Field(False, description="Every axis must pass the max − min test (Farago et al.: one axis).")
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None


class NoiseIn(Strict):
    """Noise characterisation of a still recording by the Allan deviation (issue 13)."""

    method: Literal["noise"]
    recording_id: str = Field(description="An uploaded still recording (POST /api/v1/recordings), any length.")
    sensors: Annotated[list[Literal["acc", "gyr", "mag"]], Field(min_length=1, max_length=3)] | None = Field(
        None, description="Sensors to characterise (default: every sensor the recording has)."
    )
    sensor: Literal["acc", "gyr", "mag"] | None = Field(
        None, description="The sensor a three-column array (.npy N×3 or N×4, Parquet) holds; default acc."
    )
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None


class TemperatureIn(Strict):
    """Temperature calibration of a still recording across a range of temperature (issue 26)."""

    method: Literal["temperature"]
    recording_id: str = Field(
        description="An uploaded recording with the sensor's temperature (a temp_c column, "
        "or a flight log), the device still while it warms up."
    )
    sensors: Annotated[list[Literal["acc", "gyr"]], Field(min_length=1, max_length=2)] | None = Field(
        None, description="Sensors to calibrate (default: the accelerometer and the gyroscope the recording has)."
    )
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None


Latitude = Annotated[float, Field(ge=-90, le=90)]
Longitude = Annotated[float, Field(ge=-180, le=180)]
FieldMagnitude = Annotated[float, Field(gt=0, le=1000, allow_inf_nan=False)]


class MagnetometerIn(Strict):
    """A compass calibration from readings of a device turned through all directions (issue 12)."""

    method: Literal["magnetometer"]
    mag: Annotated[list[Vec3], Field(min_length=1, max_length=200_000)] | None = Field(
        None, description="N×3 magnetometer readings in µT, in recording order (N ≥ 50, spread over all directions)."
    )
    recording_id: str | None = Field(None, description="An uploaded recording with magnetometer columns instead.")
    date: datetime.date | None = Field(None, description="Day of the recording (default today, UTC), for the model.")
    latitude_deg: Latitude | None = Field(
        None, description="Geodetic latitude: with longitude_deg, the Earth's field there from IGRF."
    )
    longitude_deg: Longitude | None = None
    height_m: Annotated[float, Field(ge=-12000, le=100000)] | None = Field(
        None, description="Height above the WGS84 ellipsoid (default 0)."
    )
    field_ut: FieldMagnitude | None = Field(
        None,
        description="The local field's magnitude in µT; overrides the model's. Without it or a place, "
        "the magnitude is estimated from the readings.",
    )
    source: Literal["phone", "board"] | None = Field(
        None,
        description="Inline readings: the device they came from (the compass page says which), kept as the "
        "calibration's source so its page speaks of that device. A recording's comes from its format.",
    )
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None

    @model_validator(mode="after")
    def _sources(self):
        if self.source is not None and self.recording_id is not None:
            raise ValueError("`source` is for inline `mag` readings: a recording's source comes from its format")
        if (self.mag is None) == (self.recording_id is None):
            raise ValueError("give either `mag` or `recording_id` (exactly one of them)")
        if (self.latitude_deg is None) != (self.longitude_deg is None):
            raise ValueError("give both `latitude_deg` and `longitude_deg` for the Earth's field there, or neither")
        return self


class CompassFlightIn(Strict):
    """A flight controller's compass calibrated from a flight log against the field its attitude expects (issue 32)."""

    method: Literal["compass_flight"]
    recording_id: str = Field(
        description="An uploaded PX4 ULog (.ulg) or ArduPilot DataFlash log (.bin) of a flight "
        "with turns through every heading, with the attitude and the compass."
    )
    mag_instance: Annotated[int, Field(ge=0, le=255)] | None = Field(
        None, description="The compass instance (default: the one read at the upload, else the first)."
    )
    date: datetime.date | None = Field(
        None, description="Day of the flight, for the model (default: the log's GPS time)."
    )
    latitude_deg: Latitude | None = Field(
        None, description="Where the vehicle flew (default: the log's first GPS fix)."
    )
    longitude_deg: Longitude | None = None
    height_m: Annotated[float, Field(ge=-12000, le=100000)] | None = Field(
        None, description="Height above the WGS84 ellipsoid (default: the fix's)."
    )
    attitude: Literal["ATT", "AHR2", "XKF1", "NKF1", "EKF1", "vehicle_attitude"] | None = Field(
        None,
        description="The attitude estimate the compass is judged by: ArduPilot's ATT (default: the one flown by, "
        "whose yaw used the primary compass), AHR2 (the DCM backup), XKF1, NKF1 or EKF1 (an EKF's first core); "
        "PX4's vehicle_attitude.",
    )
    window: Literal["flying", "all"] = Field(
        "flying",
        description="The part of the log fitted: `flying` (default), the samples whose throttle is at least 0.3 "
        "of the hover throttle (else whose current is above the idle's), so that time on the ground does not count "
        "against the headings; `all`, every sample.",
    )
    from_s: Annotated[float, Field(ge=0)] | None = Field(
        None, description="Seconds from the compass's first sample where the part fitted starts (default: the start)."
    )
    to_s: Annotated[float, Field(gt=0)] | None = Field(
        None, description="Seconds from the compass's first sample where the part fitted ends (default: the end)."
    )
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None

    @model_validator(mode="after")
    def _place(self):
        if (self.latitude_deg is None) != (self.longitude_deg is None):
            raise ValueError("give both `latitude_deg` and `longitude_deg` for the Earth's field there, or neither")
        if self.from_s is not None and self.to_s is not None and self.to_s <= self.from_s:
            raise ValueError("`to_s` must come after `from_s`: they are seconds from the compass's first sample")
        return self


ImportFirmware = Literal["ardupilot", "px4", "betaflight", "inav", "trical"]
"""The families an import may be forced to (app.io.imports.FIRMWARES, which a test holds it to)."""


class ImportIn(Strict):
    """A calibration a device already holds, brought in from the file its firmware or ground station wrote
    (issue 47): ArduPilot, PX4, Betaflight, INAV or trical's own JSON export."""

    method: Literal["imported"]
    file_base64: Annotated[str, Field(max_length=70_000_000)] = Field(
        description="The file's bytes, base64-encoded (POST /api/v1/calibrations/import takes the file itself)."
    )
    firmware: ImportFirmware | None = Field(
        None, description="The file's family, where its content does not say it (it is otherwise recognised)."
    )
    instance: Annotated[int, Field(ge=0, le=3)] = Field(
        0, description="Which IMU and compass of a file holding several (ArduPilot's 0-2, PX4's slot)."
    )
    device_id: Annotated[str, Field(min_length=1, max_length=200)] | None = None
    label: Annotated[str, Field(max_length=500)] | None = None
