"""What a recording can do: the calibrations its data support, in the order a person meets them, each with a
one-line reason and whether it is ready to run (the recording's ``supports``, docs/rest.md).

The recording decides the journey: a person brings a file, and trical says what it holds and what it can do
with it before anything runs. The page offers these in this order and runs the first one ready (the one the
person chose, if they chose); ``trical calibrate FILE`` without ``--method`` does the same. A calibration the
recording does not support is not listed; one it supports but cannot run yet says why, as a fact of the data,
never as a failure.

Order (decided here; issue "the recording decides the journey"): still poses (the accelerometer's calibration),
a compass turn (the magnetometer's) or, on a flight controller's log, the compass from the flight; one long rest
(the noise); a sensor that warms at rest (the temperature); a long wear recording (auto-calibration).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from app.calibration.shared.orientations import CANONICAL_SIX, WITHIN_LABEL_ANGLE
from app.io.log import LogData
from app.io.plural import counted

FREE_POSES_MIN = 9
"""A magnitude model's least number of free poses (Farago et al.: nine parameters)."""

TURN_MIN_DEG = 90.0
"""A compass turn: the field's direction in the sensor's frame must swing through at least this much (the
largest angle between two readings' directions) for an ellipsoid or a sphere to be fitted to it."""

AUTOCAL_MIN_S = 6 * 3600.0
"""A wear recording long enough for auto-calibration: Farago et al.'s rests of everyday wear fill the
orientation bins over hours (its own gates say whether they did)."""


@dataclass(frozen=True)
class Support:
    """A calibration a recording supports: the ``method`` of POST /api/v1/calibrations, ``why`` in one line (a fact
    of the data), and whether it is ``ready`` to run on it as it is."""

    method: str
    why: str
    ready: bool
    asks: tuple[str, ...] = ()
    """The fields that would make it ready: the upload's (a sampling rate for a file without a time column) or the
    calibration's (the place and date of a flight log without a GPS fix)."""

    def to_dict(self) -> dict[str, Any]:
        return {**asdict(self), "asks": list(self.asks)}


def supports(log: LogData, segments: list[dict[str, Any]], *, fix: dict[str, Any] | None = None) -> list[Support]:
    """The calibrations a recording supports, in the order a person meets them (the module's docstring).

    Parameters
    ----------
    log : LogData
        The recording as read.
    segments : list of dict
        Its still segments (app.workflows.recordings.still_segments), each with ``up`` (the axis within 20° of
        vertical, or None).
    fix : dict, optional
        A flight controller's log's first GPS fix (``latitude_deg``, ``longitude_deg``, ``date``), where it has one.

    Returns
    -------
    list of Support
        The first one ``ready`` is what the page and ``trical calibrate`` run when the person chose nothing.
    """
    out: list[Support] = []
    if log.acc is not None:
        out.append(_still_poses(segments))
    if log.flight is not None:
        out.extend(_flight_compass(log, fix))
    elif log.mag is not None:
        out.append(_compass_turn(np.asarray(log.mag, dtype=float)))
    out.append(_noise(log))
    if log.temperature_c is not None and (log.acc is not None or log.gyr is not None):  # an IMU's drift
        out.append(_temperature(log.temperature_c))
    rate = log.sampling_rate_hz
    if log.acc is not None and rate and log.n_samples / rate >= AUTOCAL_MIN_S:
        out.append(
            Support("autocal", f"{log.n_samples / rate / 3600:.1f} h of wear: its rests in every orientation", True)
        )
    return out


def first_ready(found: list[dict[str, Any]]) -> dict[str, Any] | None:
    """The support a recording runs first when the person chose nothing (plain ``supports`` as stored)."""
    return next((s for s in found if s["ready"]), None)


def _still_poses(segments: list[dict[str, Any]]) -> Support:
    ups = {s["up"] for s in segments if s.get("up")}
    n = len(segments)
    if ups >= set(CANONICAL_SIX):
        return Support(
            "auto", f"{counted(n, 'still pose')} covering the six axes: the accelerometer's calibration", True
        )
    if n >= FREE_POSES_MIN:
        return Support(
            "auto", f"{n} still poses in free directions: the accelerometer's calibration by magnitude", True
        )
    return Support(
        "auto",
        f"{counted(n, 'still pose')}: the accelerometer's calibration needs the six axes up in turn (each "
        f"{WITHIN_LABEL_ANGLE} of vertical; {len(ups)} of 6 seen) or {FREE_POSES_MIN} or more free poses",
        False,
    )


