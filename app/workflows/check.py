"""A stored calibration checked on a new recording, and two stored calibrations compared: the recording's still
poses, compass turn and gyroscope rest read as the core's check takes them (app.calibration.check), in the
calibration's units; the bodies rebuilt as their results (app.calibration.registry) and compared through their
corrections (app.calibration.compare)."""

from __future__ import annotations

from typing import Any

import numpy as np

from app.calibration import registry
from app.calibration.check import CANNOT, SensorCheck, check, combined
from app.calibration.compare import compare
from app.calibration.shared.errors import CalibrationError
from app.calibration.shared.result import CalibrationResult
from app.io.log import TO_SI, LogData
from app.workflows.recordings import RecordingSource, still_segments

MAX_LABELLED_POSES = 11
"""Poses that each lie along an axis are checked against the affine model of known orientations up to this many
(the six faces, twice at most); more poses are checked against the model of unknown orientations, which needs no
pose to lie exactly along an axis."""


FLIGHT_COMPASS = (
    "a flight's compass is not checked here: in flight the field it reads moves with the motors' current and the "
    "flight turns it through few directions, which a check of the field's strength cannot tell from a drift — "
    "check it on a turn through all directions on the ground (about 60 s), or calibrate this flight too "
    "(method compass_flight) and compare the two calibrations"
)
"""Why a flight log's compass is not checked (issue 47 leaves it open: a flight's compass is judged against the
flight's attitude, app/calibration/magnetometer/flight_*.py, not against the strength of the field alone)."""


def _in_unit(values: np.ndarray, sensor: str, have: str | None, want: str | None, flag: str) -> np.ndarray:
    """A sensor's readings in the unit the calibration's correction takes, or a refusal naming the unit to read in."""
    if have == want or want is None or have is None:
        return values
    table = TO_SI[sensor]
    if have in table and want in table and "raw" not in (have, want):
        return values * (table[have] / table[want])
    raise CalibrationError(
        f"the calibration's {sensor} correction takes readings in {want} and the recording's are in {have}: "
        f"read the recording in {want} ({flag})"
    )


def _finite(values: np.ndarray) -> np.ndarray:
    """The rows of readings where the sensor read (a sensor merged onto another's clock is NaN across its gaps)."""
    v = np.asarray(values, dtype=float)
    return v[np.all(np.isfinite(v), axis=1)]


def _unit_words(unit: str | None) -> str | None:
    """A correction's unit as the recordings name it (a compass's µT is ``uT``)."""
    return {"µT": "uT", "°/s": "deg/s"}.get(unit or "", unit)


def readings_of(result: CalibrationResult, log: LogData) -> dict[str, Any]:
    """What a recording gives the check of a result: the still poses' means and their labels (the accelerometer),
    the readings of the turn and its still moments beside the accelerometer's (the magnetometer), the gyroscope during
    the longest rest; each in the unit of the result's correction of that sensor, and only for the sensors it
    corrects."""
    corrections = result.corrections()
    out: dict[str, Any] = {}
    segments: list[dict[str, Any]] = []
    if log.acc is not None and set(corrections) & {"acc", "gyr", "mag"}:
        segments, _ = still_segments(log)
    if "acc" in corrections and log.acc is not None:
        means = np.array([s["acc_mean"] for s in segments], dtype=float).reshape(-1, 3)
        out["still_means"] = _in_unit(
            means, "acc", log.units.get("acc"), _unit_words(corrections["acc"].input_unit), "acc_unit"
        )
        labels = [s["up"] for s in segments]
        if 0 < len(labels) <= MAX_LABELLED_POSES and all(labels):
            out["labels"] = labels
    if "mag" in corrections and log.mag is not None:
        mag_unit = log.units.get("mag"), _unit_words(corrections["mag"].input_unit)
        out["mag"] = _in_unit(_finite(log.mag), "mag", *mag_unit, "mag_unit")
        # The still moments of the turn: the accelerometer's up beside the field (the compass's orientation).
        rests = [
            (np.asarray(s["acc_mean"], dtype=float), _finite(log.mag[s["start"] : s["end"]]).mean(axis=0))
            for s in segments
            if len(_finite(log.mag[s["start"] : s["end"]]))
        ]
        if rests:
            out["rests"] = [(acc, _in_unit(mag, "mag", *mag_unit, "mag_unit")) for acc, mag in rests]
    if "gyr" in corrections and log.gyr is not None and segments:
        longest = max(segments, key=lambda s: s["end"] - s["start"])
        out["gyr_rest"] = _in_unit(
            _finite(log.gyr[longest["start"] : longest["end"]]),
            "gyr",
            log.units.get("gyr"),
            _unit_words(corrections["gyr"].input_unit),
            "gyr_unit",
        )
    return out


