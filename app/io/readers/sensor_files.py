"""Recordings made of several files, one per sensor: ``accelerometer.csv``, ``gyroscope.csv``, ``magnetometer.csv``.

Many loggers (phone apps, makers' boards writing one file per sensor to an SD card) save each sensor
of one recording in a file of its own, each with its own time column. trical tells such a set from
the files of one calibration's poses (:mod:`app.io.readers.parts`) by the files themselves
(:func:`per_sensor_files`):

* every file's name names one sensor (:func:`sensor_from_name`: ``acc``, ``accel``, ``accelerometer``;
  ``gyr``, ``gyro``, ``gyroscope``; ``mag``, ``magnetometer``, ``compass``, ``hmc…``, ``qmc…``,
  ``ak…``), and no two files name the same one — each file then holds that one sensor (columns named
  ``x, y, z`` are that sensor's); or, whatever their names, each file's columns name one sensor, and no
  two the same (``ax, ay, az`` in one, ``gx, gy, gz`` in the other: :func:`app.io.readers.parts.read_parts`);
* their time columns overlap in time, rather than follow each other as the poses of a calibration do
  (files that do not are refused).

Each file is read alone, so that its unit is decided on its own data
(:func:`app.io.readers.units.settle_units`, through the reader). The files are then merged onto one
clock (:func:`merge_sensor_logs`): the accelerometer's, or the fastest sensor's when there is none;
every other sensor is interpolated linearly onto it, never across one of its gaps (nor beyond its
first or last sample): clock samples there are dropped, and the merged recording shows a gap there.
The notes say which file gave which sensor and which clock was chosen.
"""

from __future__ import annotations

import dataclasses
import json
import re
from collections.abc import Callable
from pathlib import Path, PurePosixPath
from typing import cast

import numpy as np

from app.calibration.shared.headlines import SENSOR_WORDS as WORDS

from ..errors import LogFormatError
from ..log import LogData
from .kinds import TEXT_SUFFIXES
from .timing import with_timing

SENSOR_WORDS = {
    "acc": (
        "acc",
        "accel",
        "accelerometer",
        "accelerometers",
        "acceleration",
        "accelerations",
        "accl",
        "totalacceleration",
        "accelerometeruncalibrated",
        "adxl",
        "lis3dh",
        "lsm303acc",
    ),
    "gyr": (
        "gyr",
        "gyro",
        "gyros",
        "gyroscope",
        "gyroscopes",
        "gyroscopeuncalibrated",
        "rotationrate",
        "angularvelocity",
    ),
    "mag": (
        "mag",
        "magn",
        "magneto",
        "magnetometer",
        "magnetometers",
        "magnetometeruncalibrated",
        "magneticfield",
        "compass",
        "hmc",
        "qmc",
        "ak",
        "mmc",
        "lis3mdl",
        "bmm",
    ),
}
"""Words of a file's name that name the one sensor it holds (a chip's family counts: ``hmc5883l``)."""
_SUFFIXES = (".gz", *TEXT_SUFFIXES)
MAX_MISSING_FRACTION = 0.5
"""More of the clock's samples than this fraction without every other sensor around them: the files are
not one recording (or their clocks differ), and they are refused."""

ReadFile = Callable[[Path, str, dict[str, str] | None], LogData]
"""The one reader of a recording's files, with the upload's options: ``read(path, name, columns)``, where ``columns``
(None for the upload's own) reads a file's unnamed ``x, y, z`` columns as its sensor's (:func:`columns_for`)."""
SensorFile = tuple[str, str, LogData, float | None]
"""One sensor of a recording's files (:func:`merge_sensor_logs`): the file's name, the sensor, the file's log and
its first sample's time on the files' shared clock (None when its time column gives none)."""
BySensor = dict[str, tuple[str, LogData, float | None]]
"""Each sensor's file: its name, its log and its first sample's time on the shared clock."""


