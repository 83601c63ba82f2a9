"""The models of /api/v1/recordings: the upload form's options for the reader and the response, an
uploaded log as read, its still segments, parts, timing, overview and a flight controller's sensor instances."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, Field

from app.calibration_requests import AccUnit
from app.io.log import UNITS_IN
from app.io.readers import FORMATS
from app.io.readers.read_options import ReadOptions, units_named


def _plus_or_minus_one(value: int) -> int:
    if value not in (1, -1):
        raise ValueError("give 1 (keep the file's accelerations) or -1 (negate them: iOS Core Motion's sign)")
    return value


class UploadOptions(BaseModel):
    """The fields of ``POST /api/v1/recordings``' multipart form besides its files: the options the log is read
    with (each default lets the file decide; :class:`app.io.readers.read_options.ReadOptions` says what each does)."""

    sampling_rate_hz: float | None = Field(None, gt=0, le=100_000)
    acc_unit: AccUnit | None = None
    gyr_unit: Literal[UNITS_IN["gyr"]] | None = None  # type: ignore[valid-type, name-defined]
    mag_unit: Literal[UNITS_IN["mag"]] | None = None  # type: ignore[valid-type, name-defined]
    format: Literal[FORMATS] = Field(  # type: ignore[valid-type]
        "auto", description="Log format; auto detects it from the header (app.io.readers)."
    )
    lsb_per_g: float | None = Field(None, gt=0, description="Counts per g of a raw (LSB) accelerometer.")
    chip: str | None = Field(
        None,
        description="The parts (and ranges) of sensors logged in counts, separated by "
        "commas, e.g. mpu6050-4g,mpu6050-500dps,ak8963-16bit: their counts become g, deg/s, µT "
        "(app.io.readers.chips).",
    )
    columns: str | None = Field(
        None,
        description="Map unrecognised CSV columns, e.g. acc_x:north,acc_y:east,acc_z:down, "
        "or name every column in order, e.g. t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z (- skips one); for several "
        "files uploaded together, one entry per file, NAME=COLUMNS;NAME=COLUMNS (a file not named is read by "
        "its header or its data).",
    )
    sign: Annotated[int, AfterValidator(_plus_or_minus_one)] | None = Field(
        None,
        description="Factor on the file's accelerations: -1 for iOS Core Motion's "
        "sign (-g up), 1 to keep them; detected from the header when omitted.",
    )
    instance: int | None = Field(
        None,
        ge=0,
        le=255,
        description=(
            "A flight controller's log (PX4 .ulg, ArduPilot .bin): the IMU instance read (PX4 multi_id, ArduPilot I); "
            "default: PX4 the source with the most samples, ArduPilot 0. `flight.instances` of the answer lists them."
        ),
    )
    mag_instance: int | None = Field(
        None,
        ge=0,
        le=255,
        description="A flight controller's log: the compass instance the compass methods read (default: the first).",
    )

    def read_options(self) -> ReadOptions:
        """The reader's options the form gives."""
        units = units_named(self.acc_unit, self.gyr_unit, self.mag_unit)
        return ReadOptions(
            format=self.format,
            sampling_rate_hz=self.sampling_rate_hz,
            units=units,
            lsb_per_g=self.lsb_per_g,
            columns=self.columns,
            sign=self.sign,
            chip=self.chip,
            instance=self.instance,
            mag_instance=self.mag_instance,
        )


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
    pose_from_name: str | None = Field(
        None,
        description=(
            "The up axis the file's name gives (x_axis_pos → +x, z_down → -z), when it gives one; the data decide "
            "`up`, and a note names a file whose name they contradict."
        ),
    )


class PartOut(BaseModel):
    """One file of a recording made of several files (one per pose), in the order given."""

    index: int
    filename: str = Field(description="The file's name as uploaded (in a zip: its name without folders).")
    start: int = Field(description="Its first sample in the recording.")
    end: int = Field(description="The sample after its last.")
    n_samples: int
    sampling_rate_hz: float | None = Field(
        description="Its rate, from its time column or the one given; null when it has neither."
    )
    pose_from_name: str | None = Field(None, description="The up axis its name gives, if any.")


