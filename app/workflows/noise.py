"""Noise: the Allan deviation of a still recording."""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from app.calibration import CalibrationError
from app.calibration.noise.still_part import NOISE_MIN_S, NOISE_REST_S
from app.calibration.shared.errors import InsufficientDataError
from app.io.log import SI_UNITS, TO_SI, LogData
from app.workflows.calibration import Calibration
from app.workflows.recordings import RecordingSource, require_rate
from app.workflows.requests import NoiseRequest

if TYPE_CHECKING:
    from app.io.readers.timing import Gap

NOISE_SENSORS = ("acc", "gyr", "mag")
NOISE_GAPS_MAX = 0.01
"""Gaps losing more than this fraction of the still part's time make its Allan deviation unreliable
(``ok`` false): the estimator takes the samples as evenly spaced, and a lost stretch joins two
stretches as if they were adjacent."""


def characterise_log(
    log: LogData, *, sensors: Sequence[str] | None = None, array_sensor: str | None = None, **fields: Any
) -> Calibration:
    """Noise characterisation (app.calibration.noise.characterise) of every chosen sensor of a still recording.

    ``array_sensor`` names the sensor a three-column array (``.npy``, Parquet) holds, which the readers
    return as ``acc``. Gyroscopes in deg/s become rad/s, magnetometers in nT µT, accelerometers in g
    m/s² (Kalibr's units). The still part is the longest stretch still on every sensor the recording
    holds: when some of the recording moved, a warning says what was used; when less than half of it is
    still, ``ok`` is false.
    """
    from app.calibration.noise.characterise import NoiseResult, characterise_noise
    from app.calibration.noise.spikes import remove_spikes
    from app.calibration.noise.still_part import common_still_runs

    arrays, units, wanted = _chosen_sensors(log, sensors, array_sensor)
    # Spikes out first: a torn read breaks the half-second block it falls in, and the still part with it.
    spikes = {}
    for name in list(arrays):
        arrays[name], spikes[name] = remove_spikes(arrays[name])
    fs, n = require_rate(log.sampling_rate_hz, "noise"), len(next(iter(arrays.values())))
    notes: list[str] = list(log.warnings) + list(log.notes)
    # Still means still on every sensor the recording holds, asked for or not (a gyroscope ringing after
    # the device was put down, a compass turning): docs/methods.md, "Still on every sensor".
    still_on = [s for s in NOISE_SENSORS if s in arrays]
    runs = common_still_runs([arrays[s] for s in still_on], fs)
    reasons: list[str] = []
    span = _gap_free(log, _still_span(runs, fs, n, notes, reasons), fs, notes)
    _judge_gaps(log, span, fs, notes, reasons)
    a, b = span
    if (b - a) / fs < NOISE_MIN_S:
        from app.calibration.noise.allan import MIN_SAMPLES
        from app.calibration.noise.characterise import duration_words

        said = (
            f"too short: the still part lasts {duration_words((b - a) / fs)} ({b - a} samples), and the noise needs "
            f"one rest of {duration_words(NOISE_MIN_S)} or more — record the device resting, untouched, for "
            f"{duration_words(NOISE_MIN_S)} or more"
        )
        if b - a < MIN_SAMPLES:  # no Allan deviation at all: nothing to answer but what to record
            raise InsufficientDataError(said[0].upper() + said[1:])
        if not reasons:
            reasons.append(said)
    parts = {}
    for name in wanted:
        unit = units[name]
        samples = arrays[name][a:b]
        counts = spikes[name][a:b].sum(axis=0).tolist()
        if any(counts):
            notes.append(_spikes_said(name, counts))
        scale = TO_SI[name].get(unit, 1.0)
        if scale != 1.0:
            samples = np.asarray(samples, dtype=float) * scale
            unit = SI_UNITS[name]
        part = characterise_noise(samples, fs, unit=unit, sensor=name)
        notes.extend(part.pop("warnings"))
        parts[name] = part
    duration = (b - a) / fs
    result = NoiseResult(
        sensors={k: {x: p[x] for x in ("model", "adev", "uncertainty", "metrics")} for k, p in parts.items()},
        sampling_rate_hz=fs,
        duration_s=duration,
        still={"start": a, "end": b, "n_samples": b - a, "fraction": (b - a) / n, "detected_from": ", ".join(still_on)},
        units_stated=log.flight is not None,
        reasons=tuple(reasons),
        unit=parts[wanted[0]]["model"]["unit"],
    )
    return Calibration.of(result, {}, unit=result.unit, notes=notes, **fields)