def _compass_turn(mag: np.ndarray) -> Support:
    finite = mag[np.all(np.isfinite(mag), axis=1)]
    if len(finite) < 10 or not np.any(finite):
        return Support("magnetometer", "the magnetometer reads nothing (zero or no readings)", False)
    swing, not_a_turn = _turn_deg(finite)
    if swing >= TURN_MIN_DEG:
        return Support("magnetometer", f"the magnetometer turned through {swing:.0f}° of directions: the compass", True)
    if not_a_turn is not None:
        return Support(
            "magnetometer", f"the magnetometer {not_a_turn} (the compass needs a turn through every direction)", False
        )
    return Support(
        "magnetometer",
        f"the magnetometer's direction swings only {swing:.0f}° (the compass needs a turn through every direction)",
        False,
    )


TURN_SPREAD_NOISE = 10.0
"""A turn moves the readings this many times their sample-to-sample noise at least: a still compass's readings
spread over a few times it."""


TURN_SHELL = 0.6
"""Readings of a turn lie on a shell about their centre: the 10th to 90th percentile of their distances from it
within this fraction of the median (an ellipsoid of soft iron stays well inside it; a cloud of noise, or a few
seconds of handling beside a long rest, does not)."""

TURN_ONE_SIDE = 0.5
"""…and no sixth of the directions (the side of a cube they point through) holds more than this fraction."""


def _turn_deg(mag: np.ndarray) -> tuple[float, str | None]:
    """How far the field's direction turned in the sensor's frame: the largest angle between two readings seen
    from their centre (the middle of their range on each axis, the hard iron's first estimate, as MotionCal and
    Adafruit's tools begin); or 0 with what the readings did instead of a turn: move no more than their noise, lie
    off a shell about that centre, or point mostly to one side of it."""
    spread = mag.max(axis=0) - mag.min(axis=0)
    if float(spread.max()) <= TURN_SPREAD_NOISE * _noise_floor(mag):
        return 0.0, "did not turn (its readings move no more than their noise)"
    centred = mag - (mag.max(axis=0) + mag.min(axis=0)) / 2.0
    norms = np.linalg.norm(centred, axis=1)
    low, mid, high = np.percentile(norms, [10, 50, 90])
    if mid <= 0 or (high - low) > TURN_SHELL * mid:
        return 0.0, "turned only part of the way: its readings do not go round their middle as a turn does"
    units = centred[norms > 0] / norms[norms > 0, None]
    axis = np.abs(units).argmax(axis=1)
    side = axis * 2 + (units[np.arange(len(units)), axis] > 0)
    crowded = np.bincount(side, minlength=6).max() / len(units)
    if crowded > TURN_ONE_SIDE:
        return (
            0.0,
            f"turned only part of the way: {100 * crowded:.0f} % of its readings point to one side of their middle",
        )
    return _largest_angle_deg(units), None


def _noise_floor(mag: np.ndarray, window: int = 10) -> float:
    """The readings' noise where they are quietest (the tenth percentile of 10-sample windows' spread, the largest
    axis), and never under their quantization step (the smallest change between two readings)."""
    n = len(mag) // window * window
    quiet = np.percentile(mag[:n].reshape(-1, window, 3).std(axis=1), 10, axis=0) if n else np.zeros(3)
    steps = np.abs(np.diff(mag, axis=0))
    step = float(steps[steps > 0].min()) if np.any(steps > 0) else 0.0
    return max(float(quiet.max()), step, 1e-12)


def _largest_angle_deg(units: np.ndarray) -> float:
    """The largest angle between two of these unit vectors (about; from the extremes along each axis)."""
    picks = np.unique(np.concatenate([units.argmin(axis=0), units.argmax(axis=0)]))
    ext = units[picks]
    cos = np.clip(ext @ units.T, -1.0, 1.0)
    return float(np.degrees(np.arccos(cos.min())))


