"""SensorLog (Bernd Thomas; iPhone and Apple Watch): one CSV row per sample, one column per Core Motion value.

The header names each value with its unit, e.g. ``loggingTime(txt),loggingSample(N),
accelerometerTimestamp_sinceReboot(s),accelerometerAccelerationX(G),…,motionUserAccelerationX(G),…,
motionGravityX(G),…,gyroTimestamp_sinceReboot(s),gyroRotationX(rad/s),…,magnetometerX(µT),…``.
trical reads the raw streams — ``accelerometerAcceleration*`` (``CMAccelerometerData``, g),
``gyroRotation*`` (``CMGyroData``, rad/s) and ``magnetometer*`` (``CMMagnetometerData``, µT) — with
the accelerometer's own timestamps; the ``motion*`` values are Core Motion's fused estimates and are
not used.  The accelerations are on Core Motion's sign (−1 g on the up axis): :mod:`.ios_sign`
negates them in :func:`app.io.readers.read_log` unless the caller gives ``sign=1``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import LogFormatError
from ..log import LogData
from .table import Sniff, columns_not_read, first_row, guess_decimal, read_columns

NAME = "sensorlog"
TIME = "accelerometertimestamp_sincereboot(s)"
STREAMS = {
    "acc": (tuple(f"accelerometeracceleration{a}(g)" for a in "xyz"), "g"),
    "gyr": (tuple(f"gyrorotation{a}(rad/s)" for a in "xyz"), "rad/s"),
    "mag": (tuple(f"magnetometer{a}(µt)" for a in "xyz"), "uT"),
}


def detect(s: Sniff) -> bool:
    """A header naming SensorLog's ``accelerometerAccelerationX(G)``, ``…Y(G)`` and ``…Z(G)``."""
    if s.is_zip:
        return False
    found = first_row(s.lines)
    return found is not None and set(STREAMS["acc"][0]) <= {n.lower() for n in found[2]}


NOT_READ = (
    "SensorLog's fused motion values, its location and its other sensors and fields: trical reads the raw "
    "accelerometer, gyroscope and magnetometer"
)


def read(path: Path, s: Sniff, *, units: dict[str, str] | None = None, name: str = "the file") -> LogData:
    """Read the raw accelerometer (and gyroscope, magnetometer) columns of a SensorLog CSV.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    s : Sniff
        Its head: its header row.
    units : dict, optional
        The caller's units by sensor, over the format's (g, rad/s, µT); the rate, the counts and the sign are
        :func:`app.io.readers.read_log`'s.
    name : str
        How to call the file in messages.

    Returns
    -------
    LogData
        Its samples on the accelerometer's timestamps, on Core Motion's sign, ``format`` ``sensorlog``.
    """
    found = first_row(s.lines)
    if found is None or not detect(s):
        raise LogFormatError(
            f"{name} is not a SensorLog CSV: its header must name accelerometerAccelerationX(G), "
            "accelerometerAccelerationY(G) and accelerometerAccelerationZ(G)"
        )
    index, delimiter, names = found
    lowered = [n.lower().replace("μ", "µ") for n in names]  # Greek mu or the micro sign
    present = {k: [lowered.index(c) for c in cols] for k, (cols, _) in STREAMS.items() if set(cols) <= set(lowered)}
    order = ([lowered.index(TIME)] if TIME in lowered else []) + [c for cols in present.values() for c in cols]
    arrays = read_columns(
        Path(path),
        skip_lines=index + 1,
        n_columns=len(names),
        columns=order,
        delimiter=delimiter,
        decimal=guess_decimal(s.lines[index + 1 :], delimiter),
        name=name,
        column_names=names,
    )
    time = arrays.pop(0) if TIME in lowered else None
    stacked = {k: np.column_stack(arrays[3 * i : 3 * i + 3]) for i, k in enumerate(present)}
    units = units or {}
    return LogData(
        acc=stacked["acc"],
        gyr=stacked.get("gyr"),
        mag=stacked.get("mag"),
        time_s=None if time is None else time - time[0],
        sampling_rate_hz=None,
        units={k: units.get(k) or STREAMS[k][1] for k in stacked},
        format=NAME,
        columns=names,
        notes=tuple(filter(None, [columns_not_read(names, order, NOT_READ)])),
    )