def _tokens(filename: str) -> list[str]:
    stem = PurePosixPath(str(filename).replace("\\", "/")).name
    for suffix in _SUFFIXES:
        if stem.lower().endswith(suffix):
            stem = stem[: -len(suffix)]
    stem = re.sub(r"(?<=[a-z])(?=[A-Z])", "_", stem)  # camelCase: TotalAcceleration → Total_Acceleration
    words = [w for w in re.split(r"[^a-z0-9]+", stem.lower()) if w]
    joined = ["".join(words[i : i + 2]) for i in range(len(words) - 1)]  # total_acceleration → totalacceleration
    return words + joined


def sensor_from_name(filename: str) -> str | None:
    """The one sensor a file's name names (``acc``, ``gyr`` or ``mag``), or None when it names none, or several.

    A word of the name (split at anything not a letter or digit, and at camelCase) names a sensor
    when it is one of :data:`SENSOR_WORDS`, possibly followed by digits (``hmc5883l``, ``ak8963``,
    ``gyro2``).

    Parameters
    ----------
    filename : str
        The file's name, with or without folders and suffix.

    Returns
    -------
    str or None
    """
    found = set()
    for token in _tokens(filename):
        base = re.sub(r"\d+[a-z]?$", "", token) or token
        for sensor, words in SENSOR_WORDS.items():
            if token in words or base in words:
                found.add(sensor)
    return found.pop() if len(found) == 1 else None


GRAVITY_REMOVED_WORDS = ("linear", "linearacceleration", "useracceleration", "gravity")
"""Words of a file's name that say it holds not the accelerometer's readings but what a phone computes from them
(phyphox's ``Linear Acceleration.csv``, ``Gravity.csv``; Core Motion's user acceleration): left out beside the
accelerometer's own file, with a note."""


def _gravity_removed(filename: str) -> bool:
    return any(t in GRAVITY_REMOVED_WORDS for t in _tokens(filename))


UNNAMED_COLUMNS = {3: ["x", "y", "z"], 4: ["time", "x", "y", "z"]}
"""The columns of a file named for one sensor whose rows carry no names: its x, y, z (after its time)."""


def per_sensor_files(names: list[str]) -> dict[str, str] | None:
    """The sensor of each file when the names make the files one recording per sensor, else None.

    Two or more files, each naming one sensor (:func:`sensor_from_name`), no sensor twice.
    """
    if len(names) < 2:
        return None
    sensors = {n: s for n in names if (s := sensor_from_name(n)) is not None}
    if len(sensors) != len(names) or len(set(sensors.values())) != len(names):
        return None
    return sensors


def _table(path: Path, name: str) -> tuple[list[str], int | None, list[float]] | None:
    """A file's column names, its time column and the first two values of that column, or None when the file
    is not a table trical reads as one (a zip, a table it cannot lay out). A JSON array of samples is the table
    it becomes (:mod:`app.io.readers.json_samples`)."""
    from . import json_samples
    from .generic_csv import map_columns, table_layout
    from .table import SNIFF_BYTES, decode_head, is_comment, split_row

    with open(path, "rb") as f:
        head = f.read(SNIFF_BYTES)
    try:
        text = decode_head(head, name)
        if text.lstrip()[:1] in ("[", "{"):
            header, rows, _ = json_samples.to_table(json.loads(path.read_bytes().decode("utf-8-sig")), name)
            names = header or UNNAMED_COLUMNS.get(len(rows[0]))
            if names is None:
                return None
            time_col = map_columns(names)[1]
            return names, time_col, [r[time_col] for r in rows[:2]] if time_col is not None else []
        layout = table_layout(text, name)
        time_col = map_columns(layout.names)[1]
    except (LogFormatError, ValueError):
        return None
    raw: list[float] = []
    if time_col is not None:
        lines = [ln for ln in text.splitlines()[layout.skip_lines :] if ln.strip() and not is_comment(ln)]
        try:
            raw = [float(split_row(ln, layout.delimiter)[time_col].replace(layout.decimal, ".")) for ln in lines[:2]]
        except (ValueError, IndexError):
            raw = []
    return [n.strip().strip('"').strip() for n in layout.names], time_col, raw


