"""Generic and Arduino CSV logs: a header row naming the columns (or none), readings in g, m/s² or LSB.

Accelerometer columns are recognised by names such as ``acc_x``, ``ax``, ``x`` or
``Acceleration x (m/s^2)``; gyroscope (``gyr_x``, ``gx``, ``Gyroscope x (rad/s)``) and magnetometer
(``mag_x``, ``mx``, ``Magnetic field x (µT)``) columns are optional.  An optional leading index or
time column (seconds, milliseconds, microseconds or nanoseconds) gives the sampling rate; without
one, the caller gives ``sampling_rate_hz``.  Error messages name lines 1-based, the header being
line 1 (comment lines starting with ``#`` or ``@`` before the header count too).  Parquet files name their
columns the same way (:mod:`app.io.readers.arrays` uses :func:`map_columns`).

Loggers often write no header row: numbers from the first line, separated by commas, semicolons,
tabs or spaces (runs of blanks, as in aligned tables), with a decimal point or — with any separator
but a comma — a decimal comma (``0,25;9,81``).  Which column is which is read from the data
(:mod:`.columns`: a time, a temperature, and an accelerometer, gyroscope or magnetometer for each
three others; the file's name breaks a tie, a 422 asks where the data leave two readings), or given
with ``columns`` — one name per column in order, ``t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z``
(:func:`table_layout`).  A first line with text among numbers is a bad line, named as such.  Numbers with decimal
commas between comma separators cannot be told apart and are refused by their column count.

The unit comes from the caller, else the header (``acc_x (g)``, ``mag_x (G)`` for gauss); the
data then have the last word (:func:`app.io.readers.units.settle_units`).  Readings in counts (LSB)
become g with the sensor's sensitivity, given as ``lsb_per_g`` or ``chip`` by the caller or in a
comment line of the file such as ``# MPU-6050 ±2 g, lsb_per_g=16384``.

The *arduino* format adds the Arduino IDE Serial Plotter's ``label:value`` lines
(``ax:-112 ay:35 az:16490``, separated by spaces, tabs or commas) to the CSV layout.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import LogFormatError
from ..log import UNITS, UNITS_IN, LogData
from .columns import PREVIEW_LINES, ColumnsAmbiguous, guess_columns
from .table import (
    BAD_LINE,
    SKIP,
    SNIFF_BYTES,
    WHITESPACE,
    Sniff,
    columns_not_read,
    decode_head,
    guess_decimal,
    guess_delimiter,
    is_comment,
    listed_columns,
    numeric_layout,
    read_columns,
    split_row,
    text_block_cell,
)
from .timing import time_scale as infer_time_scale
from .timing import with_timing

_AXIS = r"[ _.\-]?(?:\(?)(?P<axis>[xyz])(?:\)?)"
_UNIT = r"(?:\s*[\(\[](?P<unit>[^\)\]]*)[\)\]])?"
PATTERNS = {
    "acc": re.compile(rf"^(?:acc|accel|accelerometer|acceleration|a)?{_AXIS}(?:[ _]?axis)?{_UNIT}$"),
    "gyr": re.compile(
        rf"^(?:gyr|gyro|gyroscope|g|angular[ _]velocity|rotation[ _]rate|w){_AXIS}(?:[ _]?axis)?{_UNIT}$"
    ),
    "mag": re.compile(rf"^(?:mag|magn|magnetometer|magnetic[ _]field|m|b){_AXIS}(?:[ _]?axis)?{_UNIT}$"),
}
_TIME = re.compile(
    r"^(?:t|time|timestamp|times|elapsed|seconds_elapsed|time_elapsed)"
    r"(?:[ _]?(?P<suffix>s|sec|ms|us|ns))?(?:\s*[\(\[](?P<unit>[^\)\]]*)[\)\]])?$"
)
_TEMPERATURE = re.compile(
    r"^(?:temp|temperature|temp_c|t_c|imu_temp|temperature_c)(?:\s*[\(\[](?:°\s*c|deg\s*c|degc|c)[\)\]])?$"
    r"|^t\s*[\(\[](?:°\s*c|deg\s*c|degc)[\)\]]$"
)
"""A column of the sensor's temperature in °C (``temp_c``, ``temp``, ``temperature``, ``T (°C)``)."""
_INDEX = re.compile(r"^(?:index|idx|i|n|sample|sample_index|#)$")
_LINEAR = re.compile(r"linear|user[ _]?acc|without[ _]g|gravity[ _]removed")
_CHIP = r"(?:_[a-z0-9]+)*?"
_NAMED = {
    "acc": re.compile(rf"^(?:scaled|raw|imu)?[ _]?(?:accel|accelerometer){_CHIP}{_AXIS}$"),
    "gyr": re.compile(rf"^(?:scaled|raw|imu)?[ _]?(?:gyro|gyroscope){_CHIP}{_AXIS}$"),
    "mag": re.compile(rf"^(?:scaled|raw|imu)?[ _]?(?:mag|magnetometer){_CHIP}{_AXIS}$"),
}
"""Sensor columns named with a prefix or the chip (tried after :data:`PATTERNS`): an IMU's
``scaledAccelX`` (MicroStrain, beside its filter's ``estLinearAccelX``), HyperIMU's
``accelerometer_lsm6ds3_c.x`` and ``gyroscope_lsm6ds3_c.x`` (beside Android's ``linear_Acceleration.x``)."""
_ACC_AXIS = re.compile(r"^(?=.*(?i:acc)).*(?:[ _.\-]\(?[xyzXYZ]\)?|[a-z][XYZ])(?:\s*[\(\[][^\)\]]*[\)\]])?$")
"""A name, as written, that may be an acceleration's axis (``bodyAccX``, ``acc_lis3dh (x)``; not
``accuracy``)."""

