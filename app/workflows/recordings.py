"""Logs into recordings: read a file, describe it (its still segments, its overview), store it; and the
recording a request calibrates from (:class:`RecordingSource`) with the checks every method makes of it."""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Collection, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from app.calibration import STANDARD_GRAVITY, CalibrationError, nearest_orientation
from app.calibration.segments.static import StaticSegment, detect_static_segments
from app.calibration.shared.errors import InsufficientDataError
from app.calibration.shared.orientations import WITHIN_LABEL_ANGLE
from app.io.log import LogData
from app.io.readers import read_log, source_of_format
from app.io.readers.parts import Part, content_digest, pose_from_name
from app.io.readers.read_options import ReadOptions
from app.workflows.supports import supports

if TYPE_CHECKING:
    from app.store import Store

BROWSER_STEP = 0.1
"""Browsers round DeviceMotion values to 0.1 m/s² (W3C Device Orientation, fingerprinting mitigation)."""


def add_recording(
    store: Store, recording_id: str, path: Path, *, filename: str | None, options: ReadOptions, owner: str | None
) -> dict[str, Any]:
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
    options : app.io.readers.read_options.ReadOptions
        How to read it (the caller's rate included), kept with the recording.
    owner : str or None

    Returns
    -------
    dict
        The stored recording (:func:`describe_log` with its id, filename and creation time).
    """
    try:
        log = read_log(path, options, name=filename or "the file")
        body = describe_log(log, options, path=path)
        body["filename"] = filename
        body["content_sha256"] = content_digest(path)  # the same upload read again: its calibrations supersede
        return store.add_recording(recording_id, body, path, owner=owner)
    except BaseException:
        path.unlink(missing_ok=True)
        raise


def quantization_step(samples: np.ndarray, step: float = BROWSER_STEP) -> float | None:
    """``step`` when every sample is a multiple of it (browser rounding), else None."""
    sub = samples[:10_000]
    scaled = sub / step
    if len(sub) > 10 and np.allclose(scaled, np.round(scaled), atol=1e-6):
        return step
    return None


def describe_log(log: LogData, options: ReadOptions | None = None, *, path: Path | None = None) -> dict[str, Any]:
    """Recording metadata and its static segments (docs/rest.md, POST /recordings).

    ``options`` are what the reader was told (:class:`app.io.readers.read_options.ReadOptions`); they are kept as
    ``read_with``, with the sign applied, so that the stored file is read again the same way. ``path``, the file
    read: a flight controller's log's first GPS fix is read from it (``flight.fix``), for the compass's place.
    """
    segments, part_notes = still_segments(log)
    fix = flight_fix(path, options) if log.flight is not None and path is not None else None
    rate = log.sampling_rate_hz
    notes = list(log.notes) + part_notes
    if log.acc is not None and log.sampling_rate_hz is None:
        notes.append(
            f"still segments looked for as if sampled at {NOMINAL_RATE_HZ:g} Hz (the log has no rate): "
            "their start and end are sample indices"
        )
    body: dict[str, Any] = {
        "format": log.format,
        "n_samples": log.n_samples,
        "sampling_rate_hz": rate,
        "duration_s": None if rate is None else log.n_samples / rate,
        "channels": log.channels,
        "units": log.units,
        "columns": log.columns,
        "notes": notes,
        "warnings": list(log.warnings),
        "questions": [dict(q) for q in log.questions],
        "scales": log.scales,
        "sign": log.sign,
        "timing": None if log.timing is None else log.timing.to_dict(),
        "read_with": (options or ReadOptions()).stored(log.sign),
        "quantization_step": quantization_step(log.acc)
        if log.units.get("acc") == "m/s^2" and log.acc is not None
        else None,
        "segments": segments,
        "supports": [s.to_dict() for s in supports(log, segments, fix=fix)],
        "overview": overview(log),
    }
    if log.flight is not None:  # a flight controller's log: every instance, and those read
        body["flight"] = {**log.flight.to_dict(), "fix": fix}
        body["temperature_c"] = temperature_range(log.temperature_c)
    if log.parts:
        body["parts"] = [
            {
                "index": i,
                "filename": p.filename,
                "start": p.start,
                "end": p.end,
                "n_samples": p.n_samples,
                "sampling_rate_hz": p.sampling_rate_hz,
                "pose_from_name": pose_from_name(p.filename),
            }
            for i, p in enumerate(log.parts)
        ]
    return body


def flight_fix(path: Path, options: ReadOptions | None) -> dict[str, Any] | None:
    """A flight controller's log's first 3-D GPS fix (``latitude_deg``, ``longitude_deg``, ``date``) as its compass
    is read (app.io.flight.context), or None: no fix, no compass, or a log whose compass cannot be read (the
    compass from the flight then says why)."""
    from app.io.errors import LogFormatError
    from app.io.flight.compass import read_flight_compass

    try:
        log = read_flight_compass(path, mag_instance=(options or ReadOptions()).mag_instance)
    except LogFormatError:
        return None
    if log.latitude_deg is None or log.longitude_deg is None:
        return None
    return {
        "latitude_deg": float(log.latitude_deg),
        "longitude_deg": float(log.longitude_deg),
        "date": None if log.utc is None else log.utc.date().isoformat(),
    }


def temperature_range(temperature: np.ndarray | None) -> dict[str, float] | None:
    """The smallest and largest of a log's sensor temperature (°C), or None without one."""
    if temperature is None:
        return None
    finite = np.asarray(temperature, dtype=float)
    finite = finite[np.isfinite(finite)]
    return {"min": float(finite.min()), "max": float(finite.max())} if finite.size else None


def _short_still_file(
    acc: np.ndarray, part: Part, gravity: float | None, everything: np.ndarray
) -> tuple[list[dict[str, Any]], str] | None:
    """A pose file too short for a still segment (under MIN_DURATION_S) that is still all through: the
    whole file is its pose's reading, as the person who saved it meant (one file, one pose).

    Still means the spread (root of the summed per-axis variances) within CAP_G of gravity and a mean
    norm within NORM_RANGE_G, the bounds of the still-segment detector (docs/methods.md)."""
    from app.calibration.segments.static import CAP_G, MIN_DURATION_S, NORM_RANGE_G

    rate = part.sampling_rate_hz or NOMINAL_RATE_HZ
    if part.n_samples < 2 or part.n_samples / rate >= MIN_DURATION_S:
        return None
    a = np.asarray(acc, dtype=float)
    g = gravity or float(np.median(np.linalg.norm(np.asarray(everything, dtype=float), axis=1)))
    mean, std = a.mean(axis=0), a.std(axis=0)
    spread = float(np.sqrt(np.sum(std**2)))
    norm = float(np.linalg.norm(mean))
    if not (np.all(np.isfinite(mean)) and spread <= CAP_G * g and NORM_RANGE_G[0] * g <= norm <= NORM_RANGE_G[1] * g):
        return None
    seg = {
        "start": 0,
        "end": part.n_samples,
        "acc_mean": mean.tolist(),
        "acc_std": std.tolist(),
        "up": nearest_orientation(mean),
        "count": part.n_samples,
    }
    duration = part.n_samples / rate
    return [seg], (
        f"{part.filename}: {duration:.1f} s, shorter than the {MIN_DURATION_S:g} s a still segment needs, "
        f"but still all through (spread {spread / g * 1000:.1f} mg): the whole file is its pose's reading"
    )


NOMINAL_RATE_HZ = 100.0
"""The rate still segments are looked for at in a log that has none (no time column, none given): their
windows and least length are counted in samples as at 100 Hz; a note says so."""


def _still_between_gaps(
    acc: np.ndarray, rate: float, gravity: float | None, cuts: Sequence[int], others: Sequence[np.ndarray] = ()
) -> list[StaticSegment]:
    """Still segments (app.calibration.segments.static) of ``acc``, still on every sensor of ``others`` too (the
    gyroscope's and the magnetometer's samples on its clock), each stretch between the sample indices
    ``cuts`` (gaps of the time column) searched on its own, so that a segment's samples are contiguous
    in time; a stretch shorter than one window holds none."""
    bounds = [0, *cuts, len(acc)]
    out = []
    for a, b in itertools.pairwise(bounds):
        try:
            found = detect_static_segments(acc[a:b], rate, gravity=gravity, others=[o[a:b] for o in others])
        except InsufficientDataError:  # shorter than one window: no rest in it
            continue
        out += [
            dataclasses.replace(
                seg, start=seg.start + a, end=seg.end + a, gaps=tuple((p + a, q + a) for p, q in seg.gaps)
            )
            for seg in found
        ]
    return out


def still_segments(log: LogData) -> tuple[list[dict[str, Any]], list[str]]:
    """A log's still segments in their plain form (docs/rest.md), and notes on a recording in parts.

    The segments are the accelerometer's rests (a log of other sensors alone has none) that are still on
    every other sensor the log holds too (a gyroscope ringing after the board was put down, a compass
    turning about gravity: docs/methods.md), none spanning a gap of the time column. A recording made of several files
    (one per pose, :mod:`app.io.readers.parts`) is
    searched file by file, so that no segment joins two files; each segment then names its file
    (``source``, ``part``), and a file whose name names a pose (``x_axis_pos``) that its still
    readings contradict gets a note.
    """
    if log.acc is None:
        return [], []
    unit = log.units.get("acc")
    gravity = {"m/s^2": STANDARD_GRAVITY, "g": 1.0}.get(unit or "")  # raw: estimated from the data
    rate = log.sampling_rate_hz or NOMINAL_RATE_HZ
    others = [o for o in (log.gyr, log.mag) if o is not None]
    if not log.parts:
        rests = _still_between_gaps(log.acc, rate, gravity, [g.index for g in log.gaps], others)
        return [dict(index=i, **seg.to_dict(), count=seg.count) for i, seg in enumerate(rests)], []
    segments: list[dict[str, Any]] = []
    notes: list[str] = []
    for k, part in enumerate(log.parts):
        cuts = [g.index - part.start for g in log.gaps if part.start < g.index < part.end]
        found = [
            seg.to_dict() | {"count": seg.count}
            for seg in _still_between_gaps(
                log.acc[part.start : part.end],
                part.sampling_rate_hz or rate,
                gravity,
                cuts,
                [o[part.start : part.end] for o in others],
            )
        ]
        named = pose_from_name(part.filename)
        if not found and (short := _short_still_file(log.acc[part.start : part.end], part, gravity, log.acc)):
            found, note = short
            notes.append(note)
        for plain in found:
            plain.update(start=plain["start"] + part.start, end=plain["end"] + part.start)
            segments.append(
                dict(
                    index=len(segments),
                    **plain,
                    source=part.filename,
                    part=k,
                    **({"pose_from_name": named} if named else {}),
                )
            )
        if not found:
            notes.append(
                f"{part.filename}: no still stretch found in its {part.n_samples} samples, so it gives no "
                "reading: record the board resting, untouched, for a few seconds in that pose"
            )
        elif named:
            ups = [seg["up"] for seg in found]
            if any(up != named for up in ups):
                seen = ", ".join(sorted({up or f"no axis {WITHIN_LABEL_ANGLE}" for up in ups if up != named}))
                notes.append(
                    f"{part.filename}: its name says {named} up, but its still readings point {seen} "
                    f"up: the data's label is used — check the file's name, or how the board lay"
                )
    return segments, notes


OVERVIEW_POINTS = 300
"""Bins of a log's overview: enough for a plot the width of a phone."""


def overview(log: LogData) -> dict[str, Any]:
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
    plain = {
        "sensor": sensor,
        "unit": log.units.get(sensor),
        "t_s": None if rate is None else (edges[:-1] / rate).tolist(),
        "start": edges[:-1].tolist(),
        "low": [float(f.min()) if f.size else None for f in finite],
        "high": [float(f.max()) if f.size else None for f in finite],
    }
    if log.temperature_c is not None:  # the sensor's temperature over the same bins: the page's warm-up curve
        temps = [b[np.isfinite(b)] for b in np.split(np.asarray(log.temperature_c, dtype=float), edges[1:-1])]
        plain["temperature_c"] = [float(b.mean()) if b.size else None for b in temps]
    return plain


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

    meta: dict[str, Any]
    path: Path
    id: str | None = None
    log: LogData | None = None

    def read(self, clock: str | None = None) -> LogData:
        """The recording's samples as stored; ``clock="mag"`` reads a flight controller's log on its compass's
        clock (app.io.flight.instances), which the compass methods ask for (other logs are read as stored)."""
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
        return read_log(
            self.path,
            ReadOptions.from_stored({**read_with, "sampling_rate_hz": rate}),
            name=self.meta.get("filename") or "the recording",
        )

    @property
    def source_fields(self) -> dict[str, Any]:
        """The calibration's fields about its recording: its id, and where it came from (``source``): by its
        format (app.io.readers.source_of_format), else a board where its readings
        were counts (no phone app logs counts: an Arduino's CSV, an HMC5883L's)."""
        fields = {} if self.id is None else {"recording_id": self.id}
        source = source_of_format(self.meta.get("format", ""))
        if source is None and self._counts():
            source = "board"
        return fields if source is None else {**fields, "source": source}

    def _counts(self) -> bool:
        """Whether the recording's readings were counts (kept as counts, or scaled from them)."""
        scales = (self.meta.get("scales") or {}).values()
        units = (self.meta.get("units") or {}).values()
        return "raw" in units or any(s.get("read_in") == "counts" for s in scales)

    def supersede_key(self, body: dict[str, Any]) -> str | None:
        """What a calibration of this recording supersedes the earlier ones by (with its method, device name and
        owner: app.store): the upload's digest, and for a flight log's compass which compass it is — compass 1's
        calibration is no later reading of compass 0's."""
        digest = self.meta.get("content_sha256")
        instance = (body.get("flight") or {}).get("instance")
        return digest if digest is None or instance is None else f"{digest}:compass{instance}"


def require_rate(rate: float | None, method: str) -> float:
    """The recording's sampling rate, or a refusal naming what to give: methods over time need one."""
    if rate is None:
        raise CalibrationError(
            f"method {method} needs the sensor's sampling rate, and this recording has none (no time column, and "
            "sampling_rate_hz not given): read it again with sampling_rate_hz, the "
            "sensor's output data rate, or log a time column"
        )
    return rate


def require_accelerometer(channels: Collection[str], method: str) -> None:
    """Refuse a recording without accelerometer columns for an accelerometer method, naming the fix."""
    if "acc" not in channels:
        other = {
            "mag": "method magnetometer calibrates a magnetometer turned through all directions",
            "gyr": "method noise characterises a still gyroscope",
        }
        raise CalibrationError(
            f"the recording has no accelerometer columns (it has {', '.join(channels)}): method {method} needs "
            "acc_x, acc_y, acc_z — record the accelerometer too; " + "; ".join(other[c] for c in channels if c in other)
        )