def columns_for(path: Path, sensor: str, name: str) -> dict[str, str] | None:
    """The ``columns`` mapping that reads a file's unnamed ``x, y, z`` columns as ``sensor``'s, or None.

    None when the file's header names its sensor's columns itself (``gx, gy, gz``), names another
    sensor's too, or is not a table (a zip): it is then read as it is.
    """
    from .generic_csv import map_columns

    if sensor == "acc":
        return None
    table = _table(path, name)
    if table is None:
        return None
    names = table[0]
    try:
        channels = map_columns(names)[0]
    except LogFormatError:
        return None
    if set(channels) != {"acc"}:
        return None
    return {f"{sensor}_{axis}": names[col] for axis, col in channels["acc"].items()}


def read_as_named(read: ReadFile, path: Path, fname: str, sensor: str | None, columns_given: bool) -> LogData:
    """A file read with ``read`` (:func:`read_sensor_files`), its unnamed ``x, y, z`` columns read as ``sensor``'s
    where its name names one (:func:`columns_for`), unless the upload named the columns itself."""
    mapping = None if columns_given or sensor is None else columns_for(path, sensor, fname)
    return read(path, fname, mapping) if mapping else read(path, fname, None)


def first_time(path: Path, log: LogData, name: str) -> float | None:
    """The time of a file's first sample in seconds on the file's own clock (its time column's zero), or None.

    :class:`LogData` counts time from each file's first sample; merging files needs where each starts on
    the clock they share. The first two values of the time column and the log's first step give it.
    """
    if log.time_s is None or len(log.time_s) < 2 or log.time_s[1] <= 0:
        return None
    table = _table(path, name)
    if table is None or len(table[2]) < 2 or table[2][1] == table[2][0]:
        return None
    raw = table[2]
    scale = float(log.time_s[1]) / (raw[1] - raw[0])
    return raw[0] * scale


def _outside(times: np.ndarray, log: LogData, start: float) -> np.ndarray:
    """Where ``times`` (on the shared clock) fall outside ``log``'s samples or inside one of its gaps."""
    t = np.asarray(log.time_s, dtype=float) + start
    out: np.ndarray = (times < t[0]) | (times > t[-1])
    for gap in log.gaps:
        out |= (times > t[gap.index - 1]) & (times < t[gap.index])
    return out


