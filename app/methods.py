"""The method table: one declaration per calibration method, from which the rest is derived.

Each :class:`Method` names its request model (:mod:`app.calibration_requests`), its handler (a function of
:mod:`app.workflows`), its response model (by its class name, which :mod:`app.api.schemas.calibrations` finds
in its family's module and builds its union from this table: the CLI, which imports this module, never loads
the API), the ``trical`` command that runs it and the export formats its calibrations offer. From it come the
request union that POST /api/v1/calibrations and ``trical calibrate`` validate, the response union of the API,
the dispatch of a request to its handler, the CLI's ``--method`` choices and the formats the export route
accepts.

Adding a method: its result class, its request model, its handler and one entry here (docs/methods.md).

The table names pydantic models, so the workflow, which imports none (docs/architecture.md), never imports
it: the API and the CLI look a request's method up here and call :func:`app.workflows.entry.calibrate`
with its handler.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Annotated, Any, Generic, TypeAlias, TypeVar, Union

from pydantic import BaseModel, Field, TypeAdapter

from app import calibration_requests as rq
from app.calibration.still.solvers import SOLVERS
from app.io.errors import ExportError
from app.io.exports.compass import FLIGHT_COMPASS_EXPORTS
from app.io.exports.exporters import EXPORTERS, Export, export_calibration
from app.io.exports.noise import NOISE_EXPORTERS
from app.io.exports.temperature import TEMPERATURE_EXPORTERS
from app.workflows import autocal, compass, cube, flight_compasses, imports, noise, still, temperature
from app.workflows.calibration import Calibration
from app.workflows.entry import calibrate as run_handler
from app.workflows.recordings import RecordingSource

CORRECTION_EXPORTS = tuple(EXPORTERS)
"""The formats of a calibration that corrects readings (``f = M (m − o)``): JSON, C, ArduPilot, PX4, …"""
NOISE_EXPORTS = tuple(NOISE_EXPORTERS)
TEMPERATURE_EXPORTS = tuple(TEMPERATURE_EXPORTERS)
ACCELEROMETER = "an accelerometer calibration"
AS_CHOSEN = "as the method it chose"
"""The :attr:`Method.response` of ``auto``: its calibrations answer as the method it chose."""


Request = TypeVar("Request", bound=BaseModel)
"""A method's request model, which its handler must read as what it declares (app.workflows.requests): mypy
checks each entry of :data:`TABLE`, so a handler reading a field its model lacks is a type error."""


@dataclass(frozen=True)
class Method(Generic[Request]):
    """One calibration method.

    Attributes
    ----------
    name : str
        The request's ``method``.
    request : type
        Its request model (a member of :data:`CalibrationIn`).
    handler : callable
        ``handler(request, recording)``: the workflow's function that computes its typed calibration (the
        recording is None for a request on inline readings, where its handler takes them).
    response : str or None
        The class name of its response model in its family's module of :mod:`app.api.schemas`;
        :data:`AS_CHOSEN` for ``auto``, which answers as the method it chose; None (a method without a model
        of its own) for the fields every calibration answers with (:mod:`app.api.schemas.calibrations`).
    command : str
        The ``trical`` command that runs it: ``calibrate`` (a choice of ``--method``) or its own command.
    formats : tuple of str
        The export formats of its calibrations (GET /api/v1/calibrations/{id}/export, ``trical export``).
    kind : str
        What its calibrations are, in words, for the export's refusals.
    words : str
        The method in words, as a person reads it (the history of calibrations, the page's result).
    page_words : str
        Its calibration as a message read on the page names it (``method six_position`` → ``the six-position
        calibration``: app.words).
    """

    name: str
    request: type[Request]
    handler: Callable[[Request, RecordingSource], Calibration]
    response: str | None
    command: str
    formats: tuple[str, ...]
    kind: str
    words: str
    page_words: str

    @property
    def needs_recording(self) -> bool:
        """Whether it calibrates an uploaded recording only (no inline readings)."""
        field = self.request.model_fields.get("recording_id")
        return field is not None and field.is_required()

    @property
    def solvers(self) -> tuple[str, ...]:
        """The solvers of its fit it lets the caller choose (``solver``), or none."""
        return SOLVERS if "solver" in self.request.model_fields else ()

    @property
    def options(self) -> tuple[str, ...]:
        """The fields its request takes besides ``method``."""
        return tuple(name for name in self.request.model_fields if name != "method")


_ENTRIES = (  # unannotated, so that mypy checks each request model against its handler
    Method(
        "auto",
        request=rq.AutoIn,
        handler=still.auto,
        response=AS_CHOSEN,
        command="calibrate",
        formats=CORRECTION_EXPORTS,
        kind=ACCELEROMETER,
        words="the model the still readings support (accelerometer)",
        page_words="the calibration from still poses",
    ),
    Method(
        still.SIX_POSITION.name,
        request=rq.SixPositionIn,
        handler=still.six_position,
        response="SixPositionOut",
        command="calibrate",
        formats=CORRECTION_EXPORTS,
        kind=ACCELEROMETER,
        words="six positions (accelerometer)",
        page_words="the six-position calibration",
    ),
    Method(
        still.ORIENTATIONS.name,
        request=rq.OrientationsIn,
        handler=still.orientations,
        response="OrientationsOut",
        command="calibrate",
        formats=CORRECTION_EXPORTS,
        kind=ACCELEROMETER,
        words="known orientations (accelerometer)",
        page_words="the calibration from known orientations",
    ),
    Method(
        still.NONORTHOGONAL.name,
        request=rq.NonOrthogonalIn,
        handler=still.nonorthogonal,
        response="NonOrthogonalOut",
        command="calibrate",
        formats=CORRECTION_EXPORTS,
        kind=ACCELEROMETER,
        words="non-orthogonal axes (accelerometer)",
        page_words="the non-orthogonal calibration",
    ),
    Method(
        still.TRIANGULAR.name,
        request=rq.TriangularIn,
        handler=still.triangular,
        response="TriangularOut",
        command="calibrate",
        formats=CORRECTION_EXPORTS,
        kind=ACCELEROMETER,
        words="free poses (accelerometer)",
        page_words="the free-pose calibration",
    ),
    Method(
        "cube",
        request=rq.CubeIn,
        handler=cube.cube,
        response="CubeOut",
        command="calibrate",
        formats=CORRECTION_EXPORTS,
        kind="a cube calibration (accelerometer, gyroscope, magnetometer)",
        words="24 positions of a cube (accelerometer and gyroscope)",
        page_words="the cube calibration",
    ),
    Method(
        "autocal",
        request=rq.AutocalIn,
        handler=autocal.autocal,
        response="AutocalOut",
        command="autocal",
        formats=CORRECTION_EXPORTS,
        kind=ACCELEROMETER,
        words="free-living log (accelerometer)",
        page_words="the free-living calibration",
    ),
    Method(
        "noise",
        request=rq.NoiseIn,
        handler=noise.noise,
        response="NoiseOut",
        command="noise",
        formats=NOISE_EXPORTS,
        kind="a noise characterisation",
        words="noise (Allan deviation)",
        page_words="the noise characterisation",
    ),
    Method(
        "magnetometer",
        request=rq.MagnetometerIn,
        handler=compass.magnetometer,
        response="MagnetometerOut",
        command="calibrate",
        formats=CORRECTION_EXPORTS,
        kind="a compass calibration",
        words="the compass (magnetometer)",
        page_words="the compass calibration",
    ),
    Method(
        "temperature",
        request=rq.TemperatureIn,
        handler=temperature.temperature,
        response="TemperatureOut",
        command="temperature",
        formats=TEMPERATURE_EXPORTS,
        kind="a temperature calibration (offsets against temperature)",
        words="temperature drift (accelerometer and gyroscope)",
        page_words="the temperature calibration",
    ),
    Method(
        "compass_flight",
        request=rq.CompassFlightIn,
        handler=flight_compasses.compass_flight,
        response="CompassFlightOut",
        command="calibrate",
        formats=FLIGHT_COMPASS_EXPORTS,
        kind="a compass calibrated from a flight",
        words="the compass from a flight (flight controller)",
        page_words="the compass calibration from a flight",
    ),
    Method(
        "imported",
        request=rq.ImportIn,
        handler=imports.imported,
        response="ImportedOut",
        command="import",
        formats=CORRECTION_EXPORTS,
        kind="a calibration imported from a device",
        words="imported from the device's firmware",
        page_words="the imported calibration",
    ),
)
TABLE: tuple[Method[Any], ...] = _ENTRIES
"""Every method. ``auto`` on a recording of the magnetometer alone is the compass (its handler calls
:func:`app.workflows.compass.auto_compass`), answered as method ``magnetometer``: not a method of its own."""

BY_NAME = {method.name: method for method in TABLE}

AUTO_CHOICES = (*still.AUTO_CHOICES, compass.CompassAsk.method)
"""What ``auto`` answers as: a fit of still readings it chose, or the compass on a recording of the magnetometer
alone (:func:`app.workflows.compass.auto_compass`)."""

METHODS = tuple(BY_NAME)
"""The values of `method` that POST /api/v1/calibrations accepts."""

if TYPE_CHECKING:  # a union the table makes at run time: to the checker, the base of every request model
    CalibrationIn: TypeAlias = rq.Strict
else:
    CalibrationIn = Annotated[
        Union[tuple(method.request for method in TABLE)],  # noqa: UP007 - a union of a run-time tuple: no `|` spelling
        Field(discriminator="method"),
    ]
"""A calibration request: the request model its ``method`` names."""

CALIBRATION_REQUEST = TypeAdapter(CalibrationIn)

ALL_FORMATS = tuple(dict.fromkeys(fmt for method in TABLE for fmt in method.formats))
"""Every export format of any calibration (``trical export --format``)."""


def parse_calibration_request(data: dict[str, Any]) -> CalibrationIn:
    """The request model for ``data`` (its ``method`` picks the model).

    Raises
    ------
    pydantic.ValidationError
        Described in words by :func:`describe_errors`.
    """
    return CALIBRATION_REQUEST.validate_python(data)


def calibrate(request: Any, recording: RecordingSource | None = None) -> Calibration:
    """The calibration a request asks for, computed by its method's handler (unstored, typed: its plain form by
    :meth:`~app.workflows.calibration.Calibration.body`); see :func:`app.workflows.entry.calibrate`."""
    return run_handler(BY_NAME[request.method].handler, request, recording)


def commanded_by(command: str) -> tuple[str, ...]:
    """The methods a ``trical`` command runs (``calibrate``: the choices of its ``--method``)."""
    return tuple(method.name for method in TABLE if method.command == command)


def formats_in_words() -> str:
    """The export formats and the methods whose calibrations offer them, in a line for the API's docs."""
    groups: dict[tuple[str, ...], list[str]] = {}
    for method in TABLE:
        groups.setdefault(method.formats, []).append(method.name)
    return "; ".join(f"method {', '.join(names)}: {', '.join(formats)}" for formats, names in groups.items())


