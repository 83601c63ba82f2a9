"""The calibrations' resource: the union of every method's response model, the list, apply, and the export's
snippets.

Each method's response model lives in its family's module (still readings, autocal, cube, noise, compass,
temperature); the method table (:mod:`app.methods`) names it, and :data:`RESPONSE_MODELS` here finds it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any, Literal, TypeAlias, Union

from pydantic import BaseModel, Field, create_model

from app.api.schemas import autocal, compass, cube, noise, still_readings, temperature
from app.api.schemas.common import CalibrationCommon, Mat3Out, Vec3Out
from app.api.schemas.recordings import UploadOptions
from app.calibration_requests import Strict, Vec3
from app.io.writers.samples import FORMATS as SAMPLE_FORMATS
from app.methods import AS_CHOSEN, TABLE

FAMILIES = (still_readings, autocal, cube, noise, compass, temperature)
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
