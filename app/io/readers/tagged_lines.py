"""Logs whose every line names its sensor first: ``acc 2060 0.0332 -0.0012 0.9692``, ``gyro 2060 0.29 1.30 -4.29``.

A board's firmware that prints each sensor as it reads it writes such lines, one sensor per line, the
lines of the sensors interleaved: a tag word (``acc``, ``accel``, ``gyro``, ``mag``, ``compass``…,
optionally followed by ``:``), then an optional time and the three readings, separated by spaces, tabs,
commas or semicolons. Each tag's lines are one sensor's stream; the streams are put on the
accelerometer's times (else the first sensor's) by linear interpolation, as GnssLogger's records are
(:mod:`.gnss_logger`). Nothing in the lines states a unit: the data decide it
(:func:`app.io.readers.units.settle_units`), the accelerometer and the gyroscope together.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..errors import LogFormatError
from ..log import UNITS, LogData
from .table import Sniff, is_comment, resample_to
from .timing import time_scale

NAME = "tagged"
TAGS = {
    "acc": ("acc", "accel", "accelerometer", "acceleration"),
    "gyr": ("gyr", "gyro", "gyroscope"),
    "mag": ("mag", "magn", "magnetometer", "compass"),
}
"""The words a line may begin with, by the sensor they name (any case)."""
_SENSOR_OF = {word: sensor for sensor, words in TAGS.items() for word in words}
_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_LINE = re.compile(rf"^\s*(?P<tag>[A-Za-z][A-Za-z_]*)\s*:?[\s,;]+(?P<values>{_NUMBER}(?:[\s,;]+{_NUMBER}){{2,3}})\s*$")
MAX_HEADER_LINES = 3
"""Lines before the first reading that are skipped as a header (more are refused: they are not such a log)."""
MIN_LINES = 5
"""Lines needed before the format is recognised."""
TAGGED_FRACTION = 0.9
"""Of the non-comment lines of the first 64 KiB, at least this fraction are tagged readings."""


def _parse(line: str) -> tuple[str, list[float]] | None:
    m = _LINE.match(line)
    if m is None:
        return None
    return m.group("tag").lower(), [float(v) for v in re.split(r"[\s,;]+", m.group("values").strip())]


def detect(s: Sniff) -> bool:
    """Most lines are a tag, then three or four numbers, and some tag names a sensor (:data:`TAGS`)."""
    if s.is_zip:
        return False
    lines = [ln for ln in s.lines if ln.strip() and not is_comment(ln)]
    parsed = [p for p in map(_parse, lines) if p is not None]
    return (
        len(parsed) >= MIN_LINES
        and len(parsed) >= TAGGED_FRACTION * len(lines)
        and any(tag in _SENSOR_OF for tag, _ in parsed)
    )


def read(path: Path, s: Sniff, *, units: dict[str, str] | None = None, name: str = "the file") -> LogData:
    """Read a log of tagged lines: each sensor's lines one stream, on the accelerometer's times.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    s : Sniff
        Its head (unused: the file is read whole).
    units : dict, optional
        The caller's units by sensor, over the format's (none stated: the data decide); the rate, the counts
        and the sign are :func:`app.io.readers.read_log`'s.
    name : str
        How to call the file in messages.

    Returns
    -------
    LogData
        Each sensor's samples on the accelerometer's times, ``format`` ``tagged``.
    """
    with open(path, encoding="utf-8-sig", errors="replace") as f:
        lines = [ln for ln in f.read().splitlines() if ln.strip() and not is_comment(ln)]
    streams: dict[str, list[list[float]]] = {}
    other: dict[str, int] = {}
    first = next((i for i, line in enumerate(lines) if _parse(line) is not None), 0)
    header = lines[:first] if first <= MAX_HEADER_LINES else []  # a header row (VMU931's Attribute,Time stamp,x,y,z)
    for number, line in enumerate(lines, start=1):
        parsed = _parse(line)
        if parsed is None and number <= len(header):
            continue
        if parsed is None:
            raise LogFormatError(
                f"{name}: line {number} {line[:60]!r} is not a tagged reading: every line must name its sensor "
                "(acc, gyro or mag) and then give an optional time and three numbers; fix or remove that line"
            )
        tag, numbers = parsed
        if tag not in _SENSOR_OF:
            other[tag] = other.get(tag, 0) + 1
            continue
        streams.setdefault(_SENSOR_OF[tag], []).append(numbers)
    if not streams:
        raise LogFormatError(
            f"{name}: no line names a sensor trical reads (its tags are {', '.join(sorted(other)) or 'none'}): "
            f"tag each line with {', '.join(_SENSOR_OF)}, or upload it with format=auto"
        )
    arrays = {sensor: _rows(rows, sensor, name) for sensor, rows in streams.items()}
    base = "acc" if "acc" in arrays else next(iter(arrays))
    timed = all(a.shape[1] == 4 for a in arrays.values())
    notes = ["lines tagged by sensor: " + ", ".join(f"{len(a)} {sensor}" for sensor, a in arrays.items())] + [
        f"{count} line{'s' if count > 1 else ''} tagged {tag!r} not read (no sensor trical calibrates)"
        for tag, count in other.items()
    ]
    notes += [f"line {k} {line[:60]!r} skipped before the readings" for k, line in enumerate(header, start=1)]
    if timed:
        scale, unit = time_scale(arrays[base][:, 0])
        t0 = arrays[base][0, 0]
        time_s = (arrays[base][:, 0] - t0) * scale
        values = {base: arrays[base][:, 1:]}
        values.update(
            {k: resample_to(time_s, (a[:, 0] - t0) * scale, a[:, 1:]) for k, a in arrays.items() if k != base}
        )
        notes.append(
            f"each line's time in {unit}"
            + (f"; the other sensors interpolated at the {base} lines' times" if len(arrays) > 1 else "")
        )
    else:
        counts = {k: len(a) for k, a in arrays.items()}
        if len(set(counts.values())) > 1:
            raise LogFormatError(
                f"{name} has no time on its lines, and its sensors' lines differ in number "
                f"({', '.join(f'{k} {n}' for k, n in counts.items())}): they cannot be paired; print a time on "
                "every line (the tag, then the time, then x, y, z)"
            )
        time_s = None
        values = {k: a[:, -3:] for k, a in arrays.items()}
    units = units or {}
    return LogData(
        acc=values.get("acc"),
        gyr=values.get("gyr"),
        mag=values.get("mag"),
        time_s=time_s,
        sampling_rate_hz=None,
        units={k: units.get(k) or UNITS[k][0] for k in values},
        format=NAME,
        columns=[f"{k} {axis}" for k in values for axis in "xyz"],
        notes=tuple(notes),
    )


def _rows(rows: list[list[float]], sensor: str, name: str) -> np.ndarray:
    widths = {len(r) for r in rows}
    if len(widths) > 1:
        raise LogFormatError(
            f"{name}: the {sensor} lines give {' or '.join(str(w) for w in sorted(widths))} numbers: every line of "
            "one sensor needs the same, three readings after an optional time"
        )
    return np.asarray(rows, dtype=float)
