"""The steps the API and the CLI share: logs into recordings, requests into calibrations.

Data flows one way (docs/architecture.md): the callers parse a request into the models of
:mod:`app.requests` and find its recording, :func:`calibrate` calls ``io`` to turn files into
arrays and one function of ``calibration``, and returns the plain form that the callers store,
export and serialise.  Nothing here knows HTTP or the database.
"""

from __future__ import annotations

import dataclasses
import datetime
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from app.calibration import (CANONICAL_SIX, STANDARD_GRAVITY, CalibrationError, fit_orientations, fit_six_position,
                             nearest_orientation, normal_gravity)
from app.calibration.errors import InsufficientDataError
from app.calibration.cross_validation import SIX_POSITION_NOTE, cross_validated_error
from app.calibration.trust import review
from app.calibration.validation import as_vectors
from app.calibration.static import detect_static_segments
from app.io.formats import read_log
from app.io.log import LogData
from app.io.parts import pose_from_name
from app.verdict import verdict

BROWSER_STEP = 0.1
"""Browsers round DeviceMotion values to 0.1 m/s² (W3C Device Orientation, fingerprinting mitigation)."""


@dataclass(frozen=True)
class Reading:
    """One averaged still reading handed to a known-orientation method."""

    mean: tuple
    up: str | None = None
    expected: tuple | None = None
    std: tuple | None = None
    count: int | None = None


def reference_gravity(unit: str, gravity: float | None = None, latitude_deg: float | None = None,
                      height_m: float | None = None) -> tuple[float, list[str]]:
    """Reference magnitude in the calibrated output unit, and notes about how it was chosen.

    ``unit: g`` calibrates into g, so the magnitude is 1; otherwise an explicit ``gravity`` wins,
    then local normal gravity from ``latitude_deg`` (and ``height_m``), then 9.80665 m/s².
    """
    notes: list[str] = []
    if unit == "g":
        if gravity is not None or latitude_deg is not None:
            notes.append("readings in g calibrate into g with reference magnitude 1: gravity/latitude_deg ignored")
        return 1.0, notes
    if gravity is not None:
        if latitude_deg is not None:
            notes.append("both gravity and latitude_deg given: the explicit gravity is used")
        return float(gravity), notes
    if latitude_deg is not None:
        return normal_gravity(latitude_deg, 0.0 if height_m is None else height_m), notes
    if height_m is not None:
        notes.append("height_m without latitude_deg is ignored: give latitude_deg too")
    return STANDARD_GRAVITY, notes


def load_log(path: Path, *, sampling_rate_hz: float | None, units: dict, name: str, format: str = "auto",
             lsb_per_g: float | None = None, columns: str | None = None, sign: int | None = None,
             chip: str | None = None, instance: int | None = None, mag_instance: int | None = None,
             clock: str = "imu") -> LogData:
    """Read an uploaded log file into arrays, its format given or detected (app.io.formats); ``instance``,
    ``mag_instance`` and ``clock`` choose the sensors of a flight controller's log (app.io.formats.flight_log)."""
    return read_log(path, format=format, sampling_rate_hz=sampling_rate_hz, units=units, name=name,
                    lsb_per_g=lsb_per_g, columns=columns, sign=sign, chip=chip, instance=instance,
                    mag_instance=mag_instance, clock=clock)


def add_recording(store, recording_id: str, path: Path, *, filename: str | None, sampling_rate_hz: float | None,
                  read_with: dict, owner: str | None) -> dict:
    """Read a saved upload, describe it and store it as a recording; the file is removed if any step fails,
    so that nothing is kept that no recording names.

    Parameters
    ----------
    store : app.store.Store
    recording_id : str
        The id the file was saved under.
    path : pathlib.Path
        The saved upload (one file, or a zip of several files, one per pose).
    filename : str or None
        The name (or names) it came with, for messages and the recording.
    sampling_rate_hz : float or None
        The caller's rate.
    read_with : dict
        How to read it (:func:`load_log`'s options), kept with the recording.
    owner : str or None

    Returns
    -------
    dict
        The stored recording (:func:`describe_log` with its id, filename and creation time).
    """
    try:
        log = load_log(path, sampling_rate_hz=sampling_rate_hz, name=filename or "the file", **read_with)
        body = describe_log(log, {**read_with, "sampling_rate_hz": sampling_rate_hz})
        body["filename"] = filename
        return store.add_recording(recording_id, body, path, owner=owner)
    except BaseException:
        path.unlink(missing_ok=True)
        raise


def quantization_step(samples: np.ndarray, step: float = BROWSER_STEP) -> float | None:
    """``step`` when every sample is a multiple of it (browser rounding), else None."""
    sub = samples[: 10_000]
    scaled = sub / step
    if len(sub) > 10 and np.allclose(scaled, np.round(scaled), atol=1e-6):
        return step
    return None


def describe_log(log: LogData, read_with: dict | None = None) -> dict:
    """Recording metadata and its static segments (docs/rest.md, POST /recordings).

    ``read_with`` holds what the reader was told (``format``, ``units``, ``lsb_per_g``, ``columns``);
    it is kept with the sign applied, so that the stored file is read again the same way.
    """
    segments, part_notes = still_segments(log)
    rate = log.sampling_rate_hz
    notes = list(log.notes) + part_notes
    if log.acc is not None and log.sampling_rate_hz is None:
        notes.append(f"still segments looked for as if sampled at {NOMINAL_RATE_HZ:g} Hz (the log has no rate): "
                     "their start and end are sample indices")
    body = {
        "format": log.format,
        "n_samples": log.n_samples,
        "sampling_rate_hz": rate,
        "duration_s": None if rate is None else log.n_samples / rate,
        "channels": log.channels,
        "units": log.units,
        "columns": log.columns,
        "notes": notes,
        "warnings": list(log.warnings),
        "sign": log.sign,
        "timing": None if log.timing is None else log.timing.to_dict(),
        "read_with": {"format": "auto", "units": {}, "lsb_per_g": None, "columns": None, "chip": None,
                      "sampling_rate_hz": None, "instance": None, "mag_instance": None, **(read_with or {}),
                      "sign": log.sign},
        "quantization_step": quantization_step(log.acc) if log.units.get("acc") == "m/s^2" and log.acc is not None else None,
        "segments": segments,
        "overview": overview(log),
    }
    if log.flight is not None:  # a flight controller's log: every instance, and those read
        body["flight"] = log.flight.to_dict()
        body["temperature_c"] = temperature_range(log.temperature_c)
    if log.parts:
        body["parts"] = [{"index": i, "filename": p.filename, "start": p.start, "end": p.end,
                          "n_samples": p.n_samples, "sampling_rate_hz": p.sampling_rate_hz,
                          "pose_from_name": pose_from_name(p.filename)} for i, p in enumerate(log.parts)]
    return body


def temperature_range(temperature) -> dict | None:
    """The smallest and largest of a log's sensor temperature (°C), or None without one."""
    if temperature is None:
        return None
    finite = np.asarray(temperature, dtype=float)
    finite = finite[np.isfinite(finite)]
    return {"min": float(finite.min()), "max": float(finite.max())} if finite.size else None


