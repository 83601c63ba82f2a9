"""Sensor Logger (Tsz Hei Choi) exports: one CSV per sensor, or the zip of a recording's folder.

Each sensor's CSV has ``time`` (UNIX epoch, nanoseconds), ``seconds_elapsed``, then ``z, y, x``.
Which accelerometer file holds gravity (awesome-sensor-logger UNITS.md, CROSSPLATFORM.md):

* ``TotalAcceleration.csv`` (Android): with gravity, m/s².
* ``AccelerometerUncalibrated.csv``: with gravity; in g on iOS unless "Standardise Units & Frames"
  is on, m/s² otherwise.
* ``Accelerometer.csv``: user acceleration *without* gravity on both platforms — refused.

A magnetometer recorded alone (``MagnetometerUncalibrated.csv`` or ``Magnetometer.csv``, µT, on its
own or in a zip without an accelerometer file) is read as a magnetometer-only log, for the compass.

iOS and Android differ by a sign on all three acceleration axes; with "Standardise Units & Frames"
on, iOS follows Android (+g on the up axis, docs/methods.md).  The zip's ``Metadata.csv`` gives
``platform`` and the standardisation flag (a column whose name contains ``standardi``, e.g.
``standardisation``; absent in exports older than the option, meaning off).  The sign is flipped
only when the data confirm the platform: a raw iOS stream is the only one in g, so readings in g
without standardisation are iOS readings and get flipped; readings in m/s² are on the Android sign.
When the metadata and the data disagree, the file is refused rather than guessed.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from ..errors import LogFormatError
from ..log import LogData
from .table import Sniff, find_member, read_columns, read_member, resample_to, split_row
from .units import infer_acc_unit, median_norm, refuse_linear_acceleration

NAME = "sensor_logger"
METADATA = "Metadata.csv"
ACC_FILES = ("TotalAcceleration.csv", "AccelerometerUncalibrated.csv")
LINEAR_FILE = "Accelerometer.csv"
GYR_FILES = ("GyroscopeUncalibrated.csv", "Gyroscope.csv")
MAG_FILES = ("MagnetometerUncalibrated.csv", "Magnetometer.csv")
_TRUE = {"true", "1", "yes", "on", "enabled"}


def _is_sensor_header(line: str) -> bool:
    names = [n.lower() for n in split_row(line, ",")]
    return {"time", "seconds_elapsed", "x", "y", "z"} <= set(names)


def detect(s: Sniff) -> bool:
    """A zip with ``Metadata.csv`` and an accelerometer CSV, or a header ``time,seconds_elapsed,z,y,x``."""
    if s.is_zip:
        return (
            find_member(s.members, METADATA) is not None
            and find_member(s.members, *ACC_FILES, LINEAR_FILE, *MAG_FILES) is not None
        )
    first = next((line for line in s.lines if line.strip()), "")
    return _is_sensor_header(first)


def read_metadata(data: bytes) -> dict[str, str]:
    """``Metadata.csv`` (a header row and one value row) as a dict with lower-case keys."""
    rows = list(csv.reader(io.StringIO(data.decode("utf-8-sig", errors="replace"))))
    rows = [r for r in rows if any(c.strip() for c in r)]
    if len(rows) < 2:
        return {}
    return {k.strip().lower(): v.strip() for k, v in zip(rows[0], rows[1])}


def _read_sensor(data: bytes, label: str) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Epoch time in ns and the (N, 3) x, y, z values of one sensor CSV."""
    lines = data.decode("utf-8-sig", errors="replace").splitlines()
    index = next((i for i, line in enumerate(lines) if line.strip()), None)
    if index is None or not _is_sensor_header(lines[index]):
        raise LogFormatError(
            f"{label} is not a Sensor Logger sensor file: its header must hold time, seconds_elapsed, z, y, x"
        )
    names = split_row(lines[index], ",")
    lowered = [n.lower() for n in names]
    cols = [lowered.index(c) for c in ("time", "x", "y", "z")]
    time_ns, x, y, z = read_columns(
        data,
        skip_lines=index + 1,
        n_columns=len(names),
        columns=cols,
        delimiter=",",
        name=label,
        column_names=names,
        integer_columns=(cols[0],),
    )
    return time_ns, np.column_stack([x, y, z]), names