def _too_few_compass_samples(compasses: list[dict[str, Any]], read: int | None) -> str:
    """Why the compass a flight calibration reads (the instance read, else the first) has too few samples to be
    fitted at all (app.calibration.magnetometer.flight.MIN_FIT_SAMPLES), naming a compass of the log that has
    enough; "" when it has enough."""
    from app.calibration.magnetometer.flight import MIN_FIT_SAMPLES

    counts = {c["instance"]: c["n_samples"] for c in compasses}
    instance = read if read in counts else compasses[0]["instance"]
    if counts[instance] >= MIN_FIT_SAMPLES:
        return ""
    enough = [k for k, n in counts.items() if n >= MIN_FIT_SAMPLES]
    other = f"; compass {enough[0]} has {counts[enough[0]]}: give mag_instance {enough[0]}" if enough else ""
    return (
        f"its compass {instance} logged {counted(counts[instance], 'sample')}: a calibration from a flight needs "
        f"at least {MIN_FIT_SAMPLES}, and a minute of flight with turns{other}"
    )


def _flight_compass(log: LogData, fix: dict[str, Any] | None) -> list[Support]:
    assert log.flight is not None
    flight = log.flight.to_dict()
    compasses = [i for i in flight["instances"] if i["sensor"] == "mag"]
    if not compasses:
        return []
    short = _too_few_compass_samples(compasses, (flight.get("mag") or {}).get("instance"))
    if short:
        return [Support("compass_flight", short, False, ("mag_instance",) if "mag_instance" in short else ())]
    place = f"{fix['latitude_deg']:.2f}°, {fix['longitude_deg']:.2f}°" if fix else ""
    asks: tuple[str, ...]
    if fix and fix.get("date"):
        where, asks = f"the Earth's field at its GPS fix ({place}, {fix['date']})", ()
    elif fix:  # a fix without the GPS's time: the day of the field is unknown
        where, asks = f"the Earth's field at its GPS fix ({place}; the log has no GPS time: give `date`)", ("date",)
    else:
        where = "the Earth's field where it flew (the log has no GPS fix: give latitude_deg, longitude_deg and `date`)"
        asks = ("latitude_deg", "longitude_deg", "date")
    return [
        Support(
            "compass_flight",
            f"a flight controller's log with {counted(len(compasses), 'compass', 'compasses')}: each against the "
            f"flight's attitude and {where}",
            not asks,
            asks,
        )
    ]


def _noise(log: LogData) -> Support:
    from app.calibration.noise.characterise import duration_words
    from app.calibration.noise.still_part import MIN_STILL_FRACTION, NOISE_MIN_S, common_still_runs

    rate = log.sampling_rate_hz
    if rate is None:
        return Support(
            "noise",
            "the noise needs the sampling rate, and this recording has no time column: give sampling_rate_hz",
            False,
            ("sampling_rate_hz",),
        )
    arrays = [np.asarray(getattr(log, s)) for s in ("acc", "gyr", "mag") if getattr(log, s) is not None]
    runs = common_still_runs(arrays, rate) if arrays else []
    longest = max((b - a for a, b in runs), default=0)
    still_s, total_s = longest / rate, log.n_samples / rate
    if still_s >= NOISE_MIN_S and longest >= MIN_STILL_FRACTION * log.n_samples:
        return Support(
            "noise", f"one rest of {duration_words(still_s)} of {duration_words(total_s)}: the sensors' noise", True
        )
    needs = f"the noise needs one rest of {duration_words(NOISE_MIN_S)} or more"
    if total_s < NOISE_MIN_S:
        return Support("noise", f"the recording lasts {duration_words(total_s)} ({needs})", False)
    return Support(
        "noise",
        f"its longest rest is {duration_words(still_s)} of {duration_words(total_s)} ({needs}, most of the recording)",
        False,
    )


def _temperature(temperature_c: np.ndarray) -> Support:
    from app.calibration.temperature import MIN_SPAN_C

    t = np.asarray(temperature_c, dtype=float)
    t = t[np.isfinite(t)]
    span = float(t.max() - t.min()) if t.size else 0.0
    if span >= MIN_SPAN_C:
        return Support("temperature", f"the sensor warms through {span:.1f} °C: its drift with temperature", True)
    return Support(
        "temperature",
        f"the sensor's temperature spans {span:.1f} °C (the drift needs {MIN_SPAN_C:.0f} °C or more, at rest)",
        False,
    )