def _short_still_file(acc, part, gravity: float | None, everything) -> tuple[list[dict], str] | None:
    """A pose file too short for a still segment (under MIN_DURATION_S) that is still all through: the
    whole file is its pose's reading, as the person who saved it meant (one file, one pose).

    Still means the spread (root of the summed per-axis variances) within CAP_G of gravity and a mean
    norm within NORM_RANGE_G, the bounds of the still-segment detector (docs/methods.md)."""
    from app.calibration.static import CAP_G, MIN_DURATION_S, NORM_RANGE_G

    rate = part.sampling_rate_hz or NOMINAL_RATE_HZ
    if part.n_samples < 2 or part.n_samples / rate >= MIN_DURATION_S:
        return None
    a = np.asarray(acc, dtype=float)
    g = gravity or float(np.median(np.linalg.norm(np.asarray(everything, dtype=float), axis=1)))
    mean, std = a.mean(axis=0), a.std(axis=0)
    spread = float(np.sqrt(np.sum(std ** 2)))
    norm = float(np.linalg.norm(mean))
    if not (np.all(np.isfinite(mean)) and spread <= CAP_G * g and NORM_RANGE_G[0] * g <= norm <= NORM_RANGE_G[1] * g):
        return None
    seg = {"start": 0, "end": part.n_samples, "acc_mean": mean.tolist(), "acc_std": std.tolist(),
           "up": nearest_orientation(mean), "count": part.n_samples}
    duration = part.n_samples / rate
    return [seg], (f"{part.filename}: {duration:.1f} s, shorter than the {MIN_DURATION_S:g} s a still segment needs, "
                   f"but still all through (spread {spread / g * 1000:.1f} mg): the whole file is its pose's reading")


NOMINAL_RATE_HZ = 100.0
"""The rate still segments are looked for at in a log that has none (no time column, none given): their
windows and least length are counted in samples as at 100 Hz; a note says so."""


def _still_between_gaps(acc, rate: float, gravity: float | None, cuts) -> list:
    """Still segments (app.calibration.static) of ``acc``, each stretch between the sample indices
    ``cuts`` (gaps of the time column) searched on its own, so that a segment's samples are contiguous
    in time; a stretch shorter than one window holds none."""
    bounds = [0, *cuts, len(acc)]
    out = []
    for a, b in zip(bounds[:-1], bounds[1:]):
        try:
            found = detect_static_segments(acc[a:b], rate, gravity=gravity)
        except InsufficientDataError:  # shorter than one window: no rest in it
            continue
        out += [dataclasses.replace(seg, start=seg.start + a, end=seg.end + a,
                                    gaps=tuple((p + a, q + a) for p, q in seg.gaps)) for seg in found]
    return out


def still_segments(log: LogData) -> tuple[list[dict], list[str]]:
    """A log's still segments in their plain form (docs/rest.md), and notes on a recording in parts.

    The segments are the accelerometer's (a log of other sensors alone has none), none spanning a gap
    of the time column. A recording made of several files (one per pose, :mod:`app.io.parts`) is
    searched file by file, so that no segment joins two files; each segment then names its file
    (``source``, ``part``), and a file whose name names a pose (``x_axis_pos``) that its still
    readings contradict gets a note.
    """
    if log.acc is None:
        return [], []
    unit = log.units.get("acc")
    gravity = {"m/s^2": STANDARD_GRAVITY, "g": 1.0}.get(unit)  # raw: estimated from the data
    rate = log.sampling_rate_hz or NOMINAL_RATE_HZ
    if not log.parts:
        found = _still_between_gaps(log.acc, rate, gravity, [g.index for g in log.gaps])
        return [dict(index=i, **seg.to_dict(), count=seg.count) for i, seg in enumerate(found)], []
    segments: list[dict] = []
    notes: list[str] = []
    for k, part in enumerate(log.parts):
        cuts = [g.index - part.start for g in log.gaps if part.start < g.index < part.end]
        found = [seg.to_dict() | {"count": seg.count} for seg in
                 _still_between_gaps(log.acc[part.start:part.end], part.sampling_rate_hz or rate, gravity, cuts)]
        named = pose_from_name(part.filename)
        if not found and (short := _short_still_file(log.acc[part.start:part.end], part, gravity, log.acc)):
            found, note = short
            notes.append(note)
        for plain in found:
            plain.update(start=plain["start"] + part.start, end=plain["end"] + part.start)
            segments.append(dict(index=len(segments), **plain, source=part.filename, part=k,
                                 **({"pose_from_name": named} if named else {})))
        if not found:
            notes.append(f"{part.filename}: no still stretch found in its {part.n_samples} samples, so it gives no "
                         "reading: record the board resting, untouched, for a few seconds in that pose")
        elif named:
            ups = [seg["up"] for seg in found]
            if any(up != named for up in ups):
                seen = ", ".join(sorted({up or "no axis within 20°" for up in ups if up != named}))
                notes.append(f"{part.filename}: its name says {named} up, but its still readings point {seen} "
                             f"up: the data's label is used — check the file's name, or how the board lay")
    return segments, notes


OVERVIEW_POINTS = 300
"""Bins of a log's overview: enough for a plot the width of a phone."""


def overview(log: LogData) -> dict:
    """The norm of the accelerometer (else the magnetometer, else the gyroscope) in at most
    :data:`OVERVIEW_POINTS` bins: the smallest and largest of each bin, so that a short move still shows,
    for the page's plot of the log. ``t_s`` is null in a log without a rate; ``start`` counts samples;
    ``temperature_c``, in a log that records the sensor's temperature, is each bin's mean temperature."""
    sensor = log.channels[0] if log.acc is None and log.mag is None else ("acc" if log.acc is not None else "mag")
    values = np.linalg.norm(np.asarray(getattr(log, sensor), dtype=float), axis=1)
    # At most one bin per sample, so that every bin holds at least one.
    edges = np.linspace(0, len(values), min(OVERVIEW_POINTS, len(values)) + 1).astype(int)
    finite = [b[np.isfinite(b)] for b in np.split(values, edges[1:-1])]
    rate = log.sampling_rate_hz
    plain = {"sensor": sensor, "unit": log.units.get(sensor),
             "t_s": None if rate is None else (edges[:-1] / rate).tolist(), "start": edges[:-1].tolist(),
             "low": [float(f.min()) if f.size else None for f in finite],
             "high": [float(f.max()) if f.size else None for f in finite]}
    if log.temperature_c is not None:  # the sensor's temperature over the same bins: the page's warm-up curve
        temps = [b[np.isfinite(b)] for b in np.split(np.asarray(log.temperature_c, dtype=float), edges[1:-1])]
        plain["temperature_c"] = [float(b.mean()) if b.size else None for b in temps]
    return plain