def merge_sensor_logs(logs: list[SensorFile], *, name: str) -> LogData:
    """One recording from the files of its sensors, on one clock.

    Parameters
    ----------
    logs : list of (str, str, LogData, float or None)
        Each file's name, the sensor it holds, its log (read alone), and its first sample's time on the
        clock the files share (:func:`first_time`; None when its time column gives none: it is then
        taken to start with the others).
    name : str
        How to call the recording in messages.

    Returns
    -------
    LogData
        The clock's samples (the accelerometer's, else the fastest sensor's) with every other sensor
        interpolated at them; clock samples beyond another sensor's ends or inside one of its gaps are
        left out. ``units`` are each file's own; ``notes`` name each file's sensor and the clock.

    Raises
    ------
    LogFormatError
        A file without a time column (files of different sensors cannot be put on one clock without
        one) unless all have the same count of samples; files that do not overlap in time.
    """
    by_sensor = {sensor: (fname, log, start) for fname, sensor, log, start in logs}
    timed = all(log.time_s is not None and len(log.time_s) >= 2 for _, log, _ in by_sensor.values())
    files = list(dict.fromkeys(fname for fname, _, _, _ in logs))
    notes = [
        f"one recording in {len(files)} files, "
        + ("one per sensor: " if len(files) == len(logs) else "each with sensors of its own: ")
        + ", ".join(f"{fname} the {WORDS[sensor]} ({log.units[sensor]})" for fname, sensor, log, _ in logs)
    ]
    if not timed:
        return _one_to_one(logs, by_sensor, notes, name)
    starts = _overlapping_starts(by_sensor, name)
    if "acc" in by_sensor:
        clock_sensor, why = "acc", "the accelerometer's"
    else:
        clock_sensor = max(by_sensor, key=lambda s: by_sensor[s][1].sampling_rate_hz or 0.0)
        why = f"the fastest sensor's, the {WORDS[clock_sensor]}'s"
    clock_file, clock_log, _ = by_sensor[clock_sensor]
    times = np.asarray(clock_log.time_s, dtype=float) + starts[clock_sensor]
    drop = np.zeros(len(times), dtype=bool)
    for s, (_fname, log, _) in by_sensor.items():
        if s != clock_sensor:
            drop |= _outside(times, log, starts[s])
    if drop.mean() > MAX_MISSING_FRACTION:
        raise LogFormatError(
            f"{name}: {int(drop.sum())} of the {len(times)} samples of {clock_file} have no sample of the other "
            "files' sensors around them (the files overlap too little, or their clocks differ): upload the files "
            "of one recording, each with its time column on the same clock"
        )
    keep = ~drop
    kept_times = times[keep]
    arrays = {clock_sensor: np.asarray(getattr(clock_log, clock_sensor), dtype=float)[keep]}
    for s, (fname, log, _) in by_sensor.items():
        if s == clock_sensor:
            continue
        if fname == clock_file:  # a sensor of the clock's own file: on its times already
            arrays[s] = np.asarray(getattr(log, s), dtype=float)[keep]
            continue
        t = np.asarray(log.time_s, dtype=float) + starts[s]
        v = np.asarray(getattr(log, s), dtype=float)
        arrays[s] = np.column_stack([np.interp(kept_times, t, v[:, k]) for k in range(3)])
    notes.append(
        f"merged on the clock of {clock_file} ({why}, {clock_log.sampling_rate_hz or 0:.4g} Hz); "
        + ", ".join(dict.fromkeys(f"{f} interpolated onto it" for f, _, _ in by_sensor.values() if f != clock_file))
    )
    if drop.any():
        notes.append(
            f"{int(drop.sum())} of the {len(times)} samples of {clock_file} left out: another file has no "
            "samples there (before its first, after its last, or in one of its gaps); they are not "
            "interpolated across"
        )
    temperature = clock_log.temperature_c
    merged = LogData(
        acc=arrays.get("acc"),
        gyr=arrays.get("gyr"),
        mag=arrays.get("mag"),
        time_s=kept_times - kept_times[0],
        sampling_rate_hz=None,
        units={s: log.units[s] for s, (_, log, _) in by_sensor.items()},
        format=_format(logs),
        columns=list(clock_log.columns),
        notes=tuple(notes + _file_notes(logs)),
        sign=clock_log.sign,
        warnings=_warnings(logs),
        questions=_questions(logs),
        scales=_scales(logs),
        temperature_c=None if temperature is None else np.asarray(temperature)[keep],
    )
    return _gyro_against_gravity(with_timing(merged, None, name), by_sensor)


GYRO_UNIT_WORDS = ("for the gyroscope", "gyroscope unit", "the gyroscope's unit")
"""What the reading of a gyroscope's file alone says of its unit (app.io.readers.units): said again, or
overruled, once the accelerometer's file beside it is merged (:func:`_gyro_against_gravity`)."""