def export(body: dict[str, Any], fmt: str) -> Export:
    """A stored calibration in ``fmt``, which its method must offer (:attr:`Method.formats`).

    Raises
    ------
    ExportError
        A format its method does not offer (naming those it does), or one that does not fit this
        calibration's model (:func:`app.io.exports.exporters.export_calibration`).
    """
    method = BY_NAME.get(body.get("method", ""))
    if method is not None and fmt not in method.formats and fmt in ALL_FORMATS:
        kinds = dict.fromkeys(m.kind for m in TABLE if fmt in m.formats)
        raise ExportError(
            f"format {fmt!r} does not fit this calibration, {method.kind} (method {method.name}): "
            f"{fmt} writes {' or '.join(kinds)}; use one of {', '.join(method.formats)}"
        )
    return export_calibration(body, fmt)


# -- a request that fails validation, in words (the API's 422s and the CLI's errors) ---------------------------


def _location(loc: Iterable[int | str]) -> str:
    parts: list[str] = []
    for item in loc:
        if item in ("body", "query", "path", "form") and not parts:
            continue
        if item in METHODS and len(parts) == 0:
            continue  # the discriminator's branch, not a field
        if isinstance(item, int):
            parts.append(f"[{item}]")
        else:
            parts.append(("." if parts else "") + str(item))
    return "".join(parts) or "body"


def describe_errors(errors: Iterable[Mapping[str, Any]]) -> str:
    """One readable sentence per problem, e.g. ``readings[2].up: Input should be '+x', ...``."""
    messages = []
    for err in errors:
        if err.get("type") == "json_invalid":
            messages.append(f"the body is not valid JSON ({err.get('ctx', {}).get('error', 'parse error')})")
            continue
        if err.get("type") == "missing" and tuple(err.get("loc", ())) == ("body",):
            messages.append("the request needs a JSON body")
            continue
        if err.get("type") == "union_tag_not_found":
            messages.append(
                f"the field `{err.get('ctx', {}).get('discriminator', 'method').strip(chr(39))}` is "
                f"required: one of {', '.join(METHODS)}"
            )
            continue
        msg = err.get("msg", "invalid").removeprefix("Value error, ")
        messages.append(f"{_location(err.get('loc', ()))}: {msg}")
    return "; ".join(dict.fromkeys(messages)) or "invalid request"