def readings_from_segments(recording: dict, method: str, indices: list[int] | None) -> tuple[list[Reading], list[int]]:
    """Readings from a recording's static segments, and the indices of the segments used.

    ``six_position`` takes the first segment of each orientation unless ``indices`` lists them;
    ``orientations`` takes every labelled segment (or the listed ones).
    """
    segments = require_segments(recording, method)
    if indices is not None:
        chosen = []
        for i in indices:
            if not 0 <= i < len(segments):
                raise CalibrationError(
                    f"segment {i} does not exist: the recording has {len(segments)} static segments (0–{len(segments) - 1})"
                )
            if segments[i]["up"] is None:
                raise CalibrationError(
                    f"segment {i} has no recognised orientation (no axis within 20° of its direction): "
                    "leave it out, or send its mean with an explicit `expected` vector"
                )
            chosen.append(i)
    elif method == "six_position":
        first: dict[str, int] = {}
        for i, seg in enumerate(segments):
            if seg["up"] is not None and seg["up"] not in first:
                first[seg["up"]] = i
        missing = [lab for lab in ("-x", "+x", "-y", "+y", "-z", "+z") if lab not in first]
        if missing:
            found = ", ".join(f"{lab} (segment {i})" for lab, i in first.items()) or "none"
            raise InsufficientDataError(
                f"the recording has no still segment with {', '.join(missing)} up; found {found}. "
                "Record the device resting a few seconds in each of the six orientations"
            )
        chosen = sorted(first.values())
    else:
        chosen = [i for i, seg in enumerate(segments) if seg["up"] is not None]
        if not chosen:
            raise InsufficientDataError(
                f"none of the recording's {len(segments)} still segments lies within 20° of an axis: method "
                "orientations needs poses with an axis up; use a magnitude method (triangular, nonorthogonal) "
                "for free poses")
    readings = [
        Reading(mean=tuple(segments[i]["acc_mean"]), up=segments[i]["up"], std=tuple(segments[i]["acc_std"]),
                count=segments[i].get("count"))
        for i in chosen
    ]
    return readings, chosen


def holdout_metrics(result, holdout) -> dict:
    """Norm errors of further still readings, prefixed ``holdout_`` (Georgieva et al. section 3.5, Farago et al. Table 3)."""
    if not holdout:
        return {}
    return {f"holdout_{k}": v for k, v in result.evaluate(holdout).items()}


def calibrate_known(method: str, readings: list[Reading], *, unit: str, gravity: float,
                    holdout=None):
    """Run ``six_position`` or ``orientations`` on readings, reviewed (app.calibration.trust); returns the
    result and the holdout's metrics."""
    means = [r.mean for r in readings]
    stds = None
    if readings and all(r.std is not None for r in readings):
        stds = [r.std for r in readings]
    raw = unit == "raw"
    # Raw readings: the reference stays in m/s² and X maps it to counts, so scale gates do not apply.
    gates = dict(plausible_scale=None, max_offset=math.inf) if raw else {}
    if method == "six_position":
        if any(r.up is None for r in readings):
            raise CalibrationError("six_position readings each need an `up` label (+x, -x, +y, -y, +z, -z)")
        result = fit_six_position(means, [r.up for r in readings], gravity=gravity, stds=stds, **gates)
        cv = {"cv_error_mg": None, "cv_error_max_mg": None, "cv_note": SIX_POSITION_NOTE}
    elif method == "orientations":
        def fit(idx):
            return fit_orientations(
                [means[i] for i in idx], [readings[i].up for i in idx], expected=[readings[i].expected for i in idx],
                gravity=gravity, stds=None if stds is None else [stds[i] for i in idx], **gates,
            )

        result = fit(range(len(readings)))
        cv = cross_validated_error(fit, means, gravity)
    else:  # pragma: no cover - the schemas only route these two here
        raise CalibrationError(f"unknown known-orientation method {method!r}")
    result = review(result, cv, raw_unit=raw)
    return result, holdout_metrics(result, holdout)


def require_segments(recording: dict, method: str) -> list[dict]:
    """A recording's still segments, or a refusal saying what to record and what to check: a method of
    still poses has nothing to fit without them (the unit first: readings in a unit other than the one
    read find no rest near the expected gravity)."""
    segments = recording["segments"]
    if not segments:
        unit = (recording.get("units") or {}).get("acc")
        raise InsufficientDataError(
            f"the recording has no still segments ({recording['n_samples']} samples, its accelerometer read in "
            f"{unit}; a rest lasts at least 1.5 s with the accelerometer reading about 1 g): method {method} needs "
            "the device resting still in several orientations — record it a few seconds in each; if it did rest, "
            "check the accelerometer's unit (acc_unit, or chip / lsb_per_g for counts)")
    return segments


def means_from_segments(recording: dict, indices: list[int] | None, method: str = "the method") -> tuple[list, list[int]]:
    """Means of a recording's static segments (all, or the listed ones), orientation unknown."""
    segments = require_segments(recording, method)
    chosen = list(range(len(segments))) if indices is None else list(indices)
    for i in chosen:
        if not 0 <= i < len(segments):
            raise CalibrationError(
                f"segment {i} does not exist: the recording has {len(segments)} static segments"
            )
    return [segments[i]["acc_mean"] for i in chosen], chosen


def calibrate_unknown(method: str, means, *, unit: str, gravity: float, solver: str = "lm", holdout=None):
    """Run ``nonorthogonal`` (Georgieva et al. Approach 1) or ``triangular`` (Farago et al.) on still readings,
    reviewed with their cross-validated error (app.calibration.trust); the extra metrics are the holdout's."""
    # Imported here, not at the top: the models need scipy.optimize, which the CLI's autocal
    # imports on the other core while detection runs (tests/test_cli_autocal.py).
    from app.calibration.nonorthogonal import fit_nonorthogonal
    from app.calibration.triangular import fit_triangular

    m = as_vectors(means, "means")
    gates = dict(plausible_scale=None, max_offset=math.inf) if unit == "raw" else {}
    if method == "nonorthogonal":
        def fit(idx):
            return fit_nonorthogonal(m[idx], gravity=gravity, **gates)
    elif method == "triangular":
        def fit(idx):
            return fit_triangular(m[idx], gravity=gravity, solver=solver, **gates)
    else:  # pragma: no cover - the schemas only route these two here
        raise CalibrationError(f"unknown magnitude method {method!r}")
    result = review(fit(np.arange(len(m))), cross_validated_error(fit, m, gravity), raw_unit=unit == "raw")
    return result, holdout_metrics(result, holdout)


def pose_advice(result) -> list[dict]:
    """The next poses a magnitude model's fit is advised (app.calibration.advice, D-optimal), plain."""
    from app.calibration.advice import next_poses

    return [a.to_dict() for a in next_poses(result)]


GYR_TO_RAD_S = {"rad/s": 1.0, "deg/s": math.pi / 180.0, "raw": 1.0}
MAG_TO_UT = {"uT": 1.0, "nT": 1e-3, "raw": 1.0}


def calibrate_cube_log(log: LogData, *, protocol, gravity: float, field_ut: float | None, sections=None):
    """Särkkä et al.'s multi-position calibration of a recording's acc, gyr and optional mag.

    Gyroscope samples in deg/s are converted to rad/s and magnetometer samples in nT to µT first, so
    that the gyroscope model maps rad/s (and the magnetometer µT) to the recorded values.
    """
    from app.calibration.cube import calibrate_cube  # scipy.stats: see calibrate_unknown

    if log.gyr is None:
        raise CalibrationError(
            f"the recording has no gyroscope columns (found {', '.join(log.columns)}): the cube method needs "
            "gyr_x, gyr_y, gyr_z beside the accelerometer"
        )
    rate = require_rate(log.sampling_rate_hz, "cube")
    gyr = log.gyr * GYR_TO_RAD_S[log.units["gyr"]]
    mag = None if log.mag is None else log.mag * MAG_TO_UT[log.units["mag"]]
    if mag is not None and field_ut is None:
        raise CalibrationError("the recording has a magnetometer: give field_ut, the local field magnitude in µT")
    return calibrate_cube(log.acc, gyr, mag, sampling_rate_hz=rate, protocol=protocol,
                          gravity=gravity, field_ut=field_ut, sections=sections)