_UNIT_ALIASES = {
    "m/s^2": "m/s^2",
    "m/s2": "m/s^2",
    "m/s²": "m/s^2",
    "ms^-2": "m/s^2",
    "m s^-2": "m/s^2",
    "g": "g",
    "rad/s": "rad/s",
    "deg/s": "deg/s",
    "°/s": "deg/s",
    "dps": "deg/s",
    "ut": "uT",
    "µt": "uT",
    "μt": "uT",
    "nt": "nT",
    "raw": "raw",
    "lsb": "raw",
    "counts": "raw",
    "a.u.": "raw",
    "a.u": "raw",
    "au": "raw",
    "arb.": "raw",
    "arb. units": "raw",
    "g's": "g",
    "gs": "g",
    "radians/s": "rad/s",
    "radians/second": "rad/s",
    "degrees/s": "deg/s",
    "degrees/second": "deg/s",
    "microtesla": "uT",
    "microteslas": "uT",
    "nanotesla": "nT",
    "nanoteslas": "nT",
}
_TIME_SCALE = {"s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "ns": 1e-9}


def normalise(name: str) -> str:
    return re.sub(r"\s+", " ", name.strip().strip('"').strip().lower())


_MAG_ALIASES = {"g": "gauss", "gauss": "gauss", "ga": "gauss"}
"""A magnetometer's ``(G)`` is gauss, not the accelerometer's g."""


def _header_unit(text: str | None, sensor: str = "acc") -> str | None:
    if not text:
        return None
    key = text.strip().lower()
    key = (key[3:] if key.startswith("in ") else key).replace(" ", "")  # iOS loggers' "x (in G's)"
    if sensor == "mag" and key in _MAG_ALIASES:
        return _MAG_ALIASES[key]
    return _UNIT_ALIASES.get(key)


def split_header(text: str) -> tuple[int, str, list[str]]:
    """Line number (1-based) of the header, the delimiter and the column names."""
    lines = text.splitlines()
    for number, line in enumerate(lines, start=1):
        if not line.strip() or is_comment(line):
            continue
        delimiter = guess_delimiter(line)
        if line.count(delimiter) == 0:
            if len(line.split()) < 2:
                raise LogFormatError(
                    f"line {number} {line[:80]!r} is not a header of comma-, semicolon-, tab- or space-separated "
                    "columns: the first line must name the columns, e.g. acc_x,acc_y,acc_z, or be the "
                    "first row of numbers"
                )
            delimiter = WHITESPACE
        return number, delimiter, split_row(line, delimiter)
    raise LogFormatError("the file holds no header row: the first line must name the columns, e.g. acc_x,acc_y,acc_z")


@dataclass(frozen=True)
class Layout:
    """Where a table's numbers start and how they are written, with the names of its columns."""

    skip_lines: int
    delimiter: str
    decimal: str
    names: list[str]
    headerless: bool
    notes: tuple[str, ...] = ()


MAX_PROSE_LINES = 10
"""How many lines before a table may be neither its header nor numbers (a terminal capture's start-up
messages: ``GPIO initialized.``, ``i2c bus opened with handle 0.``) and be skipped."""


def leading_prose(lines: list[str]) -> list[int]:
    """The 0-based indices of the lines before a table that are neither its header nor numbers.

    The table starts at the first line below which :func:`~app.io.readers.table.numeric_layout` finds
    rows of numbers; of the lines above it (comments and blank lines aside), the last is the header
    when it splits into names by the numbers' separator (for spaces: as many as the numbers), and the
    others are prose. None when no rows of numbers begin within :data:`MAX_PROSE_LINES` lines.
    """
    content = [i for i, ln in enumerate(lines) if ln.strip() and not is_comment(ln)][: MAX_PROSE_LINES + 2]
    for k, start in enumerate(content):
        numeric = numeric_layout(lines[start:])
        if numeric is None:
            continue
        before = content[:k]
        if not before:
            return []
        delimiter, _, width = numeric
        last = lines[before[-1]]
        fields = split_row(last, delimiter)
        header = len(fields) == width if delimiter == WHITESPACE else delimiter in last and len(fields) >= 2
        return before[:-1] if header else before
    return []


_DELIMITER_WORDS = {",": "commas", ";": "semicolons", "\t": "tabs", WHITESPACE: "spaces"}


def table_layout(text: str, name: str = "the file", column_names: list[str] | None = None) -> Layout:
    """The layout of a CSV-like table: a header row naming its columns, or numbers from the first line.

    Parameters
    ----------
    text : str
        The head of the file.
    name : str
        How to call the file in messages.
    column_names : list of str, optional
        One name per column, in order (the upload field ``columns=t,acc_x,acc_y,acc_z``): they name
        the columns of a table without a header row, or replace the header row of one that has it.

    Raises
    ------
    LogFormatError
        ``column_names`` whose count is not the file's; a first line with text among the numbers of the
        lines below it (``bad_line``).
    """
    lines = text.splitlines()
    prose = leading_prose(lines)
    start = prose[-1] + 1 if prose else 0
    skipped = (
        []
        if not prose
        else [
            f"line{'s' if len(prose) > 1 else ''} {', '.join(str(i + 1) for i in prose)} skipped before the table: "
            f"neither a header nor numbers ({', '.join(repr(lines[i].strip()[:40]) for i in prose[:3])}"
            f"{', …' if len(prose) > 3 else ''})"
        ]
    )
    numeric = numeric_layout(lines[start:])
    if numeric is not None:
        delimiter, decimal, width = numeric
        skip = next(i for i, ln in enumerate(lines) if i >= start and ln.strip() and not is_comment(ln))
        names = column_names or [f"column {i + 1}" for i in range(width)]  # else named from the data (.columns)
        notes = skipped + (
            [
                f"no header row: {width} columns separated by {_DELIMITER_WORDS[delimiter]}, named by "
                f"columns {', '.join(column_names)}"
            ]
            if column_names
            else []
        )
        layout = Layout(skip, delimiter, decimal, list(names), True, tuple(notes))
    else:
        _refuse_a_bad_first_line(lines, name, start)
        header_line, delimiter, names = split_header("\n".join(lines[start:]))
        header_line += start
        decimal = guess_decimal(lines[header_line:], delimiter)
        notes = skipped + ([f"header row replaced by columns {', '.join(column_names)}"] if column_names else [])
        layout = Layout(header_line, delimiter, decimal, column_names or names, False, tuple(notes))
        width = len(names)
    if column_names and len(column_names) != width:
        hint = ""
        if layout.delimiter == ",":
            hint = (
                ". Numbers with decimal commas (0,5) cannot be told from a comma separator: save the "
                "log with semicolons or tabs between the columns"
            )
        raise LogFormatError(
            f"columns names {len(column_names)} columns ({', '.join(column_names)}) but {name} has {width} "
            f"per line, separated by {_DELIMITER_WORDS[layout.delimiter]}: give one name per column, in "
            f"order (- skips a column){hint}"
        )
    if layout.decimal == ",":
        layout = dataclasses.replace(layout, notes=layout.notes + ("decimal comma",))
    return layout


def _number(cell: str) -> bool:
    try:
        float(cell.replace(",", "."))
        return True
    except ValueError:
        return False


def _refuse_a_bad_first_line(lines: list[str], name: str, start: int = 0) -> None:
    """A first line of numbers but for a cell or two, above lines of numbers only: a bad line of a table
    without a header row, named as such (not as a header trical does not recognise); the table starts at
    line index ``start`` (after a capture's start-up lines)."""
    numbered = [(i, ln) for i, ln in enumerate(lines[start:], start=start + 1) if ln.strip() and not is_comment(ln)]
    if len(numbered) < 3:
        return
    (number, first), rest = numbered[0], [ln for _, ln in numbered[1:4]]
    numeric = numeric_layout(rest)
    if numeric is None:
        return
    delimiter, _, width = numeric
    cells = split_row(first, delimiter)
    bad = [(c, cell) for c, cell in enumerate(cells) if not _number(cell)]
    if len(cells) == width and 0 < len(bad) <= width // 2:
        column, text = bad[0]
        raise LogFormatError(
            f"{name}: line {number}, column {column + 1}: {text[:40]!r} is not a number: every "
            "column of a table without a header row must hold numbers; fix or remove that line",
            code=BAD_LINE,
        )


def map_columns(names: list[str]) -> tuple[dict[str, dict[str, int]], int | None, float | None, dict[str, str]]:
    """Find the sensor, time and index columns; returns (channels, time column, time scale, units)."""
    channels: dict[str, dict[str, int]] = {}
    units: dict[str, str] = {}
    time_col = time_scale = None
    for col, raw in enumerate(names):
        name = normalise(raw)
        if _TEMPERATURE.match(name):
            continue
        m = _TIME.match(name)
        if m and time_col is None:
            time_col = col
            unit = (m.group("unit") or m.group("suffix") or "").strip().lower()
            time_scale = _TIME_SCALE.get(unit)
            continue
        if _INDEX.match(name):
            continue
        for sensor, pattern in PATTERNS.items():
            m = pattern.match(name)
            if m:
                sensor = _sensor_of_bare_axis(name, m.group("unit")) or sensor
                channels.setdefault(sensor, {}).setdefault(m.group("axis"), col)
                unit = _header_unit(m.group("unit"), sensor)
                if unit:
                    units.setdefault(sensor, unit)
                break
        else:
            for sensor, pattern in _NAMED.items():
                m = pattern.match(name)
                if m and col not in channels.get(sensor, {}).values():
                    channels.setdefault(sensor, {}).setdefault(m.group("axis"), col)
                    break
    linear = [n for n in names if _LINEAR.search(normalise(n))]
    if linear and "acc" not in channels:
        others = [
            n
            for n in names
            if _ACC_AXIS.search(n.strip()) and not _LINEAR.search(normalise(n)) and "gravity" not in normalise(n)
        ]
        if others:  # the linear columns are not all there is: ask which are the accelerometer
            listed = ", ".join(repr(n.strip()[:40]) for n in others[:6]) + (" …" if len(others) > 6 else "")
            raise LogFormatError(
                f"columns {', '.join(repr(n.strip()[:40]) for n in linear[:3])} hold linear acceleration (gravity "
                f"removed), but {listed} may be the accelerometer including gravity, which calibration needs: "
                "name its columns with the upload field columns, e.g. columns=acc_x:<name>,acc_y:<name>,"
                "acc_z:<name>"
            )
        raise LogFormatError(
            "the accelerometer columns hold linear acceleration (gravity removed); calibration needs "
            "the raw accelerometer including gravity: export 'acceleration including gravity' instead"
        )
    complete = [s for s, axes in channels.items() if set(axes) == {"x", "y", "z"}]
    if not complete:
        listed = listed_columns(names)
        partial = ", ".join(f"{s}_{a}" for s, axes in channels.items() for a in "xyz" if a in axes)
        raise LogFormatError(
            f"no accelerometer, gyroscope or magnetometer x, y and z columns among the header's columns {listed}"
            + (f" (only {partial}: trical needs all three axes of a sensor)" if partial else "")
            + ": name them acc_x, acc_y, acc_z (or ax, ay, az, or x, y, z), gyr_x, gyr_y, gyr_z or mag_x, mag_y, "
            "mag_z, any of the three sensors, optionally with a time column "
            "time_s / time_ms / time_ns, or map them without "
            "editing the file, e.g. columns=acc_x:<name>,acc_y:<name>,acc_z:<name>,time_ms:<name>. Exports of "
            "phyphox, Sensor Logger, Physics Toolbox, GnssLogger and the Arduino Serial Plotter are "
            "recognised as they are"
        )
    for sensor in [s for s, axes in channels.items() if set(axes) != {"x", "y", "z"}]:
        del channels[sensor]
    return channels, time_col, time_scale, units


_BARE_AXIS = re.compile(r"^\(?[xyz]\)?\s*[\(\[]")


def _sensor_of_bare_axis(name: str, unit: str | None) -> str | None:
    """The sensor of a column named by its axis and unit alone, ``X (rad/s)``, ``x (µT)``: the unit's (a rate is
    a gyroscope's, a field a magnetometer's), as a per-sensor export (phyphox, Physics Toolbox) writes them; None
    for an acceleration's unit, or no unit (an ``x`` column is an accelerometer's)."""
    if not _BARE_AXIS.match(name) or _header_unit(unit, "acc") in UNITS_IN["acc"]:  # x (g) is an acceleration
        return None
    if _header_unit(unit, "gyr") in ("rad/s", "deg/s"):
        return "gyr"
    if _header_unit(unit, "mag") in ("uT", "nT", "gauss"):
        return "mag"
    return None


def temperature_column(names: list[str]) -> int | None:
    """The index of the column holding the sensor's temperature in °C, if any (:data:`_TEMPERATURE`)."""
    return next((col for col, raw in enumerate(names) if _TEMPERATURE.match(normalise(raw))), None)


_UNIT_IN_NAME = re.compile(r"[\(\[]([^\)\]]*)[\)\]]")


def mapped_units(names: list[str], column_map: dict[str, str] | None) -> dict[str, str]:
    """The units a header names per sensor, the columns of ``column_map`` keeping the unit their own name
    gives (``x (rad/s)`` mapped to ``gyr_x`` is in rad/s)."""
    units = map_columns(renamed(names, column_map))[3]
    for canonical, column in (column_map or {}).items():
        sensor = canonical.split("_")[0]
        found = _UNIT_IN_NAME.search(column)
        unit = _header_unit(found.group(1), sensor) if found and sensor in PATTERNS else None
        if unit is not None and unit in UNITS_IN[sensor]:
            units.setdefault(sensor, unit)
    return units


def renamed(names: list[str], column_map: dict[str, str] | None) -> list[str]:
    """The header with the columns of ``column_map`` (canonical name → file column) renamed."""
    if not column_map:
        return names
    stripped = [n.strip().strip('"').strip() for n in names]
    out = list(names)
    for canonical, column in column_map.items():
        if column not in stripped:
            listed = ", ".join(repr(n) for n in stripped)
            raise LogFormatError(
                f"columns maps {canonical} to {column!r}, which is not a column of the header "
                f"({listed}): use one of those names"
            )
        out[stripped.index(column)] = canonical
    return out


@dataclass(frozen=True)
class CsvColumns:
    """Which column of a generic CSV is which, decided from its head: the layout, each sensor's x, y and z
    columns, the time column and its scale (None: inferred from its step), the temperature column."""

    layout: Layout
    channels: dict[str, dict[str, int]]
    time_col: int | None
    time_scale: float | None
    temp_col: int | None
    text: str


def csv_columns(
    path: Path,
    name: str = "the file",
    column_map: dict[str, str] | None = None,
    column_names: list[str] | None = None,
) -> CsvColumns:
    """The columns of a generic CSV log as :func:`read_csv_log` reads them (and a reader in chunks,
    :mod:`app.io.readers.chunks`), from the file's head; refusals as :func:`read_csv_log`'s."""
    with open(path, "rb") as f:
        head = f.read(SNIFF_BYTES)
    text = decode_head(head, name)
    layout = table_layout(text, name, column_names)
    if layout.headerless and column_names is None:
        layout = _named_from_data(path, layout, name)
    _refuse_text_block(text, layout, name)
    _refuse_words(text, layout, name)
    layout, channels, time_col, time_scale = _mapped_layout(path, layout, column_map, column_names, name)
    temp_col = temperature_column(renamed(layout.names, column_map))
    return CsvColumns(layout, channels, time_col, time_scale, temp_col, text)


def read_csv_log(
    path: Path,
    *,
    sampling_rate_hz: float | None = None,
    units: dict[str, str] | None = None,
    name: str = "the file",
    column_map: dict[str, str] | None = None,
    column_names: list[str] | None = None,
) -> LogData:
    """Read a generic CSV log into arrays, its units as the caller or the header name them.

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
    column_names : list of str, optional
        One name per column, in order, for a table without a header row (or instead of its header row);
        see :func:`table_layout`.

    Raises
    ------
    LogFormatError
        Empty, binary or header-only files, unrecognised columns, a mapped column the header lacks,
        a table without a header row whose columns its data do not name (or name more than one way:
        :class:`~app.io.readers.columns.ColumnsAmbiguous`), a count of ``column_names`` that is not the file's, text in
        a numeric column (with its line number), a missing sampling rate.
    """
    table = csv_columns(path, name, column_map, column_names)
    layout, channels, time_col, time_scale, temp_col = (
        table.layout,
        table.channels,
        table.time_col,
        table.time_scale,
        table.temp_col,
    )
    text = table.text
    names = layout.names
    header_units = mapped_units(names, column_map)
    used = [time_col] if time_col is not None else []
    if temp_col is not None:
        used.append(temp_col)
    sensors = [channels[sensor][a] for sensor in ("acc", "gyr", "mag") if sensor in channels for a in "xyz"]
    used += sensors
    notes = list(layout.notes)
    left = columns_not_read(
        names,
        used,
        "trical reads a time, a temperature and the x, y and z of an accelerometer, a gyroscope and a magnetometer; "
        "map one with columns if it is one of these",
    )
    if left:
        notes.append(left)
    values = dict(
        zip(
            used,
            read_columns(
                Path(path),
                skip_lines=layout.skip_lines,
                n_columns=len(names),
                columns=used,
                delimiter=layout.delimiter,
                decimal=layout.decimal,
                name=name,
                column_names=names,
                first_line=layout.skip_lines + 1,
                drop_empty=tuple(sensors),
                notes=notes,
            ),
        )
    )
    arrays = {s: np.column_stack([values[channels[s][a]] for a in "xyz"]) for s in channels}
    time = values[time_col] if time_col is not None else None
    try:
        time_s = _time_seconds(time, time_scale, None if time_col is None else names[time_col], sampling_rate_hz, notes)
    except LogFormatError as exc:
        if not (layout.headerless and column_names is None and time is not None and time_col is not None):
            raise
        other = ",".join(SKIP if c == time_col else n for c, n in enumerate(names))
        raise LogFormatError(
            f"{exc}. {name} has no header row, and its column {time_col + 1} rises at every line, "
            f"so it was read as the time: if it is not a time, name the columns with `columns`, e.g. columns={other}"
        ) from None
    stated_rate = None if time_s is not None else rate_from_comments(text.splitlines()[: layout.skip_lines])
    if stated_rate is not None and sampling_rate_hz is None:
        notes.append(f"no time column: the rate {stated_rate:g} Hz the lines before its table state is used")
    final_units = {s: (units or {}).get(s) or header_units.get(s) or UNITS[s][0] for s in arrays}
    for sensor, unit in final_units.items():
        accepted = UNITS_IN[sensor]
        if unit not in accepted:
            raise LogFormatError(f"{sensor} unit {unit!r} is not one of {', '.join(accepted)}")
    return with_timing(
        LogData(
            acc=arrays.get("acc"),
            gyr=arrays.get("gyr"),
            mag=arrays.get("mag"),
            time_s=time_s,
            sampling_rate_hz=stated_rate,
            units=final_units,
            format="csv",
            columns=names,
            notes=tuple(notes),
            temperature_c=values[temp_col] if temp_col is not None else None,
        ),
        sampling_rate_hz,
        name,
    )


def _refuse_text_block(text: str, layout: Layout, name: str) -> None:
    """Refuse a header row's table whose cell holds a block of text over several lines: no mapping reads it."""
    block = None if layout.headerless else text_block_cell(text, layout.delimiter, layout.skip_lines, layout.names)
    if block is not None:
        line, column, first = block
        raise LogFormatError(
            f"{name}: line {line}, column {column!r} holds a block of text over several lines ({first!r} …), not "
            "a number: trical reads one number per column and row, so no columns mapping can read it; write each "
            "reading in a column of its own (e.g. acc_x, acc_y, acc_z), one row per sample"
        )


_NUMBER = re.compile(r"^[+-]?(?:\d+[.,]?\d*|[.,]\d+)(?:[eE][+-]?\d+)?$")
_CELLS = re.compile(r"[\s;,\t]+")


def _refuse_words(text: str, layout: Layout, name: str) -> None:
    """Refuse a file whose lines after its header hold not one number (a sketch, a table of words): no columns
    mapping can read numbers that are not there, so the columns' question would be a dead end. (A table of
    numbers whose header names too few axes is the header's to refuse: it says what is missing.)"""
    lines = [line for line in text.splitlines()[layout.skip_lines :] if line.strip()]
    if not lines:
        return  # a header alone: the table's own refusal says so
    split = _CELLS if layout.delimiter in (None, " ") else re.compile(re.escape(layout.delimiter))
    if any(_NUMBER.match(cell.strip()) for line in lines for cell in split.split(line)):
        return
    first = (text.splitlines() or [""])[0].strip()[:60]
    raise LogFormatError(
        f"{name} holds no readings: not one number after its first line (it begins {first!r}), so it is not a "
        "recording of a sensor; upload the file the board or app wrote while logging (readings in columns, one "
        "row per sample), or a flight controller's log"
    )


def _mapped_layout(
    path: Path, layout: Layout, column_map: dict[str, str] | None, column_names: list[str] | None, name: str
) -> tuple[Layout, dict[str, dict[str, int]], int | None, float | None]:
    """The table's layout (its columns named from the data when its header names no sensor), the sensors'
    columns, the time column and the time's scale (:func:`map_columns`)."""
    names = layout.names
    try:
        channels, time_col, time_scale, _ = map_columns(renamed(names, column_map))
    except LogFormatError as exc:
        # A header naming no sensor (north, east, down): the columns named from the data if they can be, the
        # header's refusal (with how to map it by hand) if they cannot.
        if (
            column_map
            or column_names
            or not _NO_SENSOR.match(str(exc))
            or any(p.match(normalise(n)) for n in names for p in PATTERNS.values())
        ):
            raise  # a header naming part of a sensor says what it holds: its refusal says what is missing
        try:
            layout = _named_from_data(path, layout, name, header=names)
        except ColumnsAmbiguous:
            raise
        except LogFormatError:
            raise exc from None
        channels, time_col, time_scale, _ = map_columns(layout.names)
    return layout, channels, time_col, time_scale


def _time_seconds(
    time: np.ndarray | None,
    time_scale: float | None,
    column: str | None,
    sampling_rate_hz: float | None,
    notes: list[str],
) -> np.ndarray | None:
    """Seconds since the first sample from the time column (None without one, or when its unit is unclear and
    the rate was given: a note says so); its unit from its step when the header does not name it."""
    if time is None or len(time) < 2:
        return None
    if time_scale is None:
        try:
            time_scale, time_unit = infer_time_scale(time)
            notes.append(f"time column {column!r} read in {time_unit} (from its step)")
        except LogFormatError:
            if sampling_rate_hz is None:
                raise
            notes.append(f"time column {column!r} not used: its unit is unclear and sampling_rate_hz was given")
    if time_scale is not None:
        seconds: np.ndarray = (time - time[0]) * time_scale
        return seconds
    return None


_NO_SENSOR = re.compile(r"^no accelerometer, gyroscope or magnetometer x, y and z columns")


def _named_from_data(path: Path, layout: Layout, name: str, header: list[str] | None = None) -> Layout:
    """A table without a header row (or whose ``header`` names no sensor), its columns named from what they
    read (:mod:`.columns`)."""
    width = len(layout.names)
    with open(path, encoding="utf-8-sig", errors="replace") as f:
        head = [ln.rstrip("\r\n") for _, ln in zip(range(layout.skip_lines + PREVIEW_LINES), f)][layout.skip_lines :]
    data: np.ndarray | None
    try:
        data = np.column_stack(
            read_columns(
                Path(path),
                skip_lines=layout.skip_lines,
                n_columns=width,
                columns=list(range(width)),
                delimiter=layout.delimiter,
                decimal=layout.decimal,
                name=name,
                column_names=layout.names,
                first_line=layout.skip_lines + 1,
            )
        )
    except LogFormatError:
        # A line that is not numbers: the columns are named from the lines before it, and the reading with
        # those names then says which line, which column and what text.
        data = _rows_before_a_bad_line(path, layout, width)
        if data is None:
            raise
    names, why = guess_columns(data, Path(name).name, head, header=header)
    said = f"the header's columns ({', '.join(header)}) name no sensor" if header else "no header row"
    note = (
        f"{said}: {width} columns separated by {_DELIMITER_WORDS[layout.delimiter]}, {why}: "
        f"{', '.join(names)} (give columns to read them otherwise)"
    )
    return dataclasses.replace(layout, names=names, notes=(note,) + layout.notes)


def _rows_before_a_bad_line(path: Path, layout: Layout, width: int) -> np.ndarray | None:
    """The numbers of the lines before the first that does not parse (None: fewer than 3)."""
    rows = []
    with open(path, encoding="utf-8-sig", errors="replace") as f:
        for number, line in enumerate(f, start=1):
            if number <= layout.skip_lines or not line.strip() or is_comment(line):
                continue
            cells = split_row(line.rstrip("\r\n"), layout.delimiter)
            try:
                row = [float(c.replace(layout.decimal, ".")) for c in cells]
            except ValueError:
                break
            if len(row) != width:
                break
            rows.append(row)
    return np.array(rows) if len(rows) >= 3 else None


CSV = "csv"
ARDUINO = "arduino"
LSB_COMMENT = re.compile(r"lsb[ _]?per[ _]?g\s*[:=]\s*([0-9][0-9.eE+]*)", re.IGNORECASE)
_PLOTTER_PAIR = re.compile(r"([A-Za-z_][A-Za-z0-9_ ]*?)\s*:\s*(-?[0-9][0-9.eE+-]*)")
_PLOTTER_LINE = re.compile(r"^\s*[A-Za-z_][A-Za-z0-9_]*\s*:\s*-?[0-9]")


_RATE_COMMENT = re.compile(
    r"(?:^|[^a-z])(?:sampl(?:ing|e)[ _]?rate|data[ _]?rate|output[ _]?data[ _]?rate|odr|fs)\s*[:=,]\s*"
    r"([0-9][0-9.]*)\s*(ms|hz)?\b",
    re.IGNORECASE,
)
"""A rate stated before the table: HyperIMU's ``@ … Sampling Rate:50ms``, PicoQuake's ``# Config: data_rate =
2000.0 Hz``, a logger's ``Fs,100`` line (a rate's name without a unit is in Hz)."""
_RATE_HZ: dict[str, Callable[[float], float]] = {"ms": lambda v: 1000.0 / v, "hz": lambda v: v}


def rate_from_comments(lines: list[str]) -> float | None:
    """The rate the lines before the table state (comments, or a preamble of ``key,value`` lines), in Hz."""
    for line in lines:
        m = _RATE_COMMENT.search(line)
        if m and float(m.group(1)) > 0:
            return _RATE_HZ[(m.group(2) or "hz").lower()](float(m.group(1)))
    return None


def lsb_from_comments(lines: list[str]) -> float | None:
    """The ``lsb_per_g`` a comment line of the file gives, if any."""
    for line in lines:
        if is_comment(line):
            m = LSB_COMMENT.search(line)
            if m:
                return float(m.group(1))
    return None


def _data_lines(lines: list[str]) -> list[str]:
    return [ln for ln in lines if ln.strip() and not is_comment(ln)]


def detect_arduino(s: Sniff) -> bool:
    """Serial Plotter ``label:value`` lines, or a CSV whose comments give ``lsb_per_g``."""
    if s.is_zip:
        return False
    data = _data_lines(s.lines)
    return bool(data and _PLOTTER_LINE.match(data[0])) or lsb_from_comments(s.lines) is not None


def detect_csv(s: Sniff) -> bool:
    return not s.is_zip


def header_units(text: str, column_map: dict[str, str] | None = None) -> dict[str, str]:
    """The units a header row names per sensor (``acc_x (g)`` …), its columns mapped by ``column_map``
    (:func:`mapped_units`); empty when it names none."""
    try:
        _, _, names = split_header(text)
        return mapped_units(names, column_map)
    except LogFormatError:
        return {}


def read_csv(
    path: Path,
    s: Sniff,
    *,
    sampling_rate_hz: float | None = None,
    units: dict[str, str] | None = None,
    columns: dict[str, str] | list[str] | None = None,
    name: str = "the file",
) -> LogData:
    """Read a generic CSV log, its units as the caller or the header name them (settled from the data
    by :func:`app.io.readers.units.settle_units`).

    Parameters
    ----------
    path : pathlib.Path
        The file.
    s : Sniff
        Its head (unused: the table's layout is read from the file itself).
    sampling_rate_hz : float, optional
        The caller's rate: a time column whose unit is unclear is then left out (:func:`read_csv_log`).
    units : dict, optional
        The caller's units by sensor, over the header's.
    columns : dict or list of str, optional
        The caller's columns as :func:`app.io.readers.parse_columns` gives them: a mapping of canonical
        names to the header's (``{"acc_x": "north"}``), or one name per column.
    name : str
        How to call the file in messages.

    Returns
    -------
    LogData
        Its samples, ``format`` ``csv``.
    """
    log = read_csv_log(
        path,
        sampling_rate_hz=sampling_rate_hz,
        units=units or {},
        name=name,
        column_map=columns if isinstance(columns, dict) else None,
        column_names=columns if isinstance(columns, list) else None,
    )
    return dataclasses.replace(log, format=CSV)


def read_arduino(
    path: Path,
    s: Sniff,
    *,
    sampling_rate_hz: float | None = None,
    units: dict[str, str] | None = None,
    columns: dict[str, str] | list[str] | None = None,
    name: str = "the file",
) -> LogData:
    """Read Arduino output: Serial Plotter ``label:value`` lines, or a CSV with an ``lsb_per_g`` comment.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    s : Sniff
        Its head: Serial Plotter lines, or else a CSV read by :func:`read_csv`.
    sampling_rate_hz, units, columns, name
        As :func:`read_csv`'s (Serial Plotter lines read only ``units`` and ``name``: their labels name the
        columns, and they carry no time).

    Returns
    -------
    LogData
        Its samples, ``format`` ``arduino``.
    """
    data = _data_lines(s.lines)
    if not (data and _PLOTTER_LINE.match(data[0])):
        log = read_csv(path, s, sampling_rate_hz=sampling_rate_hz, units=units, columns=columns, name=name)
        return dataclasses.replace(log, format=ARDUINO)
    with open(path, encoding="utf-8-sig", errors="replace") as f:
        lines = f.read().splitlines()
    first = {k.strip(): v for k, v in _PLOTTER_PAIR.findall(data[0])}
    labels = list(first)
    channels: dict[str, dict[str, str]] = {}
    for label in labels:
        for sensor, pattern in PATTERNS.items():
            m = pattern.match(normalise(label))
            if m:
                channels.setdefault(sensor, {}).setdefault(m.group("axis"), label)
                break
    if set(channels.get("acc", {})) != {"x", "y", "z"}:
        raise LogFormatError(
            f"the Serial Plotter labels of {name} ({', '.join(labels)}) name no accelerometer x, y and z: "
            'print them as ax:…, ay:…, az:… (Serial.print("ax:"); Serial.print(ax); …)'
        )
    channels = {k: v for k, v in channels.items() if set(v) == {"x", "y", "z"}}
    rows: dict[str, list[list[float]]] = {k: [] for k in channels}
    for number, line in enumerate(lines, start=1):
        if not line.strip() or is_comment(line):
            continue
        pairs = {k.strip(): v for k, v in _PLOTTER_PAIR.findall(line)}
        try:
            for sensor, axes in channels.items():
                rows[sensor].append([float(pairs[axes[a]]) for a in "xyz"])
        except (KeyError, ValueError):
            raise LogFormatError(
                f"{name}: line {number} {line[:60]!r} lacks a number for one of "
                f"{', '.join(v for ax in channels.values() for v in ax.values())}"
            ) from None
    arrays = {k: np.asarray(v, dtype=float) for k, v in rows.items()}
    units = units or {}
    log = LogData(
        acc=arrays["acc"],
        gyr=arrays.get("gyr"),
        mag=arrays.get("mag"),
        time_s=None,
        sampling_rate_hz=None,
        units={k: units.get(k) or {"acc": "m/s^2", "gyr": "raw", "mag": "raw"}[k] for k in arrays},
        format=ARDUINO,
        columns=labels,
    )
    return log
