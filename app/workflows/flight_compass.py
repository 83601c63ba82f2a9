"""The compass calibrated from a flight: a flight controller's log, its attitude and the Earth's field.

Reads the compass of a stored PX4 or ArduPilot log with its context (:func:`app.io.flight.compass.
read_flight_compass`: the raw readings, the firmware's own field, the attitude, the current or throttle,
the place and date of the first GPS fix), turns the geomagnetic model's field there (IGRF, app.geomag) into
the body frame with the attitude at each compass sample, ``e = C_nbᵀ B_ned``, and fits the compass to it
(:func:`app.calibration.magnetometer.fit_flight_compass`). The attitude is interpolated onto the compass's
times by spherical linear interpolation of its quaternions, the power linearly; samples outside either's
span are left out. One compass is fitted here (:func:`fly`); the method's handler, which fits the one asked and
sets every compass of the log beside it, is :func:`app.workflows.flight_compasses.compass_flight`.
"""

from __future__ import annotations

import datetime
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from app.calibration import CalibrationError
from app.workflows.recordings import RecordingSource
from app.workflows.requests import CompassFlightRequest

if TYPE_CHECKING:
    from app.io.flight.context import FlightCompassLog


def _attitude_on(t: np.ndarray, at: np.ndarray, c_nb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """C_nb at the times ``t`` inside the attitude's span (slerp of its quaternions), and the mask of those."""
    from scipy.spatial.transform import Rotation, Slerp

    order = np.argsort(at, kind="stable")
    at, c_nb = at[order], c_nb[order]
    keep = np.concatenate([[True], np.diff(at) > 0])
    at, c_nb = at[keep], c_nb[keep]
    inside = (t >= at[0]) & (t <= at[-1])
    if len(at) < 2 or not inside.any():
        return np.empty((0, 3, 3)), np.zeros(len(t), dtype=bool)
    slerp = Slerp(at, Rotation.from_matrix(c_nb))
    return slerp(t[inside]).as_matrix(), inside


def _power_on(t: np.ndarray, log: FlightCompassLog) -> tuple[np.ndarray | None, str | None, np.ndarray]:
    """The current (preferred: what the interference follows) or else the throttle at the times ``t``, its
    kind, and the mask of the times inside its span (all true without power)."""
    for values, kind in ((log.current_a, "current"), (log.throttle, "throttle")):
        if values is not None and log.power_time_s is not None and len(values) >= 2:
            pt = np.asarray(log.power_time_s, dtype=float)
            v = np.asarray(values, dtype=float)
            good = np.isfinite(pt) & np.isfinite(v)
            pt, v = pt[good], v[good]
            if len(pt) < 2:
                continue
            inside = (t >= pt[0]) & (t <= pt[-1])
            return np.interp(t, pt, v), kind, inside
    return None, None, np.ones(len(t), dtype=bool)


FLYING_SHARE_OF_HOVER = 0.3
"""The flying part of a log: throttle at least 0.3 of the hover throttle (the median of the throttle while the
motors run, above 0.05), which leaves out the ground before take-off and after landing (throttle 0, or the
spin of armed motors) and keeps a descent (a simulated flight's lowest throttle is 0.42 of its hover's)."""

MIN_WINDOW_SAMPLES = 60
"""A window keeping fewer compass samples than this is not applied (the whole log is fitted, a note says so)."""


def _window(t: np.ndarray, log: FlightCompassLog, request: CompassFlightRequest, notes: list[str]) -> np.ndarray:
    """The samples fitted: the request's ``from_s``–``to_s`` (seconds from the compass's first sample), and with
    ``window = "flying"`` the flying part (:data:`FLYING_SHARE_OF_HOVER` of the hover throttle; with the current
    alone, above the idle's 5th percentile plus that share of the way to its median while flying)."""
    start = t[0] if len(t) else 0.0
    keep = np.ones(len(t), dtype=bool)
    if request.from_s is not None:
        keep &= t - start >= request.from_s
    if request.to_s is not None:
        keep &= t - start <= request.to_s
    if (request.from_s is not None or request.to_s is not None) and keep.sum() < MIN_WINDOW_SAMPLES:
        raise CalibrationError(
            f"from_s–to_s keeps {int(keep.sum())} compass samples of {len(t)} (the log's compass spans "
            f"{t[-1] - start:.0f} s): widen from_s and to_s, or leave them out for the whole flight"
        )
    if request.window != "flying" or log.power_time_s is None:
        return keep
    pt = np.asarray(log.power_time_s, dtype=float)
    for values, kind in ((log.throttle, "throttle"), (log.current_a, "current")):
        if values is None or len(values) < 2:
            continue
        v: np.ndarray = np.interp(t, pt, np.asarray(values, dtype=float))
        # the motors running: throttle above 0.05, or current 1 A above the idle's 5th percentile
        idle, above = (0.0, 0.05) if kind == "throttle" else (float(np.percentile(v, 5)), 1.0)
        running = v[v > idle + above]
        threshold = idle + FLYING_SHARE_OF_HOVER * (float(np.median(running)) - idle) if len(running) else np.inf
        flying = keep & (v >= threshold)
        if flying.sum() < MIN_WINDOW_SAMPLES:
            notes.append(f"the {kind} shows no flight of {MIN_WINDOW_SAMPLES} samples or more: every sample is fitted")
            return keep
        if flying.sum() < keep.sum():
            notes.append(
                f"the flying part is fitted: {int(flying.sum())} of {int(keep.sum())} samples, the {kind} at or above "
                f"{threshold:.2f}{' A' if kind == 'current' else ''} (to fit every sample: window=all)"
            )
        return flying
    return keep


def _place(
    request: CompassFlightRequest, log: FlightCompassLog, notes: list[str]
) -> tuple[float, float, float, datetime.date]:
    """Where and when the flight was: the request's place and date over the log's first GPS fix."""
    lat = request.latitude_deg if request.latitude_deg is not None else log.latitude_deg
    lon = request.longitude_deg if request.longitude_deg is not None else log.longitude_deg
    if lat is None or lon is None:
        raise CalibrationError(
            "the log has no GPS fix, so the Earth's field there is unknown: give the place the "
            "vehicle flew (latitude_deg and longitude_deg) and its date"
        )
    height = request.height_m if request.height_m is not None else (log.altitude_m or 0.0)
    day = request.date or (log.utc.date() if log.utc is not None else None)
    if day is None:
        raise CalibrationError("the log has no GPS time, so the day of the flight is unknown: give its date")
    if request.latitude_deg is not None and log.latitude_deg is not None:
        notes.append(
            f"the place given ({lat:.5f}°, {lon:.5f}°) is used, not the log's GPS fix "
            f"({log.latitude_deg:.5f}°, {log.longitude_deg:.5f}°)"
        )
    return float(lat), float(lon), float(height), day


def _stored_model(log: FlightCompassLog) -> dict[str, np.ndarray | None] | None:
    """The firmware's stored calibration in the fit's terms, ``h = M (Q m − b − k p)`` with Q the rotation it
    applies now: ArduPilot adds COMPASS_OFS to the body-frame field and applies DIA/ODI, so ``M = D``, ``b = −O``;
    PX4 computes ``R S (m − o)``, so ``M = R S Rᵀ``, ``b = R o``. Its motor term only where it stores none (k = 0):
    the firmwares store it in terms that differ by generation. None where nothing is stored (zero offsets, no
    soft iron): there is nothing to keep, and holding "none" would only bend the rest."""
    stored, R = log.stored, np.asarray(log.frame_to_body, dtype=float)
    if not np.any(stored.offsets_ut) and np.allclose(stored.matrix, np.eye(3)):
        return None
    k = np.zeros(3) if stored.motor_kind is None else None
    if stored.firmware == "ardupilot":
        return {"M": np.asarray(stored.matrix, float), "b": -np.asarray(stored.offsets_ut, float), "k": k}
    return {"M": R @ stored.matrix @ R.T, "b": R @ stored.offsets_ut, "k": k}


def _not_measuring_remedy(log: FlightCompassLog) -> str:
    """What to check on a compass that does not measure, in its firmware's settings."""
    switch = log.stored.switch
    off = (
        f"; if it is not fitted or cannot be mended, set {switch} = 0 so that the firmware stops using it"
        if switch
        else ""
    )
    return (
        f"check compass {log.instance}'s wiring, that it is enabled, and that no magnet or power wire sits near it{off}"
    )


@dataclass(frozen=True)
class Flown:
    """One compass of a log fitted to its flight: the log read, the fit, and what it was fitted on."""

    log: Any
    fit: Any
    time_s: np.ndarray
    mag_raw: np.ndarray
    power: np.ndarray | None
    power_kind: str | None
    expected: np.ndarray
    attitude: np.ndarray
    b_ned: np.ndarray
    earth: Any
    place: tuple[float, float, float, datetime.date]


def fly(request: CompassFlightRequest, recording: RecordingSource, instance: int | None, notes: list[str]) -> Flown:
    """The compass ``instance`` of the stored log fitted to its flight (the module's docstring); ``notes`` gets
    the reader's and the window's.

    Raises
    ------
    CalibrationError
        No attitude, no place, a window too narrow, or the fit's refusals (a compass that does not measure).
    """
    from app.calibration.magnetometer import fit_flight_compass
    from app.calibration.magnetometer.flight import MAX_FIT_SAMPLES, thinning
    from app.geomag import GeomagneticRangeError, reference_field
    from app.io.flight.compass import read_flight_compass

    log = read_flight_compass(
        recording.path,
        mag_instance=instance,
        name=recording.meta.get("filename") or "the log",
        attitude=request.attitude,
    )
    notes.extend(log.notes)
    if log.attitude_c_nb is None:
        raise CalibrationError(
            "the log has no attitude (ArduPilot ATT or AHR2, PX4 vehicle_attitude): a compass from "
            "a flight compares the compass with the field the attitude expects — log the attitude"
        )
    every = thinning(len(log.time_s))
    t = np.asarray(log.time_s, dtype=float)[every]
    mag_raw, mag_firmware = log.mag_raw_ut[every], log.mag_firmware_ut[every]
    if every.step > 1:
        notes.append(
            f"a long log: one in {every.step} of its {len(log.time_s)} compass samples fitted (at most "
            f"{MAX_FIT_SAMPLES}; the residuals stay correlated over seconds, so the others add next to nothing)"
        )
    c_nb, inside = _attitude_on(t, np.asarray(log.attitude_time_s, dtype=float), np.asarray(log.attitude_c_nb, float))
    power, kind, powered = _power_on(t, log)
    keep = inside & powered & _window(t, log, request, notes)
    attitude = np.empty((len(t), 3, 3))
    attitude[inside] = c_nb
    place = _place(request, log, notes)
    try:
        earth = reference_field(place[3], *place[:3])
    except GeomagneticRangeError as exc:
        raise CalibrationError(str(exc)) from None
    b_ned = np.array([earth.north_ut, earth.east_ut, earth.down_ut])
    attitude = attitude[keep]
    expected = np.einsum("nji,j->ni", attitude, b_ned)  # e = C_nbᵀ B_ned
    if kind is None:
        notes.append("the log has neither the battery current nor the throttle: no motor term was tried")
    power = None if power is None else power[keep]
    fit = fit_flight_compass(
        mag_raw[keep],
        expected,
        time_s=t[keep],
        power=power,
        power_kind=kind,
        firmware_field=mag_firmware[keep],
        frame_to_body=log.frame_to_body,
        attitude=attitude,
        earth_ned=b_ned,
        not_measuring_remedy=_not_measuring_remedy(log),
        firmware=log.firmware,
        stored=_stored_model(log),
    )
    return Flown(log, fit, t[keep], mag_raw[keep], power, kind, expected, attitude, b_ned, earth, place)