def apply_calibration(body: dict, samples, sensor: str = "acc"):
    """Calibrate samples of one sensor with a stored calibration: the result it rebuilds applies its
    correction of that sensor, or says which sensors it has (a noise characterisation corrects nothing)."""
    from app.calibration.registry import result_from_dict  # the registry imports every model

    return result_from_dict(body).apply(samples, sensor)


def calibration_body(result, extra_metrics: dict, *, unit: str, notes: list[str], **fields) -> dict:
    """The stored and returned form of a calibration: the result's plain form with the metrics and
    notes of the request and the caller's fields (device_id, label, the recording's id…); its headline
    and verdict come from the result the body rebuilds, which sees the request's metrics too."""
    if result.unit != unit:  # the core fits numbers; the caller knows their unit (the cube's is in its units)
        result = dataclasses.replace(result, unit=unit)
    body = result.to_dict()
    body["metrics"].update(extra_metrics)
    stored = type(result).from_dict(body)
    line = stored.headline()  # the line a person reads first
    if line is not None:
        body["headline"] = line
    body["warnings"] = list(body["warnings"]) + notes
    body.update(fields)
    body["verdict"] = verdict(body, stored)
    return body


# -- the one entry point -------------------------------------------------------------------------


@dataclass(frozen=True)
class RecordingSource:
    """A recording a request calibrates from.

    Attributes
    ----------
    meta : dict
        Its description (:func:`describe_log`, as stored by POST /api/v1/recordings).
    path : pathlib.Path
        Its file.
    id : str or None
        Its id when stored (the CLI calibrates files that are not): copied into the result.
    log : LogData or None
        The file already read, when the caller has it.
    """

    meta: dict
    path: Path
    id: str | None = None
    log: LogData | None = None

    def read(self, clock: str | None = None) -> LogData:
        """The recording's samples as stored; ``clock="mag"`` reads a flight controller's log on its compass's
        clock (app.io.formats.flight_log), which the compass methods ask for (other logs are read as stored)."""
        flight = self.meta.get("flight")
        if clock is not None and (flight is None or flight.get("clock", "imu") == clock):
            clock = None
        if self.log is not None and (clock is None or (self.log.flight and self.log.flight.clock == clock)):
            return self.log
        # As it was read when stored; bodies stored before read_with give only their units.
        read_with = dict(self.meta.get("read_with") or {"units": self.meta["units"]})
        if clock is not None:
            read_with["clock"] = clock
        # The caller's rate as given at the upload, so that the time column is judged again the same
        # way (its gaps); recordings stored before read_with kept it are read at their stored rate.
        rate = read_with.pop("sampling_rate_hz") if "sampling_rate_hz" in read_with else self.meta["sampling_rate_hz"]
        return load_log(self.path, sampling_rate_hz=rate, name=self.meta.get("filename") or "the recording",
                        **read_with)

    @property
    def source_fields(self) -> dict:
        return {} if self.id is None else {"recording_id": self.id}


def calibrate(request, recording: RecordingSource | None = None) -> dict:
    """Compute the calibration a request asks for, and return its stored form (unstored).

    Parameters
    ----------
    request : app.requests.CalibrationIn
        One of the request models; its ``method`` picks the method.
    recording : RecordingSource, optional
        The recording ``request.recording_id`` names, found by the caller (the API in the store
        of the calling owner, the CLI on disk).

    Returns
    -------
    dict
        The calibration's plain form with ``device_id``, ``label`` and the recording's fields.

    Raises
    ------
    CalibrationError
        Input that cannot be calibrated (InsufficientDataError: too little of it).
    LogFormatError
        A recording that cannot be read.
    """
    if getattr(request, "recording_id", None) is not None and recording is None:
        raise CalibrationError(f"recording {request.recording_id!r} was not given to the workflow")
    body = _METHODS[request.method](request, recording)
    if recording is not None:  # what the reader decided against the header or the caller (units) comes first
        said = [w for w in recording.meta.get("warnings") or [] if w not in body["warnings"]]
        body["warnings"] = said + list(body["warnings"])
    return body


def require_rate(rate: float | None, method: str) -> float:
    """The recording's sampling rate, or a refusal naming what to give: methods over time need one."""
    if rate is None:
        raise CalibrationError(
            f"method {method} needs the sensor's sampling rate, and this recording has none (no time column, and "
            "no sampling_rate_hz was given): upload it again with sampling_rate_hz (--sampling-rate-hz), the "
            "sensor's output data rate, or log a time column")
    return rate


def require_accelerometer(channels, method: str) -> None:
    """Refuse a recording without accelerometer columns for an accelerometer method, naming the fix."""
    if "acc" not in channels:
        other = {"mag": "method magnetometer calibrates a magnetometer turned through all directions",
                 "gyr": "method noise characterises a still gyroscope"}
        raise CalibrationError(
            f"the recording has no accelerometer columns (it has {', '.join(channels)}): method {method} needs "
            "acc_x, acc_y, acc_z — record the accelerometer too; "
            + "; ".join(other[c] for c in channels if c in other))


def _unit_gravity(request, recording: RecordingSource | None) -> tuple[str, float, list[str]]:
    """The unit, the reference magnitude and notes for a request on inline readings or a recording."""
    unit = request.unit
    notes: list[str] = []
    if recording is not None:
        meta = recording.meta
        require_accelerometer(meta["units"], request.method)
        if request.unit != meta["units"]["acc"]:
            notes.append(
                f"the recording's accelerometer unit is {meta['units']['acc']}; the request's unit "
                f"{request.unit} was replaced by it"
            )
        unit = meta["units"]["acc"]
        if meta.get("quantization_step"):
            notes.append(
                f"the recording's values are rounded to {meta['quantization_step']} m/s² (as browsers "
                "round motion sensor data): each reading's mean is still precise when averaged over many samples"
            )
    else:
        unit = inline_unit(request, notes)
    gravity, more = reference_gravity(unit, request.gravity, request.latitude_deg, request.height_m)
    return unit, gravity, notes + more


def inline_unit(request, notes: list[str]) -> str:
    """The unit of a request's inline readings, checked against their magnitude as an upload's is
    (app.io.formats.units): readings resting at about 1 are in g, at about 9.8 in m/s²; where the
    request's unit (given, or the default) says otherwise the data win, and a note says both."""
    from app.io.formats.units import infer_acc_unit

    unit = request.unit
    means = [r.mean for r in request.readings] if getattr(request, "readings", None) else getattr(request, "means", None)
    if unit not in ("g", "m/s^2") or not means:
        return unit
    inferred = infer_acc_unit(np.asarray(means, dtype=float))
    if inferred in ("g", "m/s^2") and inferred != unit:
        norm = float(np.median(np.linalg.norm(np.asarray(means, dtype=float), axis=1)))
        said = "the request's unit said" if "unit" in request.model_fields_set else "the request gave no unit, so"
        notes.append(f"{said} {unit}, but its readings' median norm is {norm:.3g}, about 1 g in {inferred}: "
                     f"calibrated in {inferred}")
        return inferred
    return unit


