"""The compass: a magnetometer turned through all directions."""

from __future__ import annotations

import datetime
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from app.calibration import CalibrationError
from app.io.log import MAG_TO_UT, LogData
from app.workflows.calibration import Calibration
from app.workflows.recordings import RecordingSource, still_segments
from app.workflows.requests import AutoRequest, FieldPlace, MagnetometerRequest


def magnetometer_reference(
    request: FieldPlace, notes: list[str], fix: dict[str, Any] | None = None
) -> tuple[dict[str, Any], dict[str, Any]]:
    """The field the calibration is referenced to: ``field_ut`` given, else the geomagnetic model's at
    the place and day (the request's, else a flight log's first GPS fix ``fix``), else none (estimated by the
    fit); with a place, the model's dip and declination too. Returns the keyword arguments of
    :func:`~app.calibration.magnetometer.fit_magnetometer` and the metrics naming the model and its day (none
    without a place)."""
    reference: dict[str, Any] = {"field_ut": request.field_ut, "field_source": "given" if request.field_ut else None}
    lat, lon, day, height = request.latitude_deg, request.longitude_deg, request.date, request.height_m
    if lat is None and fix is not None:
        lat, lon = fix["latitude_deg"], fix["longitude_deg"]
        day = day or (datetime.date.fromisoformat(fix["date"]) if fix.get("date") else None)
        notes.append(f"the Earth's field at the log's first GPS fix ({lat:.5f}°, {lon:.5f}°)")
    if lat is None or lon is None:
        if request.date is not None or request.height_m is not None:
            notes.append(
                "`date` and height_m without latitude_deg and longitude_deg are not used: give the place too "
                "for the Earth's field there"
            )
        return reference, {}
    from app.geomag import GeomagneticRangeError, reference_field  # the model's package loads only here

    day = day or datetime.datetime.now(datetime.UTC).date()
    try:
        earth = reference_field(day, lat, lon, 0.0 if height is None else height)
    except GeomagneticRangeError as exc:
        raise CalibrationError(str(exc)) from None
    reference.update(inclination_deg=earth.inclination_deg, declination_deg=earth.declination_deg)
    if request.field_ut is None:
        reference.update(field_ut=earth.field_ut, field_source="model")
    elif abs(request.field_ut / earth.field_ut - 1.0) > 0.1:
        notes.append(
            f"field_ut {request.field_ut:g} µT is more than 10 % from the {earth.model} field here "
            f"({earth.field_ut:.1f} µT): the given value is used"
        )
    return reference, {"field_model": earth.model, "field_date": day.isoformat()}


def compass_rests(log: LogData, segments: list[dict[str, Any]]) -> list[tuple[Sequence[float], np.ndarray]]:
    """The accelerometer's still segments of a recording with their mean magnetometer reading."""
    if log.mag is None or log.acc is None:
        return []
    mag = log.mag * MAG_TO_UT[log.units["mag"]]
    return [
        (seg["acc_mean"], mag[seg["start"] : seg["end"]].mean(axis=0)) for seg in segments if seg["end"] > seg["start"]
    ]


def inline_mag(mag: np.ndarray, notes: list[str]) -> tuple[np.ndarray, str]:
    """A request's inline magnetometer readings in µT, or in counts (``raw``), as the field they show says
    (app.io.readers.units, as an upload's): a board's compass page sends its counts as they are."""
    from app.io.readers.chips import GAUSS_UT
    from app.io.readers.units import field_magnitude, infer_mag_unit

    inferred = infer_mag_unit(mag)
    if inferred in (None, "uT"):
        return mag, "uT"
    field = field_magnitude(mag)
    words = "counts" if inferred == "raw" else inferred
    notes.append(
        f"the readings show a field of {field:.4g}, which is {words}: "
        + ("calibrated in counts" if inferred == "raw" else "converted into µT")
    )
    return (mag, "raw") if inferred == "raw" else (mag * {"gauss": GAUSS_UT, **MAG_TO_UT}[inferred], "uT")