def _sign_and_unit(
    acc: np.ndarray, meta: dict[str, str] | None, acc_file: str | None, caller_unit: str | None, label: str
) -> tuple[float, str, list[str]]:
    """The factor (+1 or −1) and unit of the accelerometer readings, from the data and the metadata."""
    data_unit = infer_acc_unit(acc)
    unit = caller_unit or data_unit
    if unit is None and median_norm(acc) < 0.6:
        unit = "m/s^2"  # well below 1 g in either unit: no gravity, refused just below
    if unit is None:
        raise LogFormatError(
            f"the accelerometer readings of {label} are neither about 1 g nor about 9.8 m/s² in norm: give "
            "acc_unit (g or m/s^2)"
        )
    refuse_linear_acceleration(
        acc,
        unit,
        label,
        hint="in Sensor Logger, enable 'Accelerometer Uncalibrated' (iOS) or use TotalAcceleration.csv (Android)",
    )
    notes: list[str] = []
    if meta:
        platform = meta.get("platform", "").lower()
        flag = next((v for k, v in meta.items() if "standardi" in k), "")
        standardised = flag.lower() in _TRUE
        ios_raw = platform == "ios" and not standardised
        if platform not in ("ios", "android"):
            raise LogFormatError(
                f"Metadata.csv gives platform {meta.get('platform')!r}, not iOS or Android: "
                "the acceleration sign cannot be decided; upload the original export"
            )
        if ios_raw and unit != "g":
            raise LogFormatError(
                f"Metadata.csv says iOS without 'Standardise Units & Frames', but {acc_file or label} reads "
                f"in {unit}, not g: the export looks edited; upload the original zip"
            )
        if not ios_raw and unit == "g" and caller_unit is None:
            raise LogFormatError(
                f"Metadata.csv says {meta.get('platform')} (standardisation {'on' if standardised else 'off'}), "
                f"but {acc_file or label} reads in g, which only raw iOS exports do: upload the original zip"
            )
        sign = -1.0 if ios_raw else 1.0
        notes.append(f"platform {meta.get('platform')}, standardisation {'on' if standardised else 'off'}")
    else:
        # Without metadata the data decide: only the raw iOS stream is in g (and on the iOS sign).
        sign = -1.0 if data_unit == "g" else 1.0
        notes.append("no Metadata.csv: sign decided from the unit of the data (g: raw iOS stream)")
    if sign < 0:
        notes.append("iOS sign flipped to +g on the up axis")
    return sign, unit, notes


def _is_magnetometer_file(name: str) -> bool:
    """Sensor Logger names each sensor's CSV after the sensor (``MagnetometerUncalibrated.csv``)."""
    return "magnetometer" in Path(name).name.lower()


def _magnetometer_only(
    time_ns: np.ndarray, mag: np.ndarray, names: list[str], units: dict[str, str], notes: list[str]
) -> LogData:
    """A recording of the magnetometer alone (a compass calibration's turn), in µT."""
    time_s = (time_ns - time_ns[0]).astype(float) * 1e-9
    return LogData(
        acc=None,
        gyr=None,
        mag=mag,
        time_s=time_s,
        sampling_rate_hz=None,
        units={"mag": units.get("mag") or "uT"},
        format=NAME,
        columns=names,
        notes=tuple(notes + ["the magnetometer alone (no accelerometer file)"]),
    )