def clock_for(body: dict[str, Any]) -> str | None:
    """The clock a recording is read on for the check of ``body``: a flight log's compass on its own (``mag``) where
    the calibration corrects the magnetometer and not the accelerometer (app.io.flight.instances), else as stored."""
    sensors = registry.from_dict(body).corrected_sensors()
    return "mag" if "mag" in sensors and "acc" not in sensors else None


def check_source(
    body: dict[str, Any],
    source: RecordingSource,
    *,
    field_ut: float | None = None,
    inclination_deg: float | None = None,
) -> dict[str, Any]:
    """:func:`check_recording` of a stored recording, read on the clock the calibration needs (:func:`clock_for`)."""
    log = source.read(clock=clock_for(body))
    return check_recording(body, log, field_ut=field_ut, inclination_deg=inclination_deg)


def check_recording(
    body: dict[str, Any],
    log: LogData,
    *,
    field_ut: float | None = None,
    inclination_deg: float | None = None,
) -> dict[str, Any]:
    """The check of a stored calibration (its body) on a recording: the verdict, its reasons and each sensor's
    figures (docs/rest.md, "Check a calibration").

    Raises
    ------
    CalibrationError
        When the recording holds no readings of a sensor the calibration corrects, or holds them in a unit the
        correction cannot take.
    """
    result = registry.from_dict(body)
    found = readings_of(result, log)
    if not found:
        raise CalibrationError(
            f"the recording holds {', '.join(log.channels) or 'no sensor'} and the calibration corrects "
            f"{', '.join(result.corrections()) or 'nothing'}: check it on a recording of a sensor it corrects"
        )
    flight_compass = found.pop("mag") if log.flight is not None and "mag" in found else None
    if flight_compass is not None:
        found.pop("rests", None)
    checks = list(check(result, field_ut=field_ut, inclination_deg=inclination_deg, **found).sensors) if found else []
    if flight_compass is not None:
        checks.append(SensorCheck("mag", CANNOT, (FLIGHT_COMPASS,), len(flight_compass)))
    return {"calibration_id": body.get("id"), **combined(checks).to_dict()}


def check_turn(
    body: dict[str, Any],
    mag: Any,
    *,
    field_ut: float | None = None,
    inclination_deg: float | None = None,
) -> dict[str, Any]:
    """The check of a stored calibration's compass on a turn's readings as the device read them (the page's live
    turn: in the unit of the calibration's compass correction), as :func:`check_recording` answers it.

    Raises
    ------
    CalibrationError
        When the calibration does not correct the compass.
    """
    result = registry.from_dict(body)
    if "mag" not in result.corrections():
        raise CalibrationError(
            f"the calibration corrects {', '.join(result.corrections()) or 'nothing'}, not the compass: a turn "
            "checks a compass's calibration; check it on a recording of a sensor it corrects (recording_id)"
        )
    readings = _finite(np.asarray(mag, dtype=float).reshape(-1, 3))
    checks = check(result, mag=readings, field_ut=field_ut, inclination_deg=inclination_deg).sensors
    return {"calibration_id": body.get("id"), **combined(list(checks)).to_dict()}


def compare_calibrations(
    a: dict[str, Any],
    b: dict[str, Any],
    *,
    field_ut: float | None = None,
    inclination_deg: float | None = None,
) -> dict[str, Any]:
    """Two stored calibrations compared (B − A), sensor by sensor (docs/rest.md, "Compare two calibrations").

    Raises
    ------
    CalibrationError
        When they correct no sensor in common, or take readings in different units.
    """
    result = compare(
        registry.from_dict(a), registry.from_dict(b), field_ut=field_ut, inclination_deg=inclination_deg
    ).to_dict()
    return {"calibration_id": a.get("id"), "with": b.get("id"), **result}