def _known(request, recording: RecordingSource | None) -> dict:
    unit, gravity, notes = _unit_gravity(request, recording)
    source: dict = {}
    if recording is not None:
        try:
            readings, used = readings_from_segments(recording.meta, request.method, request.segments)
        except InsufficientDataError as exc:
            hint = missing_named_poses(recording.meta)
            if not hint:
                raise
            raise InsufficientDataError(f"{str(exc).rstrip('.')}. {hint}") from None
        source = {**recording.source_fields, "segments_used": used}
    else:
        readings = [Reading(mean=tuple(r.mean), up=r.up, expected=None if r.expected is None else tuple(r.expected),
                            std=None if r.std is None else tuple(r.std), count=r.count)
                    for r in request.readings]
    result, extra = calibrate_known(request.method, readings, unit=unit, gravity=gravity, holdout=request.holdout)
    return name_sources(calibration_body(result, extra, unit=unit, notes=notes, device_id=request.device_id,
                                         label=request.label, **source), recording)


def _means_and_source(request, recording: RecordingSource | None) -> tuple[list, dict]:
    """The still readings of a request on means: inline, or the recording's segments (and their fields)."""
    if recording is None:
        return request.means, {}
    means, used = means_from_segments(recording.meta, request.segments, request.method)
    return means, {**recording.source_fields, "segments_used": used}


def missing_named_poses(meta: dict) -> str:
    """On a recording of pose files, the poses their names promise that no still reading shows, and the
    files whose readings point elsewhere ("" when the names and the data agree, or name no pose)."""
    parts = meta.get("parts") or []
    named = {p["pose_from_name"] for p in parts if p.get("pose_from_name")}
    seen = {seg["up"] for seg in meta.get("segments") or []}
    missing = sorted(named - seen)
    if not missing:
        return ""
    wrong = sorted({f"{seg['source']} holds {seg['up'] or 'no axis'} up" for seg in meta["segments"]
                    if seg.get("pose_from_name") in missing and seg["up"] != seg["pose_from_name"]})
    return (f"The files' names promise {', '.join(missing)} up, but no still reading shows it"
            + (f" ({'; '.join(wrong)})" if wrong else "")
            + ": record that pose again, or check which file holds which pose")


def name_sources(body: dict, recording: RecordingSource | None) -> dict:
    """On a recording made of several files (one per pose), each reading of the calibration names its
    file (``source``), and a warning names each file whose name gives a pose its reading contradicts."""
    if recording is None or not recording.meta.get("parts"):
        return body
    segments = recording.meta["segments"]
    for reading, i in zip(body.get("readings") or [], body.get("segments_used") or []):
        seg = segments[i]
        reading["source"] = seg.get("source")
        named = seg.get("pose_from_name")
        if named and seg["up"] != named:
            body["warnings"].append(
                f"{seg.get('source')} names {named} up, but its still reading points "
                f"{seg['up'] or 'to no axis within 20°'}{' up' if seg['up'] else ''}: the data's pose was used — check "
                "the file's name, or how the board lay")
    return body


def _magnitude(request, recording: RecordingSource | None) -> dict:
    unit, gravity, notes = _unit_gravity(request, recording)
    means, source = _means_and_source(request, recording)
    result, extra = calibrate_unknown(request.method, means, unit=unit, gravity=gravity,
                                      solver=getattr(request, "solver", "lm"), holdout=request.holdout)
    return name_sources(calibration_body(result, extra, unit=unit, notes=notes, device_id=request.device_id,
                                         label=request.label, advice=pose_advice(result), **source), recording)


def choose_model(means, *, unit: str, gravity: float, solver: str = "lm", holdout=None) -> tuple:
    """The ``auto`` method: the model these still readings support, fitted, and why it was chosen.

    Readings each within 20° of an axis, covering all six, are known orientations: ``six_position``
    for exactly six, else ``orientations`` (Georgieva et al., ESGI'95, section 3.3). Nine or more
    readings also support the magnitude model ``triangular`` (Farago et al.). Where both apply,
    a calibration that passes its gates beats one that does not, then the lower error on readings
    left out of the fit wins (a tilted "axis" pose shows there).

    Returns
    -------
    result, extra, choice
        The chosen fit, its extra metrics, and ``{"method", "why", "candidates"}``.

    Raises
    ------
    InsufficientDataError
        Fewer than 9 readings that are not six axis-aligned ones.
    """
    m = as_vectors(means, "means")
    labels = [nearest_orientation(v) for v in m]
    aligned = None not in labels and set(labels) == set(CANONICAL_SIX)
    candidates = {}
    if aligned:
        known = "six_position" if len(m) == 6 else "orientations"
        readings = [Reading(mean=tuple(v), up=lab) for v, lab in zip(m, labels)]
        candidates[known] = calibrate_known(known, readings, unit=unit, gravity=gravity, holdout=holdout)
    if len(m) >= 9:
        try:
            candidates["triangular"] = calibrate_unknown("triangular", m, unit=unit, gravity=gravity, solver=solver,
                                                         holdout=holdout)
        except InsufficientDataError:
            if not candidates:  # nothing else applies: say what the magnitude model lacks
                raise
    if not candidates:
        raise InsufficientDataError(
            f"{len(m)} still readings are not the six axis-aligned poses (each within 20° of one of ±x, ±y, ±z) "
            f"and a magnitude model needs at least 9 free poses (12 or more recommended): add "
            f"{9 - len(m)} or more poses in other directions"
        )

    def rank(name):
        result = candidates[name][0]
        cv = result.metrics.get("cv_error_mg")
        return (not result.ok, math.inf if cv is None else cv)

    chosen = min(candidates, key=rank)
    summary = {name: {"ok": r.ok, "cv_error_mg": r.metrics.get("cv_error_mg")} for name, (r, _) in candidates.items()}
    why = _why(chosen, summary, aligned, len(m))
    result, extra = candidates[chosen]
    return result, extra, {"method": chosen, "why": why, "candidates": summary}


def _why(chosen: str, summary: dict, aligned: bool, n: int) -> str:
    if not aligned:
        return (f"the {n} poses are free (not all within 20° of an axis, or not all six axes): the magnitude model "
                "triangular (Farago et al.) needs no orientation")
    if len(summary) == 1:
        return (f"the {n} poses are the six axis orientations (each within 20° of ±x, ±y, ±z): {chosen} "
                "(Georgieva et al.); nine or more distinct poses would also allow a magnitude model to check it")

    def figure(name):
        cv = summary[name]["cv_error_mg"]
        return f"{name} {'n/a' if cv is None else f'{cv:.2f} mg'}{'' if summary[name]['ok'] else ' (not ok)'}"

    return (f"the {n} poses cover the six axes, so both a known-orientation and a magnitude model apply; "
            f"on poses left out: {', '.join(figure(k) for k in summary)}; {chosen} was chosen")