def _spikes_said(sensor: str, counts: list[int]) -> str:
    """The warning that names the spikes removed from a sensor's still part, axis by axis."""
    from app.calibration.shared.headlines import SENSOR_WORDS

    axes = ", ".join(f"{n} on {axis}" for n, axis in zip(counts, "xyz") if n)
    return (
        f"the {SENSOR_WORDS[sensor]}'s still part holds {sum(counts)} spike{'s' if sum(counts) > 1 else ''} ({axes}): "
        "one or two samples far off both neighbours, as a register read in two halves (a torn read), a bus error or "
        "a knock shorter than a sample gives, removed (each replaced by its neighbours) before the Allan deviation; "
        "on a board, reading the sensor's registers in one burst avoids torn reads"
    )


def _chosen_sensors(
    log: LogData, sensors: Sequence[str] | None, array_sensor: str | None
) -> tuple[dict[str, np.ndarray], dict[str, str], list[str]]:
    """The recording's samples and units by sensor (an array's under the sensor it holds), and the sensors
    asked for (by default every one it has); a sensor it lacks is refused."""
    arrays = {name: getattr(log, name) for name in log.channels}
    units = dict(log.units)
    if array_sensor not in (None, "acc"):
        if log.channels != ["acc"]:
            raise CalibrationError(
                f"the sensor of an array is given for files with one sensor; this one has "
                f"{', '.join(log.channels)}: leave it out"
            )
        arrays = {array_sensor: log.acc}
        units = {array_sensor: SI_UNITS[array_sensor]}
    wanted = list(sensors) if sensors else [s for s in NOISE_SENSORS if s in arrays]
    missing = [s for s in wanted if s not in arrays]
    if missing:
        raise CalibrationError(
            f"the recording has no {', '.join(missing)} samples (it has {', '.join(arrays)}): ask for those it has"
        )
    return arrays, units, wanted


def _still_span(
    runs: list[tuple[int, int]], fs: float, n: int, notes: list[str], reasons: list[str]
) -> tuple[int, int]:
    """The longest still stretch (the whole recording when none is), with a note or a reason when the device
    moved: several rests, or too little of the recording still."""
    from app.calibration.noise.still_part import MIN_STILL_FRACTION

    span = max(runs, key=lambda r: r[1] - r[0]) if runs else None
    rests = [r for r in runs if r[1] - r[0] >= NOISE_REST_S * fs]
    if span is not None and len(rests) >= 2:
        a, b = span
        said = (
            f"the device moved: the recording holds {len(rests)} rests separated by moves (the poses of a "
            f"calibration, or handling): only the longest, {a / fs:.1f}–{b / fs:.1f} s ({100 * (b - a) / n:.0f} % "
            "of the recording), was characterised — no term is fitted across a move"
        )
        if b - a < MIN_STILL_FRACTION * n:
            reasons.append(
                said + "; for the noise, record the device resting in one orientation, untouched, for "
                "the whole recording"
            )
        else:
            notes.append(said)
    elif span is None or (span[1] - span[0]) < MIN_STILL_FRACTION * n:
        still_s = 0.0 if span is None else (span[1] - span[0]) / fs
        reasons.append(
            f"the device moved: the longest still stretch is {still_s:.1f} s of {n / fs:.1f} s; the noise "
            "is characterised on a still recording — leave the device resting on a firm surface, "
            "untouched, for the whole recording"
        )
        span = span or (0, n)
    elif n - (span[1] - span[0]) > max(2.0 * fs, 0.01 * n):
        notes.append(
            f"the device moved: only the longest still stretch, {span[0] / fs:.1f}–{span[1] / fs:.1f} s "
            f"({100 * (span[1] - span[0]) / n:.0f} % of the recording), was used"
        )
    return span


def _gaps_inside(log: LogData, span: tuple[int, int]) -> list[Gap]:
    """The time column's gaps inside the still part ``span``."""
    return [g for g in log.gaps if span[0] < g.index < span[1]]


