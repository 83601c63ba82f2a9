"""Physics Toolbox Sensor Suite (Vieyra Software): g-Force Meter and Multi Record CSVs.

The header is ``time,gFx,gFy,gFz,TgF`` (g-force meter) or a longer Multi Record row that adds
``ax,ay,az`` (linear acceleration, gravity removed — not used), ``wx,wy,wz`` (rad/s) and
``Bx,By,Bz`` (µT).  The g-force ``gF = N / (m g)`` is specific force in g with +1 on the up axis.
``time`` is seconds, or a clock ``hh:mm:ss:SSS`` / ``mm:ss.SSS`` in some versions; some locales
write ``;`` with a decimal comma.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..errors import LogFormatError
from ..log import LogData
from .table import Sniff, columns_not_read, first_row, guess_decimal, read_columns, split_row

NAME = "physics_toolbox"
_GF = ("gfx", "gfy", "gfz")
_CLOCK = re.compile(r"^(?:(\d+):)?(\d+):(\d+)(?:[:.,](\d+))?$")


def detect(s: Sniff) -> bool:
    """A header naming ``gFx``, ``gFy`` and ``gFz``."""
    if s.is_zip:
        return False
    found = first_row(s.lines)
    return found is not None and set(_GF) <= {n.lower() for n in found[2]}


def _clock_seconds(text: str) -> float:
    m = _CLOCK.match(text.strip())
    if not m:
        return float(text.replace(",", "."))
    h, mnt, sec, frac = m.groups()
    seconds = int(h or 0) * 3600 + int(mnt) * 60 + int(sec)
    return seconds + (int(frac) / 10 ** len(frac) if frac else 0.0)


def read(path: Path, s: Sniff, *, units: dict[str, str] | None = None, name: str = "the file") -> LogData:
    """Read a Physics Toolbox CSV: the g-force columns, and gyroscope/magnetometer when present.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    s : Sniff
        Its head (unused: the file is read whole).
    units : dict, optional
        The caller's units by sensor, over the format's (g, rad/s, µT); the rate, the counts and the sign are
        :func:`app.io.readers.read_log`'s.
    name : str
        How to call the file in messages.

    Returns
    -------
    LogData
        Its samples on its time column when it reads as seconds or a clock, ``format`` ``physics_toolbox``.
    """
    data = path.read_bytes()
    lines = data.decode("utf-8-sig", errors="replace").splitlines()
    found = first_row(lines)
    if found is None:
        raise LogFormatError(f"{name} holds no lines: give the Physics Toolbox CSV with its header and readings")
    index, delimiter, names = found
    lowered = [n.lower() for n in names]
    decimal = guess_decimal(lines[index + 1 :], delimiter, first_column=1)  # a clock may read 00:01,500
    sensors = {"acc": _GF, "gyr": ("wx", "wy", "wz"), "mag": ("bx", "by", "bz")}
    present = {k: [lowered.index(c) for c in cols] for k, cols in sensors.items() if set(cols) <= set(lowered)}
    order = [c for cols in present.values() for c in cols]
    arrays = read_columns(
        data,
        skip_lines=index + 1,
        n_columns=len(names),
        columns=order,
        delimiter=delimiter,
        decimal=decimal,
        name=name,
        column_names=names,
    )
    stacked = {k: np.column_stack(arrays[3 * i : 3 * i + 3]) for i, k in enumerate(present)}
    time = None
    if "time" in lowered:
        col = lowered.index("time")
        rows = [split_row(ln, delimiter) for ln in lines[index + 1 :] if ln.strip()]
        try:
            time = np.array([_clock_seconds(r[col]) for r in rows])
        except (ValueError, IndexError):
            time = None
        if time is not None and len(time) != len(stacked["acc"]):
            time = None
        if time is not None:
            # A clock passing midnight, or mm:ss wrapping at the hour, steps back: unwrap it.
            back = np.diff(time) < -1800
            if back.any():
                period = 86400.0 if ":" in rows[0][col] and rows[0][col].count(":") >= 2 else 3600.0
                time = time + period * np.concatenate([[0], np.cumsum(back)])
    notes = ["g-force columns gFx, gFy, gFz (g)"]
    left = columns_not_read(
        names,
        order + ([lowered.index("time")] if time is not None else []),
        "the linear acceleration ax, ay, az (gravity removed), the total and the other sensors: trical reads the "
        "g-force, the gyroscope and the magnetometer",
    )
    notes += [left] if left else []
    if time is None and "time" in lowered:
        notes.append(f"the time column of {name} could not be read as seconds or a clock: it is not used")
    units = units or {}
    return LogData(
        acc=stacked["acc"],
        gyr=stacked.get("gyr"),
        mag=stacked.get("mag"),
        time_s=None if time is None else time - time[0],
        sampling_rate_hz=None,
        units={
            "acc": units.get("acc") or "g",
            **{k: units.get(k) or {"gyr": "rad/s", "mag": "uT"}[k] for k in stacked if k != "acc"},
        },
        format=NAME,
        columns=names,
        notes=tuple(notes),
    )
