"""Google GnssLogger (Android) text logs: the ``UncalAccel``, ``UncalGyro`` and ``UncalMag`` lines.

Every line starts with its record type; the file's ``#`` header describes each type, e.g.
``# UncalAccel,utcTimeMillis,elapsedRealtimeNanos,UncalAccelXMps2,UncalAccelYMps2,UncalAccelZMps2,
BiasXMps2,BiasYMps2,BiasZMps2``.  The uncalibrated readings (Android sensor frame, m/s², +g on the
up axis) are what trical calibrates; the platform's bias estimate is left out, since trical fits the
offset itself.  Gyroscope (rad/s) and magnetometer (µT) lines are interpolated at the accelerometer's
``elapsedRealtimeNanos``; a log of ``UncalMag`` lines alone (the magnetometer's hard-iron estimate
``BiasX/Y/ZMicroT`` left out too) is a magnetometer-only log, for the compass.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import LogFormatError
from ..log import LogData
from .table import Sniff, resample_to

NAME = "gnss_logger"
RECORDS = {
    "acc": ("UncalAccel", ("UncalAccelXMps2", "UncalAccelYMps2", "UncalAccelZMps2"), "m/s^2"),
    "gyr": ("UncalGyro", ("UncalGyroXRadPerSec", "UncalGyroYRadPerSec", "UncalGyroZRadPerSec"), "rad/s"),
    "mag": ("UncalMag", ("UncalMagXMicroT", "UncalMagYMicroT", "UncalMagZMicroT"), "uT"),
}
TIME = "elapsedRealtimeNanos"


def detect(s: Sniff) -> bool:
    """A line starting with ``UncalAccel,`` or ``UncalMag,`` (or their ``#`` headers) in the first 64 KiB."""
    if s.is_zip:
        return False
    return any(line.lstrip("# ").startswith(("UncalAccel,", "UncalMag,")) for line in s.text.splitlines())


def _layouts(lines: list[str]) -> dict[str, list[str]]:
    """Column names per record type, from the ``#`` header lines."""
    out = {}
    for line in lines:
        if line.startswith("#"):
            fields = [f.strip() for f in line.lstrip("# ").split(",")]
            if len(fields) > 1 and fields[0] in {r[0] for r in RECORDS.values()}:
                out[fields[0]] = fields
    return out


def _records(
    lines: list[tuple[int, str]], record: str, layout: list[str], columns: tuple[str, ...], name: str
) -> tuple[np.ndarray, np.ndarray]:
    want = [layout.index(TIME)] + [layout.index(c) for c in columns]
    rows = []
    for number, line in lines:
        fields = line.split(",")
        try:
            rows.append([float(fields[i]) for i in want])
        except (ValueError, IndexError):
            raise LogFormatError(
                f"{name}: line {number} ({record}) does not hold numbers in the columns "
                f"{', '.join([TIME, *columns])}: fix or remove that line"
            ) from None
    arr = np.asarray(rows, dtype=float)
    return arr[:, 0], arr[:, 1:]


def read(path: Path, s: Sniff, *, units: dict[str, str] | None = None, name: str = "the file") -> LogData:
    """Read the uncalibrated accelerometer (and gyroscope, magnetometer) lines of a GnssLogger file.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    s : Sniff
        Its head (unused: the file is read whole).
    units : dict, optional
        The caller's units by sensor, over the format's (the records'); the rate, the counts and the sign are
        :func:`app.io.readers.read_log`'s.
    name : str
        How to call the file in messages.

    Returns
    -------
    LogData
        Each sensor's samples on the accelerometer's times, ``format`` ``gnss_logger``.
    """
    with open(path, encoding="utf-8-sig", errors="replace") as f:
        lines = f.read().splitlines()
    layouts = _layouts(lines)
    by_type: dict[str, list[tuple[int, str]]] = {}
    for number, line in enumerate(lines, start=1):
        head = line.split(",", 1)[0]
        if head in ("UncalAccel", "UncalGyro", "UncalMag"):
            by_type.setdefault(head, []).append((number, line))
    streams = {}
    for sensor, (record, columns, _unit) in RECORDS.items():
        if record not in by_type:
            continue
        layout = layouts.get(record) or [record, "utcTimeMillis", TIME, *columns]
        missing = [c for c in (TIME, *columns) if c not in layout]
        if missing:
            raise LogFormatError(
                f"the {record} header of {name} lacks {', '.join(missing)}: it names {', '.join(layout[1:])}"
            )
        streams[sensor] = _records(by_type[record], record, layout, columns, name)
    if "acc" not in streams and "mag" not in streams:
        raise LogFormatError(
            f"{name} holds no UncalAccel (or UncalMag) lines: in GnssLogger, enable the sensor logging of the "
            "uncalibrated accelerometer (or magnetometer) and record again"
        )
    base = "acc" if "acc" in streams else "mag"  # the magnetometer alone: a compass calibration's turn
    t_acc, acc = streams.pop(base)
    t0 = t_acc[0]
    time_s = (t_acc - t0) * 1e-9
    aligned = {k: resample_to(time_s, (t - t0) * 1e-9, v) for k, (t, v) in streams.items()}
    units = units or {}
    arrays = {base: acc, **aligned}
    return LogData(
        acc=arrays.get("acc"),
        gyr=arrays.get("gyr"),
        mag=arrays.get("mag"),
        time_s=time_s,
        sampling_rate_hz=None,
        units={k: units.get(k) or RECORDS[k][2] for k in arrays},
        format=NAME,
        columns=list(layouts.get(RECORDS[base][0]) or []),
        notes=(f"{RECORDS[base][0]} readings without the platform's bias estimate",),
    )
