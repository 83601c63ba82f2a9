"""What each handler reads of its request: the request models as the workflow sees them, by their fields.

The request models are pydantic's (:mod:`app.calibration_requests`), which the workflow does not import
(docs/architecture.md). A handler takes one of these protocols instead: each names, read-only, the fields the
handler reads, so a misspelled field is a type error here, and the method table (:mod:`app.methods`), whose
:class:`~app.methods.Method` binds a request model to its handler, is where mypy checks that the model
gives every field its handler reads, with a type the handler accepts. The fields' meanings and limits are the
models' (one place); here are only their names and types.
"""

from __future__ import annotations

import datetime
from collections.abc import Mapping, Sequence
from typing import Any, Protocol


class Described(Protocol):
    """What every request gives: its method, and the device and label its calibration is stored with."""

    @property
    def method(self) -> str: ...
    @property
    def device_id(self) -> str | None: ...
    @property
    def label(self) -> str | None: ...


class Placed(Protocol):
    """Where the readings were taken, for the local gravity (app.calibration.shared.gravity)."""

    @property
    def gravity(self) -> float | None: ...
    @property
    def latitude_deg(self) -> float | None: ...
    @property
    def height_m(self) -> float | None: ...


class ReadingLike(Protocol):
    """An inline still reading in a known orientation (``readings[i]``)."""

    @property
    def mean(self) -> Sequence[float]: ...
    @property
    def up(self) -> str | None: ...
    @property
    def expected(self) -> Sequence[float] | None: ...
    @property
    def std(self) -> Sequence[float] | None: ...
    @property
    def count(self) -> int | None: ...


class StillRequest(Described, Placed, Protocol):
    """A calibration from still readings, inline or of a recording's segments."""

    @property
    def unit(self) -> str: ...
    @property
    def holdout(self) -> Sequence[Sequence[float]] | None: ...
    @property
    def recording_id(self) -> str | None: ...
    @property
    def segments(self) -> list[int] | None: ...
    @property
    def model_fields_set(self) -> set[str]:
        """The fields the caller gave (the others hold their defaults)."""
        ...


class KnownOrientationRequest(StillRequest, Protocol):
    """Still readings each in a known orientation: ``six_position``, ``orientations``."""

    @property
    def readings(self) -> Sequence[ReadingLike] | None: ...


class MagnitudeRequest(StillRequest, Protocol):
    """Still readings in orientations nobody knows, fitted by their magnitude: ``nonorthogonal``."""

    @property
    def means(self) -> Sequence[Sequence[float]] | None: ...


class SolvedRequest(MagnitudeRequest, Protocol):
    """A magnitude fit whose solver the caller chooses: ``triangular``."""

    @property
    def solver(self) -> str: ...


class Dated(Protocol):
    """Where and when a compass was turned or flown, for the Earth's field it is referenced to (app.geomag)."""

    @property
    def date(self) -> datetime.date | None: ...
    @property
    def latitude_deg(self) -> float | None: ...
    @property
    def longitude_deg(self) -> float | None: ...
    @property
    def height_m(self) -> float | None: ...


class FieldPlace(Dated, Protocol):
    """…or the field's magnitude itself, given."""

    @property
    def field_ut(self) -> float | None: ...


class AutoRequest(MagnitudeRequest, FieldPlace, Protocol):
    """``auto``: still readings whose model the workflow picks, or a compass's turn."""


class MagnetometerRequest(Described, FieldPlace, Protocol):
    """``magnetometer``: a compass's readings, inline or of a recording."""

    @property
    def mag(self) -> Sequence[Sequence[float]] | None: ...
    @property
    def source(self) -> str | None: ...
    @property
    def recording_id(self) -> str | None: ...


class SectionLike(Protocol):
    """One annotated region of a Ferraris recording."""

    @property
    def start(self) -> int: ...
    @property
    def end(self) -> int: ...


class CubeRequest(Described, Placed, Protocol):
    """``cube``: a recording of a cube's positions and turns."""

    @property
    def protocol(self) -> str | dict[str, object]: ...
    @property
    def field_ut(self) -> float | None: ...
    @property
    def sections(self) -> Mapping[Any, SectionLike] | None:
        """By section's name (the model's names, a Literal of str: a mapping's key type is invariant)."""
        ...


class AutocalRequest(Described, Placed, Protocol):
    """``autocal``: a long recording calibrated by its still periods."""

    @property
    def unit(self) -> str | None: ...
    @property
    def solver(self) -> str: ...
    @property
    def all_axes(self) -> bool: ...


class SensorsRequest(Described, Protocol):
    """``noise`` and ``temperature``: figures of some of a recording's sensors."""

    @property
    def sensors(self) -> Sequence[str] | None: ...


class NoiseRequest(SensorsRequest, Protocol):
    """``noise``: a still recording's noise, of its sensors or of one array's."""

    @property
    def sensor(self) -> str | None: ...


class CompassFlightRequest(Described, Dated, Protocol):
    """``compass_flight``: a flight log's compass against the attitude the firmware estimated."""

    @property
    def mag_instance(self) -> int | None: ...
    @property
    def attitude(self) -> str | None: ...
    @property
    def window(self) -> str: ...
    @property
    def from_s(self) -> float | None: ...
    @property
    def to_s(self) -> float | None: ...


class ImportRequest(Described, Protocol):
    """``imported``: the file a device's calibration is in (base64), and the family it is of where forced."""

    @property
    def file_base64(self) -> str: ...
    @property
    def firmware(self) -> str | None: ...
    @property
    def instance(self) -> int: ...
