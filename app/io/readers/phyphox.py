"""phyphox exports: ``Raw Data.csv`` alone or inside the zip export ("CSV (…)" formats).

phyphox names its columns ``"Time (s)"``, ``"Acceleration x (m/s^2)"`` … (experiment
*Acceleration with g*), ``"Linear Acceleration x (m/s^2)"`` (*Acceleration without g*, refused),
``"Gyroscope x (rad/s)"``, ``"Magnetic field x (µT)"``; the zip holds ``Raw Data.csv`` and a ``meta``
folder.  Its CSV flavours are comma, tab or semicolon separated with a decimal point, and tab or
semicolon separated with a decimal comma.  Readings are specific force in m/s² with +g on the up
axis on both platforms: phyphox's iOS app multiplies Core Motion's readings (in g, opposite sign) by
``kG = -9.81`` (phyphox-ios, ``ExperimentSensorInput.swift``), so no flip is needed here.  (Its very
first iOS releases used ``+9.81``; such files read upside down, every rest labelled with the
opposite axis.)
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..errors import LogFormatError
from ..log import LogData
from .table import Sniff, find_member, first_row, guess_decimal, read_columns, read_member

NAME = "phyphox"
RAW_DATA = "Raw Data.csv"
_TIME = re.compile(r"^time \(s\)$")
_COLUMN = re.compile(
    r"^(?P<sensor>linear acceleration|acceleration|gyroscope|magnetic field) (?P<axis>[xyz]) \((?P<unit>[^)]*)\)$"
)
_ABSOLUTE = re.compile(r"^absolute (acceleration|field) \([^)]*\)$")
"""phyphox's norm columns beside the axes (``Absolute acceleration (m/s^2)``, ``Absolute field (µT)``): not read."""
_SENSOR = {"acceleration": "acc", "gyroscope": "gyr", "magnetic field": "mag"}
_UNIT = {"m/s^2": "m/s^2", "rad/s": "rad/s", "µt": "uT", "μt": "uT", "ut": "uT"}


def _is_phyphox_header(names: list[str]) -> bool:
    """``Time (s)``, then phyphox's own columns only: a header that names any other column (another app's
    ``Accelerometer X (g)`` beside ``Gyroscope X (deg/s)``) is not phyphox's, and is read by the general reader
    with every column its header names."""
    lowered = [n.strip().lower() for n in names]
    rest = [n for n in lowered[1:] if n]
    return (
        bool(lowered)
        and bool(_TIME.match(lowered[0]))
        and bool(rest)
        and all(_COLUMN.match(n) or _ABSOLUTE.match(n) for n in rest)
    )


def detect(s: Sniff) -> bool:
    """A zip holding ``Raw Data.csv``, or a header ``Time (s)`` followed by phyphox's sensor columns only."""
    if s.is_zip:
        return find_member(s.members, RAW_DATA) is not None
    found = first_row(s.lines)
    return found is not None and _is_phyphox_header(found[2])


def read(path: Path, s: Sniff, *, units: dict[str, str] | None = None, name: str = "the file") -> LogData:
    """Read a phyphox CSV or zip export.

    Parameters
    ----------
    path : pathlib.Path
        The file (a CSV, or the zip export).
    s : Sniff
        Its head: its header row, or the zip's members.
    units : dict, optional
        The caller's units by sensor, over the format's (the header's); the rate, the counts and the sign are
        :func:`app.io.readers.read_log`'s.
    name : str
        How to call the file in messages.

    Returns
    -------
    LogData
        Its samples on its ``Time (s)``, ``format`` ``phyphox``.
    """
    notes: list[str] = []
    if s.is_zip:
        member = find_member(s.members, RAW_DATA)
        if member is None:
            raise LogFormatError(f"{name} holds no {RAW_DATA}: give phyphox's zip export as it saved it")
        data = read_member(path, member, name)
        label = f"{member} in {name}"
        notes.append(f"read {member} from the phyphox zip export")
    else:
        data, label = path.read_bytes(), name
    lines = data.decode("utf-8-sig", errors="replace").splitlines()
    found = first_row(lines)
    if found is None or not _is_phyphox_header(found[2]):
        raise LogFormatError(
            f'{label} is not a phyphox table: its first line must be "Time (s)", then the sensor columns'
        )
    index, delimiter, names = found
    decimal = guess_decimal(lines[index + 1 :], delimiter)
    channels: dict[str, dict[str, int]] = {}
    found_units: dict[str, str] = {}
    linear = False
    left: dict[str, list[str]] = {
        "the norm of the three axes, which trical computes itself": [],
        "linear acceleration, gravity removed, which no calibration can use": [],
    }
    norms, gravity_removed = left.values()
    for col, raw in enumerate(names):
        m = _COLUMN.match(raw.strip().lower())
        if not m:
            if col and raw.strip():
                norms.append(raw.strip())
            continue
        if m.group("sensor") == "linear acceleration":
            linear = True
            gravity_removed.append(raw.strip())
            continue
        sensor = _SENSOR[m.group("sensor")]
        channels.setdefault(sensor, {})[m.group("axis")] = col
        found_units[sensor] = _UNIT.get(m.group("unit").lower(), m.group("unit"))
    if not any(set(axes) == {"x", "y", "z"} for axes in channels.values()):
        if linear:
            raise LogFormatError(
                f"{label} holds linear acceleration (gravity removed; phyphox 'Acceleration without g'): "
                "calibration needs gravity in the readings: record with phyphox 'Acceleration with g' instead"
            )
        listed = ", ".join(repr(n) for n in names)
        raise LogFormatError(
            f"{label} has no phyphox accelerometer or magnetometer columns among {listed}: record "
            "with 'Acceleration with g' (or 'Magnetometer' for a compass calibration), or map "
            "the columns as acc_x, acc_y, acc_z (format=csv)"
        )
    channels = {k: v for k, v in channels.items() if set(v) == {"x", "y", "z"}}
    order = [0] + [channels[s_][a] for s_ in channels for a in "xyz"]
    arrays = read_columns(
        data,
        skip_lines=index + 1,
        n_columns=len(names),
        columns=order,
        delimiter=delimiter,
        decimal=decimal,
        name=label,
        column_names=names,
    )
    time = arrays[0]
    stacked = {s_: np.column_stack(arrays[1 + 3 * k : 4 + 3 * k]) for k, s_ in enumerate(channels)}
    final_units = {s_: (units or {}).get(s_) or found_units.get(s_) for s_ in stacked}
    if decimal == ",":
        notes.append("decimal comma")
    notes += [f"not read: {', '.join(map(repr, cols))} ({why})" for why, cols in left.items() if cols]
    return LogData(
        acc=stacked.get("acc"),
        gyr=stacked.get("gyr"),
        mag=stacked.get("mag"),
        time_s=time - time[0],
        sampling_rate_hz=None,
        units=final_units,
        format=NAME,
        columns=names,
        notes=tuple(notes),
    )