def read(path: Path, s: Sniff, *, units: dict[str, str] | None = None, name: str = "the file") -> LogData:
    """Read a Sensor Logger per-sensor CSV or the zip of a recording.

    Parameters
    ----------
    path : pathlib.Path
        The file (a sensor's CSV, or the zip of a recording).
    s : Sniff
        Its head: the zip's members.
    units : dict, optional
        The caller's units by sensor, over the format's (m/s^2 or g by the data and Metadata.csv, rad/s, µT);
        the rate, the counts and the sign are :func:`app.io.readers.read_log`'s.
    name : str
        How to call the file in messages.

    Returns
    -------
    LogData
        The accelerometer's samples (or a magnetometer's alone), the others on its times, ``sign`` the iOS
        flip decided, ``format`` ``sensor_logger``.
    """
    units = units or {}
    extra: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    if s.is_zip:
        meta_member = find_member(s.members, METADATA)
        if meta_member is None:
            raise LogFormatError(f"{name} holds no {METADATA}: give Sensor Logger's zip export as it saved it")
        meta = read_metadata(read_member(path, meta_member, name))
        member = find_member(s.members, *ACC_FILES)
        mag_member = find_member(s.members, *MAG_FILES)
        if member is None and mag_member is not None and find_member(s.members, LINEAR_FILE) is None:
            label = f"{mag_member} in {name}"
            time_ns, mag, names = _read_sensor(read_member(path, mag_member, name), label)
            return _magnetometer_only(time_ns, mag, names, units, [f"read {mag_member} from the Sensor Logger zip"])
        if member is None:
            raise LogFormatError(
                f"{name} holds only {LINEAR_FILE}, Sensor Logger's acceleration without gravity (linear "
                "acceleration): calibration needs gravity in the readings: enable 'Accelerometer "
                "Uncalibrated' (iOS) or record TotalAcceleration (Android) and export again"
            )
        label = f"{member} in {name}"
        time_ns, acc, names = _read_sensor(read_member(path, member, name), label)
        for sensor, files in (("gyr", GYR_FILES), ("mag", MAG_FILES)):
            other = find_member(s.members, *files)
            if other is not None:
                t_o, v_o = _read_sensor(read_member(path, other, name), f"{other} in {name}")[:2]
                extra[sensor] = (t_o, v_o)
        notes = [f"read {member} from the Sensor Logger zip"]
        read = {meta_member, member, *(find_member(s.members, *files) for files in (GYR_FILES, MAG_FILES))}
        left = [m for m in s.members or () if m not in read and not m.endswith("/") and "__macosx" not in m.lower()]
        if left:
            notes.append(
                f"{len(left)} file{'s' if len(left) > 1 else ''} of the zip not read: {', '.join(left[:12])}"
                + (f" and {len(left) - 12} more" if len(left) > 12 else "")
                + " (Sensor Logger's other sensors and its derived streams: trical reads the accelerometer with "
                "gravity, the gyroscope and the magnetometer)"
            )
    else:
        meta, member, label = None, None, name
        time_ns, acc, names = _read_sensor(path.read_bytes(), label)
        if _is_magnetometer_file(name):
            return _magnetometer_only(time_ns, acc, names, units, [])
        notes = []
    sign, unit, sign_notes = _sign_and_unit(acc, meta, member, units.get("acc"), label)
    notes += sign_notes
    # Streams share the epoch clock: the others are interpolated at the accelerometer's samples.
    time_s = (time_ns - time_ns[0]).astype(float) * 1e-9
    aligned = {k: resample_to(time_s, (t - time_ns[0]).astype(float) * 1e-9, v) for k, (t, v) in extra.items()}
    return LogData(
        acc=sign * acc,
        sign=int(sign),
        gyr=aligned.get("gyr"),
        mag=aligned.get("mag"),
        time_s=time_s,
        sampling_rate_hz=None,
        units={"acc": unit, **{k: units.get(k) or {"gyr": "rad/s", "mag": "uT"}[k] for k in aligned}},
        format=NAME,
        columns=names,
        notes=tuple(notes),
    )