def _auto(request, recording: RecordingSource | None) -> dict:
    if recording is not None and "acc" not in recording.meta["units"] and "mag" in recording.meta["units"]:
        return _auto_compass(request, recording)
    unit, gravity, notes = _unit_gravity(request, recording)
    means, source = _means_and_source(request, recording)
    try:
        result, extra, choice = choose_model(means, unit=unit, gravity=gravity, holdout=request.holdout)
    except InsufficientDataError as exc:
        hint = missing_named_poses(recording.meta) if recording is not None else ""
        if not hint:
            raise
        raise InsufficientDataError(f"{str(exc).rstrip('.')}. {hint}") from None
    if choice["method"] == "triangular":  # a magnitude model: which poses to add next
        source["advice"] = pose_advice(result)
    return name_sources(calibration_body(result, extra, unit=unit, notes=notes, device_id=request.device_id,
                                         label=request.label, choice=choice, **source), recording)


def _cube(request, recording: RecordingSource) -> dict:
    if recording.meta.get("parts"):
        raise CalibrationError(
            f"the cube method follows the turns between its positions in one recording; this one is made of "
            f"{len(recording.meta['parts'])} files (one per pose), which hold no turns: calibrate the accelerometer "
            "from them with method six_position or orientations, or record the cube session in one file")
    log = recording.read()
    require_accelerometer(log.channels, "cube")
    unit = log.units["acc"]
    gravity, notes = reference_gravity(unit, request.gravity, request.latitude_deg, request.height_m)
    sections = None if request.sections is None else {k: v.model_dump() for k, v in request.sections.items()}
    result = calibrate_cube_log(log, protocol=request.protocol, gravity=gravity, field_ut=request.field_ut,
                                sections=sections)
    result = dataclasses.replace(result, units=dict(log.units))
    return calibration_body(result, {}, unit=unit, notes=notes, device_id=request.device_id,
                            label=request.label, **recording.source_fields)


def _autocal(request, recording: RecordingSource) -> dict:
    require_accelerometer(recording.meta["units"], "autocal")
    # Read as the upload was (its chip or sensitivity turns counts into g), or as the stored units say.
    read_with = recording.meta.get("read_with") or {"units": recording.meta["units"]}
    return autocalibrate_file(
        recording.path, sampling_rate_hz=recording.meta["sampling_rate_hz"],
        unit=request.unit or (read_with.get("units") or {}).get("acc"), chip=read_with.get("chip"),
        instance=read_with.get("instance"),
        lsb_per_g=read_with.get("lsb_per_g"), solver=request.solver, gravity=request.gravity,
        latitude_deg=request.latitude_deg, height_m=request.height_m,
        detection={"all_axes": True} if request.all_axes else None, device_id=request.device_id,
        label=request.label or recording.meta.get("filename"), **recording.source_fields)


AUTOCAL_UNITS = ("g", "m/s^2")


def autocalibrate_file(path, *, sampling_rate_hz: float | None = None, unit: str | None = None, progress=None,
                       solver: str = "lm", gravity: float | None = None, latitude_deg: float | None = None,
                       height_m: float | None = None, detection: dict | None = None, selection: dict | None = None,
                       columns: str | None = None, sign: int | None = None, chip: str | None = None,
                       lsb_per_g: float | None = None, instance: int | None = None, **fields) -> dict:
    """Auto-calibrate a long recording by the pipeline of Farago et al. and return the calibration body.

    Parameters
    ----------
    path : str or pathlib.Path
        ``.npy`` (N×3, or N×4 with time first; memory-mapped), Parquet or CSV.
    sampling_rate_hz : float, optional
        Needed when the file has no time column.
    unit : {"g", "m/s^2"}, optional
        The accelerometer unit; the file's (header) unit, else m/s², when omitted.
    progress : callable, optional
        ``progress(done_samples, total_samples)``.
    solver : str
        Solver of the 9-parameter fit (``lm``, ``gradient``, ``fixed16``, ``fixed32``).
    gravity, latitude_deg, height_m : float, optional
        Reference gravity for m/s² input (see :func:`reference_gravity`).
    detection, selection : dict, optional
        Options of :class:`app.calibration.stationary_002.RestAccumulator` and
        :func:`app.calibration.autocal.autocalibrate`.
    columns : str, optional
        The columns of a CSV (:func:`app.io.formats.parse_columns`).
    sign : {1, -1}, optional
        Factor on the file's accelerations; detected from the header when None.
    chip, lsb_per_g : str or float, optional
        The accelerometer's part and range, or its counts per g, for a CSV in counts
        (:func:`app.io.formats.read_log`).
    instance : int, optional
        The IMU instance of a flight controller's log (PX4 ULog, ArduPilot DataFlash).
    **fields
        Added to the body (``device_id``, ``label``...).

    Returns
    -------
    dict
        The body of :func:`calibration_body`: ``method: "autocal"``, ``model`` (triangular K, o),
        ``metrics`` (``error_before_mg``, ``error_after_mg``, ``improvement_pct`` on the control set),
        ``comparison``, ``selection``, ``detection``, ``ok``, ``warnings``, ``reasons``.
    """
    import importlib
    import sys
    import threading

    from app.calibration.stationary_002 import detect_rest_segments

    # The fit needs scipy.optimize (~0.5 s to import): import it on the other core while this one
    # reads the recording (numpy releases the GIL in its loops).
    preload = None
    if "app.calibration.autocal" not in sys.modules:
        preload = threading.Thread(
            target=lambda: [importlib.import_module(m) for m in ("app.calibration.autocal", "scipy.special")],
            daemon=True)
        preload.start()
    path = Path(path)
    log = load_log(path, sampling_rate_hz=sampling_rate_hz, units={"acc": unit} if unit else {}, name=str(path),
                   columns=columns, sign=sign, chip=chip, lsb_per_g=lsb_per_g, instance=instance)
    require_accelerometer(log.channels, "autocal")
    unit = log.units["acc"]
    if unit not in AUTOCAL_UNITS:
        raise CalibrationError(
            f"auto-calibration needs samples in g or m/s^2 (its thresholds are fractions of g); {path.name} is in "
            f"counts whose scale is unknown: give chip (--chip, e.g. mpu6050-2g) for a CSV, or convert the counts "
            f"to g first"
        )
    g, notes = reference_gravity(unit, gravity, latitude_deg, height_m)
    rest = detect_rest_segments(log.acc, require_rate(log.sampling_rate_hz, "autocal"), gravity=g, progress=progress,
                                **(detection or {}))
    if preload is not None:
        preload.join()
    from app.calibration.autocal import autocalibrate

    result = autocalibrate(rest, solver=solver, **(selection or {}))
    fields.setdefault("label", path.name)
    return calibration_body(result, {}, unit=unit, notes=notes, recording={
        "format": log.format, "n_samples": log.n_samples, "sampling_rate_hz": log.sampling_rate_hz,
        "duration_s": log.n_samples / log.sampling_rate_hz}, **fields)


# -- noise: the Allan deviation of a still recording -----------------------------------------------

NOISE_SENSORS = ("acc", "gyr", "mag")
NOISE_REST_S = 5.0
"""A still stretch this long counts as a rest: two or more of them are separate rests (poses, handling),
and only the longest is characterised."""
NOISE_GAPS_MAX = 0.01
"""Gaps losing more than this fraction of the still part's time make its Allan deviation unreliable
(``ok`` false): the estimator takes the samples as evenly spaced, and a lost stretch joins two
stretches as if they were adjacent."""
ACC_TO_M_S2 = {"m/s^2": 1.0, "g": STANDARD_GRAVITY, "raw": 1.0}