class ReadWithOut(BaseModel):
    """What the upload told the reader, kept so that the stored file is read again the same way."""

    format: str
    units: dict[str, str]
    lsb_per_g: float | None
    columns: str | None
    chip: str | None = Field(None, description="The parts the upload named (app.io.readers.chips).")
    sampling_rate_hz: float | None = Field(None, description="The rate the upload gave (null: the file's own).")
    sign: Literal[1, -1] = Field(description="The factor applied to the file's accelerations.")
    instance: int | None = Field(
        None, description="A flight controller's log: the IMU instance asked (null: the default)."
    )
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
    source: str = Field(
        description="The message: sensor_accel, sensor_gyro, sensor_mag, sensor_combined; IMU, ACC, GYR, MAG."
    )
    device_id: int | None = Field(
        None, description="The firmware's device id (ArduPilot: from INS_ACC_ID … parameters)."
    )
    device: DeviceOut | None = None
    n_samples: int
    sampling_rate_hz: float | None = Field(None, description="From the span: (N − 1)/(t_last − t_first).")
    temperature_min_c: float | None = None
    temperature_max_c: float | None = None


class FixOut(BaseModel):
    """A flight controller's log's first 3-D GPS fix."""

    latitude_deg: float
    longitude_deg: float
    date: str | None = Field(None, description="Its UTC date (ISO 8601), where the log gives the GPS time.")


class FlightOut(BaseModel):
    """What a flight controller's log holds, and what was read of it (app.io.flight.instances)."""

    instances: list[InstanceOut]
    imu: dict[str, Any] = Field(description="The IMU read: instance, source, gyr_source.")
    mag: dict[str, Any] | None = Field(None, description="The compass the compass methods read: instance, source.")
    clock: Literal["imu", "mag"] = Field(
        "imu",
        description="The samples are on the IMU's times; the compass methods read the log again on the compass's.",
    )
    fix: FixOut | None = Field(
        None,
        description="The first 3-D GPS fix of the compass read (the place and date of the Earth's field the compass "
        "from the flight takes); null without one, or for recordings stored before it existed.",
    )


class TemperatureRangeOut(BaseModel):
    min: float
    max: float


class GapOut(BaseModel):
    index: int = Field(description="The first sample after the gap.")
    t_s: float = Field(description="Where the gap starts, seconds from the first sample.")
    missing_s: float = Field(description="Time lost: the step less one sampling interval.")


class TimingOut(BaseModel):
    """How the sampling rate was decided (app.io.readers.timing), and what the time column showed."""

    source: Literal["sampling_rate_hz", "file", "time column", "none"] = Field(
        description=("The upload's sampling_rate_hz, the file's metadata, the time column's span, or none (no rate).")
    )
    sampling_rate_hz: float | None
    jitter: float | None = Field(
        None,
        description=(
            "Standard deviation of the time column's steps (gaps left out) over the sampling interval; above 0.2 "
            "the timestamps are a host's arrival times and a note says so."
        ),
    )
    median_step_s: float | None = None
    gaps: list[GapOut] = Field([], description="Where samples were lost; still segments do not span them.")
    missing_s: float = Field(0.0, description="Time lost in all gaps.")


class LogOverview(BaseModel):
    """The log's norm in at most 300 bins (app.workflows.recordings.overview), for a plot with the still segments."""

    sensor: Literal["acc", "mag", "gyr"] = Field(
        description=("The accelerometer's norm; in a log without it the magnetometer's, else the gyroscope's.")
    )
    unit: str | None
    t_s: list[float] | None = Field(
        description="Start of each bin, seconds from the first sample; null in a log without a sampling rate."
    )
    start: list[int] | None = Field(None, description="Start of each bin, in samples.")
    low: list[float | None] = Field(description="Smallest norm in the bin (null: no finite sample).")
    high: list[float | None] = Field(description="Largest.")
    temperature_c: list[float | None] | None = Field(
        None,
        description=(
            "A log that records the sensor's temperature (a flight controller's IMU, a temp_c column): each bin's "
            "mean temperature, °C."
        ),
    )