def _gyro_against_gravity(merged: LogData, by_sensor: BySensor) -> LogData:
    """The gyroscope's unit, decided on its own file (its header's, or what its data showed alone), checked
    against the accelerometer's file merged beside it: the gyroscope's integral against gravity's turn between
    rests or over windows of motion (:func:`~app.io.readers.gyro_unit.gyro_evidence`). Where the turns decide,
    what the file alone said of the unit is replaced by their word, and a unit they contradict is overruled
    (the readings are kept; their unit changes), naming both."""
    from .gyro_unit import gyro_evidence

    unit = merged.units.get("gyr")
    if merged.acc is None or merged.gyr is None or unit not in ("rad/s", "deg/s"):
        return merged
    fname, log, _ = by_sensor["gyr"]
    if (log.scales or {}).get("gyr"):
        return merged  # counts scaled by a chip or a sensitivity: the scale was given or found, not a unit
    ev = gyro_evidence(merged.gyr, whole=False, acc=merged.acc, fs=merged.sampling_rate_hz, time_s=merged.time_s)
    if ev.unit is None or not ev.by_turns:
        return merged
    prefix = f"{fname}: "

    def about_unit(text: str) -> bool:
        return text.startswith(prefix) and any(w in text for w in GYRO_UNIT_WORDS)

    notes = [n for n in merged.notes if not about_unit(n)]
    warnings = [w for w in merged.warnings if not about_unit(w)]
    questions = tuple(q for q in merged.questions if q.get("sensor") != "gyr")
    if ev.unit == unit:
        notes.append(f"{prefix}the gyroscope's unit {unit}, against the accelerometer beside it: {ev.words}")
        return dataclasses.replace(merged, notes=tuple(notes), warnings=tuple(warnings), questions=questions)
    header = any(f"({unit})" in str(c).lower() for c in log.columns)
    warnings.append(
        f"{prefix}{'its header says' if header else 'read alone, its data said'} {unit} for the gyroscope, but "
        f"against the accelerometer beside it {ev.words}: read as {ev.unit}"
    )
    units = {**merged.units, "gyr": ev.unit}
    notes = [n.replace(f"the gyroscope ({unit})", f"the gyroscope ({ev.unit})") for n in notes]
    return dataclasses.replace(merged, units=units, notes=tuple(notes), warnings=tuple(warnings), questions=questions)


def _one_to_one(logs: list[SensorFile], by_sensor: BySensor, notes: list[str], name: str) -> LogData:
    """Files without a time column in every one: their samples taken as simultaneous, one to one, when they
    hold as many; refused otherwise."""
    counts = {log.n_samples for _, log, _ in by_sensor.values()}
    if len(counts) != 1:
        lacking = ", ".join(f for f, log, _ in by_sensor.values() if log.time_s is None)
        raise LogFormatError(
            f"{name}: {lacking} has no time column, and the files hold different counts of samples "
            f"({', '.join(f'{f} {log.n_samples}' for f, log, _ in by_sensor.values())}): the sensors' files "
            "cannot be put on one clock; log a time column in every file"
        )
    notes.append("no time column in every file: the files' samples taken as simultaneous, one to one")
    clock_sensor = "acc" if "acc" in by_sensor else next(iter(by_sensor))
    clock_log = by_sensor[clock_sensor][1]
    arrays = {s: np.asarray(getattr(log, s), dtype=float) for s, (_, log, _) in by_sensor.items()}
    return dataclasses.replace(
        clock_log,
        acc=arrays.get("acc"),
        gyr=arrays.get("gyr"),
        mag=arrays.get("mag"),
        units={s: log.units[s] for s, (_, log, _) in by_sensor.items()},
        notes=tuple(notes + _file_notes(logs)),
        warnings=_warnings(logs),
        questions=_questions(logs),
        scales=_scales(logs),
        parts=(),
        format=_format(logs),
    )


def _overlapping_starts(by_sensor: BySensor, name: str) -> dict[str, float]:
    """Each sensor's first time on the files' shared clock, from the earliest (a file without one starts with
    the others); files whose times do not overlap are refused."""
    starts = {s: (st if st is not None else 0.0) for s, (_, _, st) in by_sensor.items()}
    zero = min(starts.values())
    starts = {s: st - zero for s, st in starts.items()}
    # Every file has its time column here (merge_sensor_logs): its log's time_s is an array.
    spans = {
        s: (starts[s], starts[s] + float(cast(np.ndarray, log.time_s)[-1])) for s, (_, log, _) in by_sensor.items()
    }
    begin, end = max(a for a, _ in spans.values()), min(b for _, b in spans.values())
    if end <= begin:
        listed = ", ".join(f"{by_sensor[s][0]} {a:.3f}–{b:.3f} s" for s, (a, b) in spans.items())
        raise LogFormatError(
            f"{name}: the files name one sensor each but their times do not overlap ({listed}): the sensors of one "
            "recording are logged at the same time; upload the files of one recording together"
        )
    return starts