def magnetometer(request: MagnetometerRequest, recording: RecordingSource | None) -> Calibration:
    """Method ``magnetometer``: inline readings or a recording, referenced to the field given, the Earth's at
    a place, or estimated."""
    from app.calibration.magnetometer import fit_magnetometer  # scipy.optimize: see still.calibrate_unknown

    notes: list[str] = []
    rests: list[tuple[Sequence[float], np.ndarray]] = []
    unit = "uT"
    if recording is None:
        mag, unit = inline_mag(np.asarray(request.mag, dtype=float), notes)
        source = {} if request.source is None else {"source": request.source}
    else:
        log = recording.read(clock="mag")  # a flight controller's compass on its own clock
        if log.mag is None:
            raise CalibrationError(
                f"the recording has no magnetometer columns (it has {', '.join(log.channels)}): the magnetometer "
                "method needs mag_x, mag_y, mag_z — record the magnetometer (uncalibrated) while turning the device"
            )
        unit = log.units["mag"]
        mag = log.mag * MAG_TO_UT.get(unit, 1.0)
        unit = "raw" if unit == "raw" else "uT"
        # The stored segments are on the IMU's clock in a flight log: its compass's rests are found on its own.
        segments = still_segments(log)[0] if log.flight is not None else recording.meta.get("segments") or []
        rests = compass_rests(log, segments)
        source = recording.source_fields
    flight = (recording.meta.get("flight") or {}) if recording is not None else {}
    reference, extra = magnetometer_reference(request, notes, flight.get("fix"))
    if flight:
        notes.append(
            "a flight log's compass is read as the firmware corrected it (its stored offsets, scales and motor "
            "term applied): b and M are what this turn puts beyond the firmware's own calibration, b = 0 and "
            "M = I where they agree. This method knows neither the attitude nor the motors' current, which moves "
            "the field in flight: the compass from the flight (method compass_flight) fits both"
        )
    counts = unit == "raw" and reference["field_ut"] is None
    if counts:
        notes.append(
            "the magnetometer's readings are counts and no field was given: M maps them to the "
            "readings' own scale, not to µT, and every figure is in counts — give chip (the part and "
            "its range), or a place and date, or field_ut"
        )
    result = fit_magnetometer(
        mag, rests=rests, raw_comparable=unit == "uT", label="counts" if counts else "µT", **reference
    )
    return Calibration.of(
        result,
        extra,
        unit=unit,
        notes=notes,
        device_id=request.device_id,
        label=request.label or (recording.meta.get("filename") if recording else None),
        **source,
    )


@dataclass(frozen=True)
class CompassAsk:
    """What the compass calibration reads of a request (:func:`magnetometer`): ``auto`` on a recording of the
    magnetometer alone asks with no place, date or field, so that the field is estimated."""

    recording_id: str | None
    device_id: str | None = None
    label: str | None = None
    mag: list[list[float]] | None = None
    date: datetime.date | None = None
    latitude_deg: float | None = None
    longitude_deg: float | None = None
    height_m: float | None = None
    field_ut: float | None = None
    source: str | None = None
    method: str = "magnetometer"


def auto_compass(request: AutoRequest, recording: RecordingSource) -> Calibration:
    """``auto`` on a recording of the magnetometer alone: the compass, referenced to the Earth's field at the place
    and date given (``latitude_deg`` with ``longitude_deg``), or to ``field_ut``, else estimated."""
    placed = request.longitude_deg is not None
    compass = CompassAsk(
        recording_id=request.recording_id,
        device_id=request.device_id,
        label=request.label,
        date=request.date,
        latitude_deg=request.latitude_deg if placed else None,
        longitude_deg=request.longitude_deg,
        height_m=request.height_m if placed else None,
        field_ut=request.field_ut,
    )
    calibration = magnetometer(compass, recording)
    choice = {
        "method": compass.method,
        "candidates": {},
        "why": "the recording holds the magnetometer alone (no accelerometer columns): the compass calibration",
    }
    return calibration.with_fields(choice=choice)