class SupportOut(BaseModel):
    """A calibration the recording supports (app.workflows.supports)."""

    method: str = Field(description="The `method` of POST /api/v1/calibrations that runs it on this recording.")
    why: str = Field(description="Why, in one line: a fact of the data (six axes up, a turn of the compass, one rest).")
    ready: bool = Field(description="Whether it can run on the recording as it is; when not, `why` says what it lacks.")
    asks: list[str] = Field(
        [],
        description="The fields that would make it ready: the upload's (`sampling_rate_hz` for a file without a time "
        "column) or the calibration's (`latitude_deg`, `longitude_deg`, `date` for a flight log without a GPS fix).",
    )


class FileScaleOut(BaseModel):
    op: Literal["/", "*"] = Field(description="The file's number `op` value gives the unit.")
    value: float
    words: str = Field(description="Where the figure comes from: the part, the option, or the data.")
    read_in: Literal["counts", "gauss"] = Field("counts", description="What a driver's numbers are before the scale.")


class RecordingOut(BaseModel):
    model_config = ConfigDict(extra="allow")

    id: str
    created_at: str
    format: str
    filename: str | None = None
    n_samples: int
    sampling_rate_hz: float | None = Field(
        description=(
            "The sensor's rate (timing says how it was decided); null when the file has no time column and none was "
            "given: the still poses and the compass need none, noise, cube and autocal ask for it."
        )
    )
    duration_s: float | None = None
    timing: TimingOut | None = Field(None, description="Absent from recordings stored before it existed.")
    channels: list[str]
    units: dict[str, str]
    columns: list[str] = Field([], description="The file's column names (or those `columns` gave).")
    notes: list[str] = Field([], description="What the reader decided: sign negated, unit inferred, no header row.")
    warnings: list[str] = Field(
        [],
        description="What the reader decided against the header or the upload's fields "
        "(a unit the data contradict), and sensors left in counts; every "
        "calibration of the recording repeats them.",
    )
    questions: list[dict[str, str]] = Field(
        [],
        description="What the data leave open and a figure hangs on "
        "(`sensor`, `detail`: a gyroscope's unit neither its data nor the "
        "upload say): a calibration of that sensor is not ok, its reasons ask.",
    )
    scales: dict[str, FileScaleOut] | None = Field(
        None,
        description="How the file's numbers became each sensor's unit where they were not in it (counts of a part, "
        "counts per g, gauss: `op`, `value`, `words`); a sensor absent from it was read in its unit. Null for a "
        "flight log or an array, and for recordings stored before it existed. The snippets scale a driver's "
        "readings by it.",
    )
    quantization_step: float | None = None
    sign: Literal[1, -1] = Field(1, description="-1 when the accelerations were negated (iOS Core Motion's sign).")
    read_with: ReadWithOut | None = Field(None, description="Absent from recordings stored before it existed.")
    content_sha256: str | None = Field(
        None,
        description=(
            "SHA-256 of the upload (of several files, their names and contents in order): the same upload read again "
            "with other options has the same one, and its calibrations by one method supersede each other. Absent "
            "from recordings stored before it existed."
        ),
    )
    segments: list[SegmentOut]
    supports: list[SupportOut] = Field(
        [],
        description=(
            "The calibrations the recording supports, in the order a person meets them: still poses, a compass turn "
            "(or a flight log's compass), one long rest (the noise), a sensor warming at rest (the temperature), "
            "a long wear recording (autocal). The page runs the first one `ready` unless the person chose one. "
            "Empty for recordings stored before it existed."
        ),
    )
    parts: list[PartOut] | None = Field(
        None,
        description=(
            "A recording made of several files (several `file` parts, or a zip of log files): each file, in order; "
            "absent for one file."
        ),
    )
    overview: LogOverview | None = Field(
        None, description="For a plot of the log; absent from recordings stored before it existed."
    )
    flight: FlightOut | None = Field(
        None,
        description="A flight controller's log (PX4 ULog, ArduPilot DataFlash): "
        "its sensor instances; absent for other logs.",
    )
    temperature_c: TemperatureRangeOut | None = Field(
        None, description=("The read IMU's temperature range in °C, when the log records it.")
    )