def _format(logs: list[SensorFile]) -> str:
    formats = list(dict.fromkeys(log.format for _, _, log, _ in logs))
    return formats[0] if len(formats) == 1 else "+".join(formats)


def _files(logs: list[SensorFile]) -> dict[str, LogData]:
    """Each file's log, once (a file of several sensors gives an entry per sensor)."""
    return {fname: log for fname, _, log, _ in logs}


def _file_notes(logs: list[SensorFile]) -> list[str]:
    """What the reading of each file noticed (its time column's unit, its unit inferred), named by the file."""
    return [f"{fname}: {note}" for fname, log in _files(logs).items() for note in log.notes]


def _scales(logs: list[SensorFile]) -> dict[str, dict[str, str | float]] | None:
    """How each file's numbers became its sensor's unit (:attr:`app.io.log.LogData.scales`); None where no file
    says (arrays)."""
    if all(log.scales is None for _, _, log, _ in logs):
        return None
    return {s: log.scales[s] for _, s, log, _ in logs if log.scales and s in log.scales}


def _questions(logs: list[SensorFile]) -> tuple[dict[str, str], ...]:
    """What the reading of each file left open (the gyroscope's unit), named by the file."""
    return tuple(
        {**q, "detail": f"{fname}: {q['detail']}"} for fname, log in _files(logs).items() for q in log.questions
    )


def _warnings(logs: list[SensorFile]) -> tuple[str, ...]:
    return tuple(f"{fname}: {w}" for fname, log in _files(logs).items() for w in log.warnings)


def read_sensor_files(
    sources: list[tuple[str, Path]], read: ReadFile, *, name: str, columns_given: bool
) -> LogData | None:
    """Read the files of one recording as one per sensor, or None when they are not (then they are poses).

    Parameters
    ----------
    sources : list of (str, pathlib.Path)
        Each file's name and where it is.
    read : callable
        ``read(path, name, columns)`` → :class:`LogData`: the one reader with the upload's options;
        ``columns`` (None for the upload's own) reads a file's unnamed ``x, y, z`` columns as its sensor's.
    name : str
        How to call the recording in messages.
    columns_given : bool
        The upload named the columns itself: they are used for every file as they are.
    """
    derived = [n for n, _ in sources if _gravity_removed(n)]
    kept = [(n, p) for n, p in sources if n not in derived]
    if derived and "acc" in (per_sensor_files([n for n, _ in kept]) or {}).values():
        merged = read_sensor_files(kept, read, name=name, columns_given=columns_given)
        note = (
            f"{', '.join(derived)} left out: {'they hold' if len(derived) > 1 else 'it holds'} what the phone "
            "computed from the accelerometer (gravity or the acceleration without it), not its readings, which "
            f"{next(n for n, _ in kept if sensor_from_name(n) == 'acc')} holds"
        )
        return None if merged is None else dataclasses.replace(merged, notes=(note, *merged.notes))
    sensors = per_sensor_files([n for n, _ in sources])
    if sensors is None:
        return None
    logs = []
    for fname, path in sources:
        sensor = sensors[fname]
        log = read_as_named(read, path, fname, sensor, columns_given)
        if log.channels != [sensor]:
            if len(log.channels) > 1:
                return None  # a file of several sensors: the files are a recording's poses, or parts of one
            raise LogFormatError(
                f"{fname} is named for the {WORDS[sensor]} but holds the {WORDS[log.channels[0]]}'s columns "
                f"({', '.join(map(str, log.columns[:8]))}): name the file for the sensor it holds, or its columns "
                f"for the {WORDS[sensor]} ({sensor}_x, {sensor}_y, {sensor}_z)"
            )
        logs.append((fname, sensor, log, first_time(path, log, fname)))
    return merge_sensor_logs(logs, name=name)
