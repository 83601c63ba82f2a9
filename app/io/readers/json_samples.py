"""JSON arrays of samples: ``[{"t": 0.01, "x": 0.02, "y": -0.01, "z": 0.98}, …]`` or ``[[0.01, 0.02, -0.01, 0.98], …]``.

Loggers and web apps save samples as a JSON array: of objects, one per sample, whose keys name the
columns (nested objects are flattened: ``{"acc": {"x": …}}`` is the column ``acc_x``), or of lists
of numbers, one per sample (a table without a header row). The array is the file itself, or the one
member of a top-level object that holds an array of samples (``{"device": "…", "samples": […]}``).

The array becomes a table, and the table is read as any CSV log (:mod:`.generic_csv`, or a phone app's
format when its keys are that app's columns), so that the columns, the time and the units are decided
exactly as for a CSV; the notes say what was read (where the array was, how many samples, which keys).
What is not an array of samples is refused, naming what the file holds.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeGuard

from ..errors import LogFormatError
from .table import Sniff

NAME = "json"
MAX_BYTES = 256 << 20
"""A JSON file is parsed whole: larger ones are refused (save such a recording as CSV)."""
MAX_LISTED = 12


def detect(s: Sniff) -> bool:
    """Text whose first character is ``[`` or ``{``."""
    return not s.is_zip and s.text.lstrip()[:1] in ("[", "{")


def _flat(sample: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    out = {}
    for key, value in sample.items():
        column = f"{prefix}{key}"
        if isinstance(value, dict):
            out.update(_flat(value, f"{column}_"))
        else:
            out[column] = value
    return out


def _number(value: object) -> TypeGuard[int | float]:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _samples(data: object, name: str) -> tuple[list[Any], str]:
    """The array of samples in ``data`` and where it was."""
    if isinstance(data, list):
        return data, "the top-level array"
    if isinstance(data, dict):
        arrays = [
            k
            for k, v in data.items()
            if isinstance(v, list) and len(v) >= 2 and all(isinstance(x, (dict, list)) for x in v[:10])
        ]
        if len(arrays) == 1:
            return data[arrays[0]], f"the array {arrays[0]!r}"
        keys = ", ".join(repr(k) for k in list(data)[:MAX_LISTED]) or "none"
        if arrays:
            raise LogFormatError(
                f"{name} is a JSON object holding several arrays ({', '.join(repr(k) for k in arrays)}): trical reads "
                "one array of samples per file; save each sensor's array as a file of its own (named for the "
                "sensor: accelerometer.json, gyroscope.json) and upload them together"
            )
        raise LogFormatError(
            f"{name} is a JSON object (keys {keys}) holding no array of samples: trical reads JSON arrays of samples, "
            'one object per sample ([{"t": 0.01, "acc_x": 0.02, "acc_y": -0.01, "acc_z": 0.98}, …]) or one list of '
            "numbers per sample ([[0.01, 0.02, -0.01, 0.98], …])"
        )
    raise LogFormatError(
        f"{name} holds a single JSON value, not an array of samples: trical reads JSON arrays of "
        "samples, one object or one list of numbers per sample"
    )


def to_table(data: object, name: str) -> tuple[list[str] | None, list[list[float]], str]:
    """The header (None for lists of numbers), the rows and a note saying what was read.

    Raises
    ------
    LogFormatError
        No array of samples; fewer than 2 samples; samples that are neither all objects nor all lists; a
        sample that lacks a column, or holds text where the first sample holds a number (named by its
        index and key).
    """
    samples, where = _samples(data, name)
    if len(samples) < 2:
        raise LogFormatError(f"{name}: {where} holds {len(samples)} sample: a recording needs many samples")
    if all(isinstance(x, dict) for x in samples):
        first = _flat(samples[0])
        columns = [k for k, v in first.items() if _number(v)]
        left = [k for k in first if k not in columns]
        if not columns:
            raise LogFormatError(
                f"{name}: the first sample of {where} holds no number ({', '.join(first)}): each "
                'sample needs its readings as numbers, e.g. {"t": 0.01, "x": 0.02, "y": -0.01, "z": 0.98}'
            )
        rows = []
        for i, sample in enumerate(samples):
            flat = _flat(sample)
            row = []
            for key in columns:
                value = flat.get(key)
                if not _number(value):
                    what = "lacks" if key not in flat else f"holds {json.dumps(value)[:40]} in"
                    raise LogFormatError(
                        f"{name}: sample {i} of {where} {what} {key!r}, which the first sample "
                        "holds as a number: give every sample the same numeric keys"
                    )
                row.append(float(value))
            rows.append(row)
        note = f"read as JSON: {where}, {len(rows)} samples, keys {', '.join(columns)}" + (
            f" ({', '.join(left)} not numbers: left out)" if left else ""
        )
        return columns, rows, note
    if all(isinstance(x, list) for x in samples):
        width = len(samples[0])
        rows = []
        for i, sample in enumerate(samples):
            if len(sample) != width or not all(_number(v) for v in sample):
                raise LogFormatError(
                    f"{name}: sample {i} of {where} is {json.dumps(sample)[:60]}, not {width} "
                    "numbers as the first sample: give every sample the same count of numbers"
                )
            rows.append([float(v) for v in sample])
        return None, rows, f"read as JSON: {where}, {len(rows)} samples of {width} numbers"
    kinds = sorted({type(x).__name__ for x in samples})
    raise LogFormatError(
        f"{name}: {where} holds {', '.join(kinds)} values, not samples: each sample is an object "
        '({"t": …, "x": …}) or a list of numbers, all of one kind'
    )


@dataclass(frozen=True)
class Samples:
    """A JSON file's samples as the table they make, which :func:`app.io.readers.read_log` then reads as a CSV
    file (:func:`write_table`), the columns, the time and the units decided exactly as for one.

    Attributes
    ----------
    header : list of str or None
        The columns' names (None: lists of numbers, a table without a header row).
    rows : list of list
        One row of numbers per sample.
    note : str
        What was read (where the array was, how many samples, which keys), the log's first note.
    format : str or None
        The format the log is then named by (the Betaflight configurator's tumble: ``betaflight_mag``); None keeps
        the format its table is read in.
    """

    header: list[str] | None
    rows: list[list[float]]
    note: str
    format: str | None = None


def read(path: Path, s: Sniff, *, name: str = "the file") -> Samples:
    """Read a JSON array of samples as the table it is.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    s : Sniff
        Its head (unused: the file is parsed whole).
    name : str
        How to call the file in messages.

    Returns
    -------
    Samples
        Its rows, for :func:`app.io.readers.read_log` to read as a CSV table.

    Raises
    ------
    LogFormatError
        A file over :data:`MAX_BYTES`, not UTF-8, not JSON, or holding no array of samples (:func:`to_table`).
    """
    if path.stat().st_size > MAX_BYTES:
        raise LogFormatError(
            f"{name} is a JSON file over {MAX_BYTES >> 20} MiB: save a recording this long as CSV", status=413
        )
    try:
        data = json.loads(path.read_bytes().decode("utf-8-sig"))
    except UnicodeDecodeError as exc:
        raise LogFormatError(
            f"{name} is not UTF-8 text (byte {exc.start}): save the JSON as UTF-8", status=415
        ) from None
    except json.JSONDecodeError as exc:
        raise LogFormatError(
            f"{name} starts like JSON but is not JSON: line {exc.lineno}, column {exc.colno}: "
            f"{exc.msg}; save it again whole (the file may be cut short)"
        ) from None
    header, rows, note = to_table(data, name)
    return Samples(header, rows, note)


def write_table(samples: Samples, folder: Path) -> Path:
    """Write the rows of ``samples`` as the CSV table they make (its header row when they have one) in ``folder``,
    where :func:`app.io.readers.read_log` reads it; its path."""
    table = Path(folder) / "samples.csv"
    with open(table, "w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        if samples.header:
            writer.writerow(samples.header)
        writer.writerows([repr(v) for v in row] for row in samples.rows)
    return table
