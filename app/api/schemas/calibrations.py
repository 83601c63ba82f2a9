"""The calibrations' resource: the union of every method's response model, the list, apply, and the export's
snippets.

Each method's response model lives in its family's module (still readings, autocal, cube, noise, compass,
temperature); the method table (:mod:`app.methods`) names it, and :data:`RESPONSE_MODELS` here finds it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any, Literal, Self, TypeAlias, Union

from pydantic import BaseModel, Field, create_model, model_validator

from app.api.schemas import autocal, compass, cube, imports, noise, still_readings, temperature
from app.api.schemas.common import CalibrationCommon, Mat3Out, Vec3Out
from app.api.schemas.recordings import UploadOptions
from app.calibration_requests import Strict, Vec3
from app.io.writers.samples import FORMATS as SAMPLE_FORMATS
from app.methods import AS_CHOSEN, TABLE

FAMILIES = (still_readings, autocal, cube, noise, compass, temperature, imports)
"""The modules that hold the methods' response models, by method family."""


def response_model(name: str) -> type[CalibrationCommon]:
    """The response model the method table names (``Method.response``), found in its family's module."""
    model: type[CalibrationCommon]
    (model,) = {getattr(module, name) for module in FAMILIES if hasattr(module, name)}
    return model


def common_response(method: str) -> type[CalibrationCommon]:
    """The response model of a method without one of its own (``Method.response`` None): the fields every
    calibration answers with, its ``method``, and its ``model`` and ``metrics`` as its result class writes them."""
    return create_model(
        f"CalibrationOut_{method}",
        __base__=CalibrationCommon,
        method=(Literal[method], ...),  # type: ignore[arg-type]  # a Literal of the name the table gives at run time
        model=(dict[str, Any], ...),
        metrics=(dict[str, Any], ...),
    )


RESPONSE_MODELS = {
    method.name: common_response(method.name) if method.response is None else response_model(method.response)
    for method in TABLE
    if method.response != AS_CHOSEN
}
"""Each method's response model, named by the method table (app.methods); ``auto`` answers as the method it chose."""

# One model per method, in a union discriminated by `method` (OpenAPI's discriminator must be a
# top-level property). `method` fixes `model.type` one to one: six_position and orientations give
# `affine`, nonorthogonal and triangular their own type, cube `cube`, and autocal a `triangular`
# model with the fields of its pipeline.
if TYPE_CHECKING:  # a union the table makes at run time: to the checker, the base of every response model
    CalibrationOut: TypeAlias = CalibrationCommon
else:
    CalibrationOut = Annotated[
        Union[tuple(RESPONSE_MODELS.values())],  # noqa: UP007 - a union of a run-time tuple: no `|` spelling
        Field(discriminator="method"),
    ]
"""A stored calibration, by method."""


class CalibrationList(BaseModel):
    items: list[CalibrationOut]


class ScaleOut(BaseModel):
    op: Literal["/", "*"] = Field(description="Counts `op` value gives the calibration's input unit.")
    value: float
    words: str = Field(description="What the figure is, and where it comes from.")
    known: bool = Field(
        description="True when the upload named the part (chip, lsb_per_g); false for a common "
        "part's figure the person should check against the datasheet."
    )
    read_in: Literal["counts", "gauss"] = Field("counts", description="What a driver's numbers are before the scale.")


class CorrectionOut(BaseModel):
    M: Mat3Out = Field(description="f = M (m − o): what a reading is multiplied by after the offset is taken off.")
    o: Vec3Out = Field(description="The offset taken off each reading, in the input unit.")
    input_unit: str | None
    output_unit: str | None
    source: str = Field(description="How M and o come from the model's own parameters (e.g. M = X⁻¹, o = y).")


class FirmwareFiguresOut(BaseModel):
    target: str = Field(description="ArduPilot or PX4.")
    count: int = Field(
        description="Still readings the offsets and scales were fitted on (14 directions of trical's "
        "model when the calibration holds fewer than 6)."
    )
    from_readings: bool = Field(description="True when fitted on the calibration's own still readings.")
    firmware_max_mg: float = Field(
        description="Largest | |a| − g | of those readings with the exported offsets and "
        "scales, applied by the firmware's formula, in mg."
    )
    firmware_mean_mg: float
    raw_max_mg: float = Field(description="The same readings raw.")
    raw_mean_mg: float
    full_max_mg: float = Field(description="The same readings with trical's full correction M (m − o).")
    full_mean_mg: float
    any_direction_max_mg: float = Field(
        description="The exported model's largest norm error over every direction, on "
        "readings trical's full model puts at magnitude g."
    )
    rotation_deg: float = Field(
        description="The rotation of M = R P: the table's tilt or the board's mounting, which "
        "the firmware's level calibration takes."
    )
    nonorthogonality_mg: float = Field(
        description="g ‖I − D P⁻¹‖₂: what the axes' non-orthogonality makes of a "
        "reading, which no offset or scale holds."
    )
    improves: bool = Field(
        description="Whether firmware_max_mg is below raw_max_mg: the page offers the firmware's file only then."
    )
    words: str = Field(description="One sentence for the page.")