def characterise_log(log: LogData, *, sensors=None, array_sensor: str | None = None, **fields) -> dict:
    """Noise characterisation (app.calibration.noise) of every chosen sensor of a still recording.

    ``array_sensor`` names the sensor a three-column array (``.npy``, Parquet) holds, which the readers
    return as ``acc``. Gyroscopes in deg/s become rad/s, magnetometers in nT µT, accelerometers in g
    m/s² (Kalibr's units). The still part is the longest still stretch: when some of the recording
    moved, a warning says what was used; when less than half of it is still, ``ok`` is false.
    """
    from app.calibration.noise import NoiseResult, characterise_noise
    from app.calibration.noise_still import MIN_STILL_FRACTION, still_runs

    arrays = {name: getattr(log, name) for name in log.channels}
    units = dict(log.units)
    if array_sensor not in (None, "acc"):
        if log.channels != ["acc"]:
            raise CalibrationError(f"the sensor of an array is given for files with one sensor; this one has "
                                   f"{', '.join(log.channels)}: leave it out")
        arrays = {array_sensor: log.acc}
        units = {array_sensor: {"gyr": "rad/s", "mag": "uT"}[array_sensor]}
    wanted = list(sensors) if sensors else [s for s in NOISE_SENSORS if s in arrays]
    missing = [s for s in wanted if s not in arrays]
    if missing:
        raise CalibrationError(f"the recording has no {', '.join(missing)} samples (it has {', '.join(arrays)}): "
                               "ask for those it has")
    factor = {"acc": ACC_TO_M_S2, "gyr": GYR_TO_RAD_S, "mag": MAG_TO_UT}
    si = {"acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}
    fs, n = require_rate(log.sampling_rate_hz, "noise"), len(next(iter(arrays.values())))
    notes: list[str] = list(log.warnings) + list(log.notes)
    detected_from = "acc" if "acc" in arrays else wanted[0]
    runs = still_runs(arrays[detected_from], fs)
    span = max(runs, key=lambda r: r[1] - r[0]) if runs else None
    rests = [r for r in runs if r[1] - r[0] >= NOISE_REST_S * fs]
    reasons: list[str] = []
    if span is not None and len(rests) >= 2:
        a, b = span
        said = (f"the device moved: the recording holds {len(rests)} rests separated by moves (the poses of a "
                f"calibration, or handling): only the longest, {a / fs:.1f}–{b / fs:.1f} s ({100 * (b - a) / n:.0f} % of the "
                "recording), was characterised — no term is fitted across a move")
        if b - a < MIN_STILL_FRACTION * n:
            reasons.append(said + "; for the noise, record the device resting in one orientation, untouched, for "
                                  "the whole recording")
        else:
            notes.append(said)
    elif span is None or (span[1] - span[0]) < MIN_STILL_FRACTION * n:
        still_s = 0.0 if span is None else (span[1] - span[0]) / fs
        reasons.append(f"the device moved: the longest still stretch is {still_s:.1f} s of {n / fs:.1f} s; the noise "
                       "is characterised on a still recording — leave the device resting on a firm surface, "
                       "untouched, for the whole recording")
        span = span or (0, n)
    elif n - (span[1] - span[0]) > max(2.0 * fs, 0.01 * n):
        notes.append(f"the device moved: only the longest still stretch, {span[0] / fs:.1f}–{span[1] / fs:.1f} s "
                     f"({100 * (span[1] - span[0]) / n:.0f} % of the recording), was used")
    inside = [g for g in log.gaps if span[0] < g.index < span[1]]
    if inside:
        lost = sum(g.missing_s for g in inside)
        still_s = (span[1] - span[0]) / fs
        said = (f"the timing: {len(inside)} gap{'s' if len(inside) > 1 else ''} in the time column lose "
                f"{lost:.3g} s of the {still_s:.1f} s still part ({100 * lost / (still_s + lost):.2g} %)")
        if lost > NOISE_GAPS_MAX * still_s:
            reasons.append(said + ": the Allan deviation assumes samples evenly spaced in time, so this curve is not "
                                  "the sensor's — record again without losing samples (a faster serial baud rate, "
                                  "fewer columns printed, a larger host buffer)")
        else:
            notes.append(said + ": few enough for the Allan deviation")
    a, b = span
    parts = {}
    for name in wanted:
        unit = units[name]
        samples = arrays[name][a:b]
        scale = factor[name].get(unit, 1.0)
        if scale != 1.0:
            samples = np.asarray(samples, dtype=float) * scale
            unit = si[name]
        part = characterise_noise(samples, fs, unit=unit, sensor=name)
        notes.extend(part.pop("warnings"))
        parts[name] = part
    duration = (b - a) / fs
    result = NoiseResult(sensors={k: {x: p[x] for x in ("model", "adev", "uncertainty", "metrics")}
                                  for k, p in parts.items()},
                         sampling_rate_hz=fs, duration_s=duration,
                         still={"start": a, "end": b, "n_samples": b - a, "fraction": (b - a) / n,
                                "detected_from": detected_from},
                         reasons=tuple(reasons), unit=parts[wanted[0]]["model"]["unit"])
    return calibration_body(result, {}, unit=result.unit, notes=notes, **fields)


def _noise(request, recording: RecordingSource) -> dict:
    clock = None
    if recording.meta.get("flight") is not None and request.sensors and "mag" in request.sensors:
        if list(request.sensors) != ["mag"]:
            raise CalibrationError("a flight controller's compass is read on its own clock, slower than the IMU's: "
                                   "ask for sensors [\"mag\"] alone, and for the IMU's (acc, gyr) in another request")
        clock = "mag"
    log, notes = recording.read(clock=clock), []
    if log.parts:  # one file per pose: the noise of one file, never across two
        log, notes = one_still_file(log)
    body = characterise_log(log, sensors=request.sensors, array_sensor=request.sensor, device_id=request.device_id,
                            label=request.label or recording.meta.get("filename"), **recording.source_fields)
    body["warnings"] = notes + body["warnings"]
    return body


def one_still_file(log: LogData) -> tuple[LogData, list[str]]:
    """The file of a recording in parts with the longest still stretch, as a log of its own, and a note
    naming it: the Allan deviation of a sequence joined from several files would see their seams."""
    from app.calibration.noise_still import longest_still
    from app.io.parts import part_log

    def still_samples(i):
        one = part_log(log, i)
        span = longest_still(getattr(one, one.channels[0]), one.sampling_rate_hz)
        return 0 if span is None else span[1] - span[0]

    lengths = [still_samples(i) for i in range(len(log.parts))]
    best = int(np.argmax(lengths))
    note = (f"the recording is made of {len(log.parts)} files: the noise is characterised on one, "
            f"{log.parts[best].filename} (the longest still stretch), not across files")
    return part_log(log, best), [note]


# -- the compass: a magnetometer turned through all directions --------------------------------------


def magnetometer_reference(request, notes: list[str]) -> tuple[dict, dict]:
    """The field the calibration is referenced to: ``field_ut`` given, else the geomagnetic model's at
    the place and day, else none (estimated by the fit); with a place, the model's dip and
    declination too. Returns the keyword arguments of :func:`~app.calibration.magnetometer.fit_magnetometer`
    and the metrics naming the model and its day (none without a place)."""
    reference: dict = {"field_ut": request.field_ut, "field_source": "given" if request.field_ut else None}
    if request.latitude_deg is None:
        if request.date is not None or request.height_m is not None:
            notes.append("date and height_m without latitude_deg and longitude_deg are not used: give the place too "
                         "for the Earth's field there")
        return reference, {}
    from app.geomag import GeomagneticRangeError, reference_field  # the model's package loads only here

    day = request.date or datetime.datetime.now(datetime.timezone.utc).date()
    try:
        earth = reference_field(day, request.latitude_deg, request.longitude_deg,
                                0.0 if request.height_m is None else request.height_m)
    except GeomagneticRangeError as exc:
        raise CalibrationError(str(exc)) from None
    reference.update(inclination_deg=earth.inclination_deg, declination_deg=earth.declination_deg)
    if request.field_ut is None:
        reference.update(field_ut=earth.field_ut, field_source="model")
    elif abs(request.field_ut / earth.field_ut - 1.0) > 0.1:
        notes.append(f"field_ut {request.field_ut:g} µT is more than 10 % from the {earth.model} field here "
                     f"({earth.field_ut:.1f} µT): the given value is used")
    return reference, {"field_model": earth.model, "field_date": day.isoformat()}


def compass_rests(log: LogData, segments: list[dict]) -> list[tuple]:
    """The accelerometer's still segments of a recording with their mean magnetometer reading."""
    if log.mag is None or log.acc is None:
        return []
    mag = log.mag * MAG_TO_UT[log.units["mag"]]
    return [(seg["acc_mean"], mag[seg["start"]:seg["end"]].mean(axis=0)) for seg in segments
            if seg["end"] > seg["start"]]


def _magnetometer(request, recording: RecordingSource | None) -> dict:
    from app.calibration.magnetometer import fit_magnetometer  # scipy.optimize: see calibrate_unknown

    notes: list[str] = []
    rests: list = []
    unit = "uT"
    if recording is None:
        mag = np.asarray(request.mag, dtype=float)
        source = {}
    else:
        log = recording.read(clock="mag")  # a flight controller's compass on its own clock
        if log.mag is None:
            raise CalibrationError(
                f"the recording has no magnetometer columns (it has {', '.join(log.channels)}): the magnetometer "
                "method needs mag_x, mag_y, mag_z — record the magnetometer (uncalibrated) while turning the device")
        unit = log.units["mag"]
        mag = log.mag * MAG_TO_UT.get(unit, 1.0)
        unit = "raw" if unit == "raw" else "uT"
        # The stored segments are on the IMU's clock in a flight log: its compass's rests are found on its own.
        segments = still_segments(log)[0] if log.flight is not None else recording.meta.get("segments") or []
        rests = compass_rests(log, segments)
        source = recording.source_fields
    reference, extra = magnetometer_reference(request, notes)
    counts = unit == "raw" and reference["field_ut"] is None
    if counts:
        notes.append("the magnetometer's readings are counts and no field was given: M maps them to the "
                     "readings' own scale, not to µT, and every figure is in counts — give chip (the part and "
                     "its range), or a place and date, or field_ut")
    result = fit_magnetometer(mag, rests=rests, raw_comparable=unit == "uT", label="counts" if counts else "µT",
                              **reference)
    return calibration_body(result, extra, unit=unit, notes=notes, device_id=request.device_id,
                            label=request.label or (recording.meta.get("filename") if recording else None), **source)


@dataclass(frozen=True)
class CompassAsk:
    """What the compass calibration reads of a request (:func:`_magnetometer`): ``auto`` on a recording of the
    magnetometer alone asks with no place, date or field, so that the field is estimated."""

    recording_id: str | None
    device_id: str | None = None
    label: str | None = None
    mag: list | None = None
    date: datetime.date | None = None
    latitude_deg: float | None = None
    longitude_deg: float | None = None
    height_m: float | None = None
    field_ut: float | None = None
    method: str = "magnetometer"


def _auto_compass(request, recording: RecordingSource) -> dict:
    """``auto`` on a recording of the magnetometer alone: the compass, its field estimated (``auto``
    takes no place; method magnetometer with a place references the Earth's field there)."""
    compass = CompassAsk(recording_id=request.recording_id, device_id=request.device_id, label=request.label)
    body = _magnetometer(compass, recording)
    body["choice"] = {"method": "magnetometer", "candidates": {},
                      "why": "the recording holds the magnetometer alone (no accelerometer columns): the compass "
                             "calibration; for the Earth's field at your place use method magnetometer with "
                             "latitude_deg, longitude_deg and date"}
    return body


# -- temperature: each axis's offset as a polynomial of the sensor's temperature ---------------------

TEMPERATURE_SENSORS = ("acc", "gyr")


def temperature_log(log: LogData, *, sensors=None, **fields) -> dict:
    """Temperature calibration (app.calibration.temperature) of a still recording that carries the sensor's
    temperature; accelerometers in g become m/s², gyroscopes in deg/s rad/s (the firmwares' units)."""
    from app.calibration.temperature import calibrate_temperature

    if log.temperature_c is None:
        raise CalibrationError(
            "the recording has no temperature: method temperature fits each axis's offset against the sensor's "
            "temperature — give a CSV with a temp_c column (°C, one per sample, beside the readings), or a flight "
            "controller's log (PX4 .ulg, ArduPilot .bin) that records its IMU's temperature")
    wanted = list(sensors) if sensors else [s for s in TEMPERATURE_SENSORS if getattr(log, s) is not None]
    missing = [s for s in wanted if getattr(log, s) is None]
    if not wanted or missing:
        raise CalibrationError(
            f"the recording has no {', '.join(missing or TEMPERATURE_SENSORS)} samples (it has "
            f"{', '.join(log.channels)}): method temperature calibrates the accelerometer and the gyroscope")
    notes = list(log.warnings) + list(log.notes)
    arrays = {}
    for name in wanted:
        unit = log.units[name]
        if unit == "raw":
            raise CalibrationError(
                f"the {name} readings are counts whose scale is unknown: the firmwares' temperature parameters are "
                "in m/s² and rad/s — give chip (--chip, e.g. mpu6050-2g,mpu6050-250dps), or the unit")
        scale = ACC_TO_M_S2[unit] if name == "acc" else GYR_TO_RAD_S[unit]
        arrays[name] = np.asarray(getattr(log, name), dtype=float) * scale
    rate = log.sampling_rate_hz
    if rate is None:
        rate = NOMINAL_RATE_HZ
        notes.append(f"the rests were looked for as if sampled at {NOMINAL_RATE_HZ:g} Hz (the log has no rate)")
    result = calibrate_temperature(log.temperature_c, sampling_rate_hz=rate, time_s=log.time_s, **arrays)
    return calibration_body(result, {}, unit=result.unit, notes=notes, **fields)


def _temperature(request, recording: RecordingSource) -> dict:
    log = recording.read()
    return temperature_log(log, sensors=request.sensors, device_id=request.device_id,
                           label=request.label or recording.meta.get("filename"), **recording.source_fields)


_METHODS = {"auto": _auto, "six_position": _known, "orientations": _known, "nonorthogonal": _magnitude, "triangular": _magnitude,
            "cube": _cube, "autocal": _autocal, "noise": _noise, "magnetometer": _magnetometer,
            "temperature": _temperature}
