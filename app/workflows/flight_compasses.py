"""Which compass of a flight log is lying: every compass of the log fitted to the same flight, one row each with
one action, and the firmware's consistency check between them (:mod:`app.calibration.magnetometer.flight_compare`).

Only for a log with two compasses or more; a compass that does not measure, or whose fit is refused, still has its
row, with why. The method's handler is here too (:func:`compass_flight`): the compass asked, fitted as every compass
is (:func:`app.workflows.flight_compass.fly`), with the table of them all.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from app.calibration import CalibrationError
from app.calibration.magnetometer.flight import MAX_MOTOR_HALF_WIDTH
from app.calibration.magnetometer.flight_compare import action, consistency, pull
from app.calibration.magnetometer.flight_health import CompassNotMeasuringError
from app.calibration.shared.rotations import firmware_matrix, nearest_number
from app.io.errors import LogFormatError
from app.io.exports.compass import ARDUPILOT_MOTCT, PX4_COMP_TYPE, ardupilot_name
from app.workflows.calibration import Calibration
from app.workflows.flight_compass import Flown, fly
from app.workflows.recordings import RecordingSource
from app.workflows.requests import CompassFlightRequest

if TYPE_CHECKING:
    from app.io.flight.context import FirmwareCompassCal

MAX_ORIENTATION_LEFT_DEG = 5.0
"""A mounting is named for re-orienting only where the rotation found lies within 5° of it (the flight fit's own
warning limit): further, the orientation is unresolved and the fit says so."""


def _compass_instances(recording: RecordingSource) -> list[int]:
    instances = (recording.meta.get("flight") or {}).get("instances") or []
    return sorted({int(i["instance"]) for i in instances if i.get("sensor") == "mag"})


def _px4_prefix(stored: FirmwareCompassCal) -> str | None:
    """``CAL_MAGn_`` of the slot the stored calibration came from (its parameters name one), or None."""
    return next((k[:-3] for k in stored.params if k.startswith("CAL_MAG") and k.endswith("_ID")), None)


def _orientation_setting(flown: Flown) -> str | None:
    """The setting that mounts the compass as the flight shows, where it differs from the one applied."""
    fit, stored = flown.fit, flown.log.stored
    if fit.orientation_agrees or fit.angle_left_deg > MAX_ORIENTATION_LEFT_DEG:
        return None
    if flown.log.firmware == "ardupilot":
        now = stored.orientation or 0
        number, _ = nearest_number("ardupilot", fit.rotation @ firmware_matrix("ardupilot", now))
        return f"{ardupilot_name('ORIENT', stored.instance)} = {number}"
    prefix = _px4_prefix(stored)
    return None if prefix is None else f"{prefix}ROT = {fit.rotation_nearest['px4']}"


def _motor_setting(flown: Flown) -> str | None:
    stored, kind = flown.log.stored, flown.power_kind or "current"
    if flown.log.firmware == "ardupilot":
        return f"{ardupilot_name('MOT', stored.instance)}_X/Y/Z (COMPASS_MOTCT = {ARDUPILOT_MOTCT[kind]})"
    prefix = _px4_prefix(stored)
    return None if prefix is None else f"{prefix}X/Y/ZCOMP (CAL_MAG_COMP_TYP = {PX4_COMP_TYPE[kind]})"


def _pull(flown: Flown) -> dict[str, Any] | None:
    """The power's pull on the compass (:func:`.flight_compare.pull`) from a fit of the offsets and the motor term on
    the same samples, and whether the flight determines it (the fit's motor gate)."""
    from app.calibration.magnetometer import fit_flight_compass

    p = flown.power
    if p is None or flown.power_kind is None or np.ptp(p) == 0:
        return None
    try:
        motor = fit_flight_compass(
            flown.mag_raw,
            flown.expected,
            time_s=flown.time_s,
            power=p,
            power_kind=flown.power_kind,
            frame_to_body=flown.log.frame_to_body,
            attitude=flown.attitude,
            earth_ned=flown.b_ned,
            models="offsets+motor",
            firmware=flown.log.firmware,
        )
    except CalibrationError:
        return None
    field = float(np.linalg.norm(flown.b_ned))
    half = motor.motor_half_width
    determined = half is not None and float(np.max(half) * np.ptp(p)) <= MAX_MOTOR_HALF_WIDTH * field
    return {
        **pull(motor.motor_coefficients, float(np.percentile(p, 95)), flown.b_ned),
        "unit": "µT/A" if flown.power_kind == "current" else "µT per unit of throttle",
        "determined": bool(determined),
    }


def _row(flown: Flown) -> dict[str, Any]:
    fit = flown.fit
    heading = fit.heading_error_deg or {}
    row = {
        "instance": flown.log.instance,
        "measures": True,
        "ok": bool(fit.ok),
        "before_deg": (heading.get("before") or {}).get("rms"),
        "after_deg": (heading.get("after") or {}).get("rms"),
        "orientation": fit.rotation_nearest.get("name"),
        "orientation_left_deg": float(fit.angle_left_deg),
        "orientation_agrees": bool(fit.orientation_agrees),
        "orientation_setting": _orientation_setting(flown),
        "pull": _pull(flown),
        "power_kind": flown.power_kind,
        "motor_setting": _motor_setting(flown),
        "switch": flown.log.stored.switch,
        "reason": fit.reasons[0] if fit.reasons else None,
    }
    return row


def _refused_row(recording: RecordingSource, instance: int, error: Exception) -> dict[str, Any]:
    from app.io.flight.compass import read_flight_compass

    try:
        switch = read_flight_compass(recording.path, mag_instance=instance).stored.switch
    except LogFormatError:
        switch = None
    row = {
        "instance": instance,
        "measures": not isinstance(error, CompassNotMeasuringError),
        "ok": False,
        "before_deg": None,
        "after_deg": None,
        "orientation": None,
        "orientation_left_deg": None,
        "orientation_agrees": None,
        "orientation_setting": None,
        "pull": None,
        "power_kind": None,
        "motor_setting": None,
        "switch": switch,
        "reason": str(error),
    }
    return row


def _on(t: np.ndarray, at: np.ndarray, field: np.ndarray) -> np.ndarray:
    return np.column_stack([np.interp(t, at, field[:, k]) for k in range(3)])


def compasses_table(request: CompassFlightRequest, recording: RecordingSource, asked: Flown) -> dict[str, Any]:
    """``{"compasses": [...], "consistency": [...]}`` for a log of two compasses or more (else empty): each
    compass's row (the one asked reuses its fit) and each other compass's field against the first's."""
    instances = _compass_instances(recording)
    if len(instances) < 2:
        return {}
    rows, fields = [], {}
    for instance in instances:
        try:
            flown = asked if instance == asked.log.instance else fly(request, recording, instance, [])
        except (CalibrationError, LogFormatError) as error:
            rows.append(_refused_row(recording, instance, error))
            continue
        rows.append(_row(flown))
        fields[instance] = (np.asarray(flown.log.time_s, float), np.asarray(flown.log.mag_firmware_ut, float))
    checks: list[dict[str, Any]] = []
    if fields:
        primary = min(fields)
        pt, pf = fields[primary]
        for instance, (t, field) in fields.items():
            inside = (t >= pt[0]) & (t <= pt[-1])
            if instance != primary and inside.sum() >= 2:
                checks.append({"pair": [primary, instance], **consistency(_on(t[inside], pt, pf), field[inside])})
    agrees = {c["pair"][1]: c["consistent"] for c in checks}
    rows = [{**row, "consistent": agrees.get(row["instance"])} for row in rows]
    return {"compasses": [{**row, "action": action(row)} for row in rows], "consistency": checks}


def compass_flight(request: CompassFlightRequest, recording: RecordingSource | None) -> Calibration:
    """Method ``compass_flight``: a flight log's compass against the field its attitude expects; with several
    compasses in the log, each beside the others (:func:`compasses_table`)."""
    from app.calibration.magnetometer import FlightCompassCalibration

    if recording is None or recording.meta.get("flight") is None:  # a flight controller's log lists its sensors
        raise CalibrationError(
            "a compass from a flight reads a flight controller's log: upload the PX4 ULog (.ulg) "
            "or ArduPilot DataFlash log (.bin) of a flight with turns"
        )
    read_with = recording.meta.get("read_with") or {}
    instance = request.mag_instance if request.mag_instance is not None else read_with.get("mag_instance")
    notes: list[str] = []
    flown = fly(request, recording, instance, notes)
    log, (lat, lon, height, day), earth = flown.log, flown.place, flown.earth
    flight = {
        "firmware": log.firmware,
        "generation": log.generation,
        "instance": log.instance,
        "external": log.stored.external,
        "raw_how": log.raw_how,
        "frame_to_body": log.frame_to_body.tolist(),
        "stored": log.stored.to_dict(),
        "attitude_source": log.attitude_source,
        "power_source": log.power_source if flown.power_kind else None,
        "place": {"latitude_deg": lat, "longitude_deg": lon, "height_m": height, "date": day.isoformat()},
        **compasses_table(request, recording, flown),
    }
    metrics = {
        "field_ut": earth.field_ut,
        "inclination_deg": earth.inclination_deg,
        "declination_deg": earth.declination_deg,
        "field_model": earth.model,
        "field_date": day.isoformat(),
    }
    result = FlightCompassCalibration.from_fit(flown.fit, flight=flight, metrics=metrics)
    return Calibration.of(
        result,
        {},
        unit="uT",
        notes=notes,
        device_id=request.device_id,
        label=request.label or recording.meta.get("filename"),
        **recording.source_fields,
    )