def _gap_free(log: LogData, span: tuple[int, int], fs: float, notes: list[str]) -> tuple[int, int]:
    """The longest stretch of the still part that holds no gap of the time column, when it is long enough for the
    noise (:data:`NOISE_MIN_S`; a note names the gaps it avoids); else the still part, whose gaps are judged."""
    inside = _gaps_inside(log, span)
    if not inside:
        return span
    edges = [span[0], *(g.index for g in inside), span[1]]
    a, b = max(itertools.pairwise(edges), key=lambda e: e[1] - e[0])
    if (b - a) / fs < NOISE_MIN_S:
        return span
    longest = max(inside, key=lambda g: g.missing_s)
    notes.append(
        f"the timing: {len(inside)} gap{'s' if len(inside) > 1 else ''} in the time column inside the still part "
        f"(the longest {longest.missing_s:.3g} s at {longest.t_s:.1f} s): the longest stretch without one, "
        f"{a / fs:.1f}–{b / fs:.1f} s ({(b - a) / fs:.1f} s), was characterised — the Allan deviation takes its "
        "samples as evenly spaced"
    )
    return a, b


GAP_REMEDIES = {
    "ardupilot": "log again with fewer messages or a faster SD card (the log dropped messages: its DSF messages "
    "count them)",
    "px4": "log again with a faster SD card or a lighter logging profile (the logger dropped samples)",
    "phone": "record again with the app in the foreground and the screen on (the phone paused the sensors)",
}
"""How to record again without losing samples, by where the recording comes from (app.io.readers.SOURCES); a
board printing to a serial port (or an unknown source) loses them on the way to the host."""
SERIAL_REMEDY = (
    "record again without losing samples (a faster serial baud rate, fewer columns printed, a larger host buffer)"
)


def _judge_gaps(log: LogData, span: tuple[int, int], fs: float, notes: list[str], reasons: list[str]) -> None:
    """A note on the time column's gaps inside the still part, or a reason when they lose too much of it for
    the Allan deviation (:data:`NOISE_GAPS_MAX`), with the remedy of the recording's source."""
    from app.io.readers import source_of_format

    inside = _gaps_inside(log, span)
    if inside:
        lost = sum(g.missing_s for g in inside)
        still_s = (span[1] - span[0]) / fs
        said = (
            f"the timing: {len(inside)} gap{'s' if len(inside) > 1 else ''} in the time column lose "
            f"{lost:.3g} s of the {still_s:.1f} s still part ({100 * lost / (still_s + lost):.2g} %)"
        )
        if lost > NOISE_GAPS_MAX * still_s:
            source = source_of_format(log.format)
            reasons.append(
                said + ", and no stretch without a gap lasts "
                f"{NOISE_MIN_S:g} s: the Allan deviation assumes samples evenly spaced in time, so this curve is "
                f"not the sensor's — {GAP_REMEDIES.get(source or '', SERIAL_REMEDY)}"
            )
        else:
            notes.append(said + ": few enough for the Allan deviation")


def noise(request: NoiseRequest, recording: RecordingSource) -> Calibration:
    """Method ``noise``: the chosen sensors of a still recording (a flight log's compass on its own clock)."""
    clock = None
    if recording.meta.get("flight") is not None and request.sensors and "mag" in request.sensors:
        if list(request.sensors) != ["mag"]:
            raise CalibrationError(
                "a flight controller's compass is read on its own clock, slower than the IMU's: "
                'ask for sensors ["mag"] alone, and for the IMU\'s (acc, gyr) in another request'
            )
        clock = "mag"
    notes: list[str]
    log, notes = recording.read(clock=clock), []
    if log.parts:  # one file per pose: the noise of one file, never across two
        log, notes = one_still_file(log)
    calibration = characterise_log(
        log,
        sensors=request.sensors,
        array_sensor=request.sensor,
        device_id=request.device_id,
        label=request.label or recording.meta.get("filename"),
        **recording.source_fields,
    )
    return dataclasses.replace(calibration, read_warnings=tuple(notes) + calibration.read_warnings)


def one_still_file(log: LogData) -> tuple[LogData, list[str]]:
    """The file of a recording in parts with the longest still stretch, as a log of its own, and a note
    naming it: the Allan deviation of a sequence joined from several files would see their seams."""
    from app.calibration.noise.still_part import longest_still
    from app.io.readers.parts import part_log

    def still_samples(i: int) -> int:
        one = part_log(log, i)
        # Pose files without a time column and no rate given have none: refused as the whole log is (characterise_log).
        rate = require_rate(one.sampling_rate_hz, "noise")
        span = longest_still([getattr(one, name) for name in one.channels], rate)
        return 0 if span is None else span[1] - span[0]

    lengths = [still_samples(i) for i in range(len(log.parts))]
    best = int(np.argmax(lengths))
    note = (
        f"the recording is made of {len(log.parts)} files: the noise is characterised on one, "
        f"{log.parts[best].filename} (the longest still stretch), not across files"
    )
    return part_log(log, best), [note]
