"""Generic and Arduino CSV logs: a header row naming the columns, readings in g, m/s² or LSB.

The columns are those :mod:`app.io.csv_log` recognises.  The unit comes from the caller, else the
header (``acc_x (g)``), else the data (:func:`~app.io.formats.units.infer_acc_unit`).  Readings in
counts (LSB) become g with the sensor's sensitivity, given as ``lsb_per_g`` by the caller or in a
comment line of the file such as ``# MPU-6050 ±2 g, lsb_per_g=16384``.

The *arduino* format adds the Arduino IDE Serial Plotter's ``label:value`` lines
(``ax:-112 ay:35 az:16490``, separated by spaces, tabs or commas) to the CSV layout.
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np

from ..csv_log import _PATTERNS, _map_columns, _normalise, _split_header, read_csv_log
from ..errors import LogFormatError
from ..log import LogData
from .table import Sniff, rate_from_time
from .units import infer_acc_unit

CSV = "csv"
ARDUINO = "arduino"
LSB_COMMENT = re.compile(r"lsb[ _]?per[ _]?g\s*[:=]\s*([0-9][0-9.eE+]*)", re.IGNORECASE)
_PLOTTER_PAIR = re.compile(r"([A-Za-z_][A-Za-z0-9_ ]*?)\s*:\s*(-?[0-9][0-9.eE+-]*)")
_PLOTTER_LINE = re.compile(r"^\s*[A-Za-z_][A-Za-z0-9_]*\s*:\s*-?[0-9]")


def lsb_from_comments(lines: list[str]) -> float | None:
    """The ``lsb_per_g`` a comment line of the file gives, if any."""
    for line in lines:
        if line.lstrip().startswith("#"):
            m = LSB_COMMENT.search(line)
            if m:
                return float(m.group(1))
    return None


def _data_lines(lines: list[str]) -> list[str]:
    return [ln for ln in lines if ln.strip() and not ln.lstrip().startswith("#")]


def detect_arduino(s: Sniff) -> bool:
    """Serial Plotter ``label:value`` lines, or a CSV whose comments give ``lsb_per_g``."""
    if s.is_zip:
        return False
    data = _data_lines(s.lines)
    return bool(data and _PLOTTER_LINE.match(data[0])) or lsb_from_comments(s.lines) is not None


def detect_csv(s: Sniff) -> bool:
    return not s.is_zip


def _header_acc_unit(text: str) -> str | None:
    try:
        _, _, names = _split_header(text)
        return _map_columns(names)[3].get("acc")
    except LogFormatError:
        return None


def _settle_units(log: LogData, caller_acc: str | None, header_acc: str | None, lsb_per_g, fmt: str,
                  notes: list[str]) -> LogData:
    unit = caller_acc or header_acc
    if unit is None:
        unit = infer_acc_unit(log.acc)
        if unit is None:
            unit = "m/s^2"
            notes.append("accelerometer unit not named and not evident from the data: m/s² assumed "
                         "(give acc_unit to change it)")
        else:
            notes.append(f"accelerometer unit {unit} inferred from the data (median norm)")
    if lsb_per_g is not None and unit != "raw" and caller_acc is None and header_acc is None:
        unit = "raw"  # lsb_per_g says the readings are counts
    return dataclasses.replace(log, units={**log.units, "acc": unit}, format=fmt, notes=tuple(notes))


def read_csv(path: Path, s: Sniff, *, sampling_rate_hz=None, units=None, name="the file", lsb_per_g=None,
             fmt: str = CSV, column_map: dict | None = None, **_) -> LogData:
    """Read a generic CSV log, settling the accelerometer unit (caller, header, data)."""
    units = units or {}
    log = read_csv_log(path, sampling_rate_hz=sampling_rate_hz, units=units, name=name, column_map=column_map)
    return _settle_units(log, units.get("acc"), _header_acc_unit(s.text), lsb_per_g, fmt, [])


def read_arduino(path: Path, s: Sniff, *, sampling_rate_hz=None, units=None, name="the file", lsb_per_g=None,
                 **kw) -> LogData:
    """Read Arduino output: Serial Plotter ``label:value`` lines, or a CSV with an ``lsb_per_g`` comment."""
    data = _data_lines(s.lines)
    if not (data and _PLOTTER_LINE.match(data[0])):
        return read_csv(path, s, sampling_rate_hz=sampling_rate_hz, units=units, name=name,
                        lsb_per_g=lsb_per_g, fmt=ARDUINO, column_map=kw.get("column_map"))
    with open(path, encoding="utf-8-sig", errors="replace") as f:
        lines = f.read().splitlines()
    first = dict((k.strip(), v) for k, v in _PLOTTER_PAIR.findall(data[0]))
    labels = list(first)
    channels: dict[str, dict[str, str]] = {}
    for label in labels:
        for sensor, pattern in _PATTERNS.items():
            m = pattern.match(_normalise(label))
            if m:
                channels.setdefault(sensor, {}).setdefault(m.group("axis"), label)
                break
    if set(channels.get("acc", {})) != {"x", "y", "z"}:
        raise LogFormatError(
            f"the Serial Plotter labels of {name} ({', '.join(labels)}) name no accelerometer x, y and z: "
            "print them as ax:…, ay:…, az:… (Serial.print(\"ax:\"); Serial.print(ax); …)"
        )
    channels = {k: v for k, v in channels.items() if set(v) == {"x", "y", "z"}}
    rows: dict[str, list[list[float]]] = {k: [] for k in channels}
    for number, line in enumerate(lines, start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        pairs = dict((k.strip(), v) for k, v in _PLOTTER_PAIR.findall(line))
        try:
            for sensor, axes in channels.items():
                rows[sensor].append([float(pairs[axes[a]]) for a in "xyz"])
        except (KeyError, ValueError):
            raise LogFormatError(f"{name}: line {number} {line[:60]!r} lacks a number for one of "
                                 f"{', '.join(v for ax in channels.values() for v in ax.values())}") from None
    arrays = {k: np.asarray(v, dtype=float) for k, v in rows.items()}
    units = units or {}
    log = LogData(
        acc=arrays["acc"], gyr=arrays.get("gyr"), mag=arrays.get("mag"), time_s=None,
        sampling_rate_hz=rate_from_time(None, sampling_rate_hz, name),
        units={k: units.get(k) or {"acc": "m/s^2", "gyr": "raw", "mag": "raw"}[k] for k in arrays},
        format=ARDUINO, columns=labels,
    )
    return _settle_units(log, units.get("acc"), None, lsb_per_g, ARDUINO, [])
