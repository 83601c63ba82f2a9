"""Generic CSV logs: a header row naming the columns, then one sample per line.

Accelerometer columns are recognised by names such as ``acc_x``, ``ax``, ``x`` or
``Acceleration x (m/s^2)``; gyroscope (``gyr_x``, ``gx``, ``Gyroscope x (rad/s)``) and magnetometer
(``mag_x``, ``mx``, ``Magnetic field x (µT)``) columns are optional.  An optional leading index or
time column (seconds, milliseconds, microseconds or nanoseconds) gives the sampling rate; without
one, the caller gives ``sampling_rate_hz``.  Error messages name lines 1-based, the header being
line 1 (comment lines starting with ``#`` before the header count too).
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np

from .errors import LogFormatError
from .log import UNITS, LogData

SNIFF_BYTES = 64 * 1024
MAX_LISTED_COLUMNS = 20
DELIMITERS = (",", ";", "\t")

_AXIS = r"[ _.\-]?(?:\(?)(?P<axis>[xyz])(?:\)?)"
_UNIT = r"(?:\s*[\(\[](?P<unit>[^\)\]]*)[\)\]])?"
_PATTERNS = {
    "acc": re.compile(rf"^(?:acc|accel|accelerometer|acceleration|a)?{_AXIS}(?:[ _]?axis)?{_UNIT}$"),
    "gyr": re.compile(rf"^(?:gyr|gyro|gyroscope|g|angular[ _]velocity|rotation[ _]rate|w){_AXIS}(?:[ _]?axis)?{_UNIT}$"),
    "mag": re.compile(rf"^(?:mag|magn|magnetometer|magnetic[ _]field|m|b){_AXIS}(?:[ _]?axis)?{_UNIT}$"),
}
_TIME = re.compile(
    r"^(?:t|time|timestamp|times|elapsed|seconds_elapsed|time_elapsed)"
    r"(?:[ _]?(?P<suffix>s|sec|ms|us|ns))?(?:\s*[\(\[](?P<unit>[^\)\]]*)[\)\]])?$"
)
_INDEX = re.compile(r"^(?:index|idx|i|n|sample|sample_index|#)$")
_LINEAR = re.compile(r"linear|user[ _]?acc|without[ _]g|gravity[ _]removed")

_UNIT_ALIASES = {
    "m/s^2": "m/s^2", "m/s2": "m/s^2", "m/s²": "m/s^2", "ms^-2": "m/s^2", "m s^-2": "m/s^2",
    "g": "g", "rad/s": "rad/s", "deg/s": "deg/s", "°/s": "deg/s", "dps": "deg/s",
    "ut": "uT", "µt": "uT", "μt": "uT", "nt": "nT", "raw": "raw", "lsb": "raw", "counts": "raw",
}
_TIME_SCALE = {"s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "ns": 1e-9}


def _normalise(name: str) -> str:
    return re.sub(r"\s+", " ", name.strip().strip('"').strip().lower())


def _header_unit(text: str | None) -> str | None:
    if not text:
        return None
    return _UNIT_ALIASES.get(text.strip().lower().replace(" ", ""), None)


def _decode_head(head: bytes, name: str) -> str:
    if not head.strip():
        raise LogFormatError(f"{name} is empty: upload a CSV with a header row and one sample per line")
    if b"\x00" in head:
        raise LogFormatError(
            f"{name} is not a text file (it holds NUL bytes): upload a CSV log with a header row",
            status=415,
        )
    try:
        return head.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        # A multi-byte character cut by the sniff window is fine; anything earlier is binary.
        if exc.start < len(head) - 4:
            raise LogFormatError(
                f"{name} is not UTF-8 text (byte {exc.start}): upload a CSV log with a header row",
                status=415,
            ) from None
        return head[: exc.start].decode("utf-8-sig")


def _split_header(text: str) -> tuple[int, str, list[str]]:
    """Line number (1-based) of the header, the delimiter and the column names."""
    lines = text.splitlines()
    for number, line in enumerate(lines, start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        delimiter = max(DELIMITERS, key=line.count)
        if line.count(delimiter) == 0:
            raise LogFormatError(
                f"line {number} {line[:80]!r} is not a header of comma-, semicolon- or tab-separated "
                "columns: the first line must name the columns, e.g. acc_x,acc_y,acc_z"
            )
        names = next(csv.reader([line], delimiter=delimiter))
        return number, delimiter, names
    raise LogFormatError("the file holds no header row: the first line must name the columns, e.g. acc_x,acc_y,acc_z")


def _map_columns(names: list[str]) -> tuple[dict, int | None, float | None, dict]:
    """Find the sensor, time and index columns; returns (channels, time column, time scale, units)."""
    channels: dict[str, dict[str, int]] = {}
    units: dict[str, str] = {}
    time_col = time_scale = None
    for col, raw in enumerate(names):
        name = _normalise(raw)
        m = _TIME.match(name)
        if m and time_col is None:
            time_col = col
            unit = (m.group("unit") or m.group("suffix") or "").strip().lower()
            time_scale = _TIME_SCALE.get(unit)
            continue
        if _INDEX.match(name):
            continue
        for sensor, pattern in _PATTERNS.items():
            m = pattern.match(name)
            if m:
                channels.setdefault(sensor, {}).setdefault(m.group("axis"), col)
                unit = _header_unit(m.group("unit"))
                if unit:
                    units.setdefault(sensor, unit)
                break
    if any(_LINEAR.search(_normalise(n)) for n in names) and "acc" not in channels:
        raise LogFormatError(
            "the accelerometer columns hold linear acceleration (gravity removed); calibration needs "
            "the raw accelerometer including gravity: export 'acceleration including gravity' instead"
        )
    acc = channels.get("acc", {})
    if set(acc) != {"x", "y", "z"}:
        listed = ", ".join(repr(n[:40]) for n in names[:MAX_LISTED_COLUMNS])
        if len(names) > MAX_LISTED_COLUMNS:
            listed += f" and {len(names) - MAX_LISTED_COLUMNS} more"
        raise LogFormatError(
            f"no accelerometer x, y and z columns among the header's columns {listed}: name them "
            "acc_x, acc_y, acc_z (or ax, ay, az, or x, y, z), optionally with a time column "
            "time_s / time_ms / time_ns, or map them without editing the file with the upload field "
            "columns, e.g. columns=acc_x:<name>,acc_y:<name>,acc_z:<name>,time_ms:<name>. Exports of "
            "phyphox, Sensor Logger, Physics Toolbox, GnssLogger and the Arduino Serial Plotter are "
            "recognised as they are"
        )
    partial = [s for s, axes in channels.items() if s != "acc" and set(axes) != {"x", "y", "z"}]
    for sensor in partial:
        del channels[sensor]
    return channels, time_col, time_scale, units


def _renamed(names: list[str], column_map: dict | None) -> list[str]:
    """The header with the columns of ``column_map`` (canonical name → file column) renamed."""
    if not column_map:
        return names
    stripped = [n.strip().strip('"').strip() for n in names]
    out = list(names)
    for canonical, column in column_map.items():
        if column not in stripped:
            listed = ", ".join(repr(n) for n in stripped)
            raise LogFormatError(f"columns maps {canonical} to {column!r}, which is not a column of the header "
                                 f"({listed}): use one of those names")
        out[stripped.index(column)] = canonical
    return out


def _first_bad_line(path: Path, header_line: int, delimiter: str, columns: list[int], names: list[str]) -> str:
    """Describe the first line whose used columns are not all numbers (slow path, errors only)."""
    try:
        return _scan_for_bad_line(path, header_line, delimiter, columns, names)
    except csv.Error as exc:
        return f"a line after the header could not be read as delimited text ({exc}; lines are limited to {csv.field_size_limit()} characters per field)"


def _scan_for_bad_line(path: Path, header_line: int, delimiter: str, columns: list[int], names: list[str]) -> str:
    with open(path, encoding="utf-8-sig", errors="replace", newline="") as f:
        for number, row in enumerate(csv.reader(f, delimiter=delimiter), start=1):
            if number <= header_line or not row or (len(row) == 1 and not row[0].strip()):
                continue
            if row[0].lstrip().startswith("#"):
                continue
            if len(row) < len(names):
                return f"line {number} has {len(row)} columns but the header names {len(names)}"
            for col in columns:
                value = row[col].strip()
                try:
                    float(value)
                except ValueError:
                    return f"line {number}, column {names[col]!r}: {value[:40]!r} is not a number"
    return "a line could not be read as numbers"


def read_csv_log(path: Path, *, sampling_rate_hz: float | None = None, units: dict | None = None,
                 name: str = "the file", column_map: dict | None = None) -> LogData:
    """Read a generic CSV log into arrays.

    Parameters
    ----------
    path : pathlib.Path
        The CSV file.
    sampling_rate_hz : float, optional
        Required when the file has no time column; overrides the rate the time column gives.
    units : dict, optional
        Units per sensor (``{"acc": "g"}``); override those named in the header.
    name : str
        How to call the file in messages.
    column_map : dict, optional
        Canonical names for the file's columns, ``{"acc_x": "north", ...}``: the named columns are
        read as if the header called them so.

    Raises
    ------
    LogFormatError
        Empty, binary or header-only files, unrecognised columns, a mapped column the header lacks, text in a numeric column
        (with its line number), a missing sampling rate.
    """
    import pyarrow as pa  # here, not at the top: .npy logs need no pyarrow
    import pyarrow.csv as pacsv

    with open(path, "rb") as f:
        head = f.read(SNIFF_BYTES)
    text = _decode_head(head, name)
    header_line, delimiter, names = _split_header(text)
    channels, time_col, time_scale, header_units = _map_columns(_renamed(names, column_map))

    used = [time_col] if time_col is not None else []
    for sensor in ("acc", "gyr", "mag"):
        if sensor in channels:
            used += [channels[sensor][a] for a in "xyz"]
    column_names = [f"c{i}" for i in range(len(names))]
    try:
        table = pacsv.read_csv(
            path,
            read_options=pacsv.ReadOptions(skip_rows=header_line, column_names=column_names, block_size=1 << 22),
            parse_options=pacsv.ParseOptions(delimiter=delimiter, ignore_empty_lines=True),
            convert_options=pacsv.ConvertOptions(
                include_columns=[column_names[c] for c in used],
                column_types={column_names[c]: pa.float64() for c in used},
                null_values=["", "nan", "NaN", "NA"],
                strings_can_be_null=False,
            ),
        )
    except (pa.ArrowInvalid, pa.ArrowTypeError, UnicodeDecodeError) as exc:
        detail = _first_bad_line(path, header_line, delimiter, used, names)
        raise LogFormatError(f"{detail}: every used column must hold numbers") from None
    if table.num_rows == 0:
        raise LogFormatError(f"{name} has a header (line {header_line}) but no data rows: add the samples below it")

    def column(c: int) -> np.ndarray:
        return table.column(column_names[c]).to_numpy(zero_copy_only=False).astype(float, copy=False)

    arrays = {s: np.column_stack([column(channels[s][a]) for a in "xyz"]) for s in channels}
    for sensor, arr in arrays.items():
        bad = ~np.isfinite(arr).all(axis=1)
        if bad.any():
            row = int(np.flatnonzero(bad)[0])
            raise LogFormatError(
                f"data row {row + 1} (line {header_line + 1 + row} if the file has no blank lines) has an "
                f"empty or non-finite {sensor} value: fill or remove that line"
            )
    time = column(time_col) if time_col is not None else None
    rate = _sampling_rate(time, time_scale, sampling_rate_hz)

    final_units = {s: (units or {}).get(s) or header_units.get(s) or UNITS[s][0] for s in arrays}
    for sensor, unit in final_units.items():
        if unit not in UNITS[sensor]:
            raise LogFormatError(f"{sensor} unit {unit!r} is not one of {', '.join(UNITS[sensor])}")
    return LogData(
        acc=arrays["acc"],
        gyr=arrays.get("gyr"),
        mag=arrays.get("mag"),
        time_s=None if time is None else (time - time[0]) * (time_scale or _infer_scale(time)),
        sampling_rate_hz=rate,
        units=final_units,
        format="csv",
        columns=names,
    )


def _infer_scale(time: np.ndarray) -> float:
    """Seconds per time unit, inferred from the median step when the header does not say."""
    steps = np.diff(time)
    steps = steps[np.isfinite(steps) & (steps > 0)]
    if len(steps) == 0:
        raise LogFormatError("the time column does not increase: give sampling_rate_hz or fix the time column")
    dt = float(np.median(steps))
    # Plausible sampling rates are 1 Hz to 10 kHz: pick the unit that puts the step in that range.
    for scale in (1.0, 1e-3, 1e-6, 1e-9):
        if 1e-4 <= dt * scale <= 1.0:
            return scale
    raise LogFormatError(
        f"the time column's median step {dt:g} fits no unit (s, ms, µs, ns) for a rate between 1 Hz and "
        "10 kHz: name its unit in the header (time_s, time_ms, time_ns) or give sampling_rate_hz"
    )


def _sampling_rate(time, time_scale, sampling_rate_hz) -> float:
    if sampling_rate_hz is not None:
        if not (np.isfinite(sampling_rate_hz) and sampling_rate_hz > 0):
            raise LogFormatError(f"sampling_rate_hz must be a positive number; got {sampling_rate_hz}")
        return float(sampling_rate_hz)
    if time is None:
        raise LogFormatError(
            "the file has no time column, so its sampling rate is unknown: give sampling_rate_hz "
            "(a form field of the upload, --sampling-rate-hz on the command line)"
        )
    if len(time) < 2:
        raise LogFormatError("one sample has no sampling rate: give sampling_rate_hz")
    scale = time_scale or _infer_scale(time)
    steps = np.diff(time) * scale
    steps = steps[steps > 0]
    if len(steps) == 0:
        raise LogFormatError("the time column does not increase: give sampling_rate_hz or fix the time column")
    return float(1.0 / np.median(steps))