class SnippetsOut(BaseModel):
    corrections: dict[str, CorrectionOut] = Field(description="Each sensor's correction, by acc, gyr, mag.")
    c: str = Field(
        description="Lines at file scope over the C header (C89 and later): its #include, then per sensor "
        "a function trical_<sensor>_calibrate that scales a driver's reading to the header's "
        "unit and passes it through trical_<sensor>_apply, the call for one reading in a "
        "comment."
    )
    python: str = Field(description="numpy over the JSON export.")
    javascript: str = Field(description="JavaScript over the JSON export, for a phone app.")
    functions: dict[str, str] = Field(description="The C header's apply function of each sensor.")
    calibrate: dict[str, str] = Field(
        default_factory=dict, description="The C lines' function of each sensor, taking a driver's reading."
    )
    scales: dict[str, ScaleOut | None] = Field(
        description="How a sensor's int16 counts become the input unit; "
        "null when the calibration takes them as they are."
    )
    firmware: dict[str, FirmwareFiguresOut] = Field(
        default_factory=dict,
        description="By export format (ardupilot, px4): what the firmware reaches with the "
        "exported offsets and scales; absent where that export is refused.",
    )


class ApplyIn(Strict):
    samples: Annotated[list[Vec3], Field(min_length=1, max_length=1_000_000)]
    sensor: Literal["acc", "gyr", "mag"] = Field("acc", description="Which sensor's model to apply (cube).")


class ApplyFileOptions(UploadOptions):
    """The fields of ``POST /api/v1/calibrations/{id}/apply-file``'s multipart form besides its ``file``: how the
    recording is read (as the upload's), and the format the calibrated samples are written in."""

    output_format: Literal[SAMPLE_FORMATS] = Field(  # type: ignore[valid-type]
        "csv", description="The answer's format: csv, parquet or npy (app.io.writers.samples)."
    )


class ApplyOut(BaseModel):
    samples: list[list[float]]
    unit: str


class CheckIn(Strict):
    recording_id: str | None = Field(
        None,
        max_length=200,
        description="An uploaded recording of the device (POST /api/v1/recordings): still poses, a compass turn, "
        "a rest. Give it or mag.",
    )
    mag: Annotated[list[Vec3], Field(min_length=1, max_length=200_000)] | None = Field(
        None,
        description="A compass turn's readings [x, y, z] as the device read them, in the unit of the calibration's "
        "compass (the page's live turn). Give it or recording_id.",
    )
    field_ut: float | None = Field(
        None, gt=0, le=1000, description="The place's field F in µT (default: the calibration's own, else the turn's)."
    )
    inclination_deg: float | None = Field(
        None, ge=-90, le=90, description="The place's inclination, for the heading (default: 60° assumed)."
    )

    @model_validator(mode="after")
    def _one_source(self) -> Self:
        if (self.recording_id is None) == (self.mag is None):
            raise ValueError("give recording_id (an uploaded recording of the device) or mag (a turn's readings)")
        return self


Verdict: TypeAlias = Literal["keep", "calibrate_again", "move_the_compass", "cannot_tell"]


class ErrorInterval(BaseModel):
    value: float = Field(description="The error: mean | |a| − g | (mg), RMS | |h| − F | (µT) or the bias (°/s).")
    low: float = Field(description="Its 95 % interval's lower end.")
    high: float = Field(description="Its 95 % interval's upper end.")
    unit: str
    value_deg: float | None = Field(None, description="The error as the worst tilt or heading it allows, in °.")
    high_deg: float | None = Field(None, description="The interval's upper end as an angle, in °.")


class DifferenceOut(BaseModel):
    sensor: Literal["acc", "gyr", "mag"]
    group: Literal["offsets", "scales", "cross", "orientation"]
    parameter: str = Field(description="The group as said of the sensor (offsets, hard iron, soft iron…).")
    axis: str = Field(description="x, y, z; xy, xz, yz for a cross-axis term; empty for the orientation.")
    difference: float = Field(description="B − A (a check: the fresh fit's drift from the current calibration).")
    half_width: float | None = Field(description="Its 95 % half-width from both intervals; null without any.")
    unit: str = Field(description="mg, µT, °/s or counts (offsets), ppm (scales), ° (cross-axis terms, orientation).")
    real: bool | None = Field(description="Whether the interval excludes zero; null without an interval.")
    difference_in_input_unit: float | None = Field(
        description="An offset's difference in the readings' own unit (o_B − o_A); null for the other groups."
    )
    input_unit: str | None = Field(description="The readings' unit (counts are raw).")


class SensorComparisonOut(BaseModel):
    sensor: Literal["acc", "gyr", "mag"]
    differences: list[DifferenceOut]
    effect: float = Field(description="The largest difference the two corrections make to a vector of size g or F.")
    effect_unit: str
    effect_deg: float | None = Field(description="That difference as the worst tilt (acc) or heading (mag), in °.")
    effect_kind: Literal["tilt", "heading"] | None
    reference: float = Field(description="g or F in the calibrated unit.")
    real: list[str] = Field(description="The real differences, in words.")


class SensorCheckOut(BaseModel):
    sensor: Literal["acc", "gyr", "mag"]
    verdict: Verdict
    reasons: list[str]
    count: int = Field(description="Still poses, turn readings or rest samples checked.")
    angle_kind: Literal["tilt", "heading"] | None
    current: ErrorInterval | None = Field(description="The current calibration's error on the new readings.")
    fresh: ErrorInterval | None = Field(description="A fresh calibration's error on the same readings.")
    drifted: list[str] = Field(description="What drifted, in words (calibrate_again).")
    drift: SensorComparisonOut | None = Field(description="The fresh fit's parameters against the current ones.")


class CheckOut(BaseModel):
    calibration_id: str | None
    verdict: Verdict
    reasons: list[str]
    sensors: list[SensorCheckOut]


class CompareOut(BaseModel):
    calibration_id: str | None
    with_: str | None = Field(alias="with", serialization_alias="with")
    sensors: list[SensorComparisonOut]
    missing: list[str] = Field(description="Sensors only one of the two corrects.")

    model_config = {"populate_by_name": True}
