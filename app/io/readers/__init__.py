"""Log formats of phone and microcontroller apps, recognised by their header, read into :class:`LogData`.

``read_log(path, options)`` sniffs the upload (the first 64 KiB, or the member names of a
zip), picks the first format whose ``detect`` accepts it — in the order of :data:`DETECTORS`, most
specific first — and reads it.  Whatever the format, the result then goes through the same checks:
counts become g when ``lsb_per_g`` is known (caller or a ``# lsb_per_g=…`` comment), and a log
without gravity (linear acceleration) is refused with that reason.

========================  =====================================================================
format                    recognised by
========================  =====================================================================
``ulog``                  PX4's ULog: the file header ``ULog`` 0x01 0x12 0x35 (:mod:`app.io.flight.ulog`, pyulog)
``dataflash``             ArduPilot's DataFlash ``.bin``: a first message 0xA3 0x95 0x80, FMT
                          (:mod:`app.io.flight.dataflash`, pymavlink)
``phyphox``               zip holding ``Raw Data.csv``; header ``"Time (s)","Acceleration x (m/s^2)"…``
``sensor_logger``         zip holding ``Metadata.csv``; header ``time,seconds_elapsed,z,y,x``
``gnss_logger``           lines ``UncalAccel,…`` (or the ``# UncalAccel,…`` header)
``physics_toolbox``       header naming ``gFx, gFy, gFz``
``sensorlog``             header naming ``accelerometerAccelerationX(G)`` … (SensorLog, iOS)
``tagged``                lines naming their sensor first: ``acc 2060 0.03 -0.01 0.97``, ``gyro 2060 …``
                          (:mod:`.tagged_lines`)
``arduino``               Serial Plotter ``ax:… ay:… az:…`` lines, or a ``lsb_per_g`` comment
``csv``                   any other header row, or none (:mod:`app.io.readers.generic_csv`)
(parts)                   any other zip: its log files, one per pose, read each as above and
                          joined as one recording in parts (:mod:`app.io.readers.parts`)
========================  =====================================================================

A flight controller's log holds several IMU and compass instances: ``instance`` and ``mag_instance``
choose them, and ``clock`` which sensor's times the samples are on (:mod:`app.io.flight.instances`).

Then the sign (:mod:`.ios_sign`): the caller's ``sign`` (+1 keeps, −1 negates the accelerations),
else −1 for a log whose header names Core Motion's columns in g (a note says so), else what the
reader decided (+1, or Sensor Logger's iOS flip).

What the package holds: how to read a log (:mod:`.read_options`), one module per app format over one CSV
stack (:mod:`.table`, :mod:`.generic_csv`, :mod:`.columns`), the rate (:mod:`.timing`), the units and the
chips' scales (:mod:`.units`, :mod:`.gyro_unit`, :mod:`.chips`), the sign (:mod:`.ios_sign`), JSON
(:mod:`.json_samples`, :mod:`.betaflight_mag`), arrays and wearables' files (:mod:`.arrays`, :mod:`.wearables`),
recordings in several files, one per pose or one per sensor (:mod:`.parts`, :mod:`.sensor_files`), and the kinds
of file read (:mod:`.kinds`). The flight controllers' logs are read through :mod:`app.io.flight`.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from ..errors import LogFormatError
from ..flight import dataflash, ulog
from ..flight.instances import CLOCKS
from ..log import LogData
from . import (
    betaflight_mag,
    generic_csv,
    gnss_logger,
    json_samples,
    phyphox,
    physics_toolbox,
    sensor_logger,
    sensorlog,
    tagged_lines,
)
from .chips import parse_chips
from .ios_sign import check_sign, settle_sign
from .read_options import ReadOptions
from .table import SKIP, Sniff, sniff
from .timing import with_timing
from .units import refuse_linear_acceleration, settle_units

READERS = {
    ulog.NAME: ulog.read,
    dataflash.NAME: dataflash.read,
    phyphox.NAME: phyphox.read,
    sensor_logger.NAME: sensor_logger.read,
    gnss_logger.NAME: gnss_logger.read,
    physics_toolbox.NAME: physics_toolbox.read,
    sensorlog.NAME: sensorlog.read,
    betaflight_mag.NAME: betaflight_mag.read,
    json_samples.NAME: json_samples.read,
    tagged_lines.NAME: tagged_lines.read,
    generic_csv.ARDUINO: generic_csv.read_arduino,
    generic_csv.CSV: generic_csv.read_csv,
}
"""Readers by format name."""

DETECTORS = (
    (ulog.NAME, ulog.detect),
    (dataflash.NAME, dataflash.detect),
    (phyphox.NAME, phyphox.detect),
    (sensor_logger.NAME, sensor_logger.detect),
    (gnss_logger.NAME, gnss_logger.detect),
    (physics_toolbox.NAME, physics_toolbox.detect),
    (sensorlog.NAME, sensorlog.detect),
    (betaflight_mag.NAME, betaflight_mag.detect),
    (json_samples.NAME, json_samples.detect),
    (tagged_lines.NAME, tagged_lines.detect),
    (generic_csv.ARDUINO, generic_csv.detect_arduino),
    (generic_csv.CSV, generic_csv.detect_csv),
)
"""Detection order: the first format whose detector accepts the sniffed file is read."""

FORMATS = ("auto", *READERS)
MAKER_FORMATS = (generic_csv.CSV, generic_csv.ARDUINO, tagged_lines.NAME)
"""Formats a maker's program writes, which state no unit (or a header's): the data decide each sensor's."""
"""Values of the upload's ``format`` field."""
FLIGHT_FORMATS = (ulog.NAME, dataflash.NAME)
"""Flight controllers' logs: several IMU and compass instances, chosen by ``instance`` and ``mag_instance``."""

SOURCES = ("board", "phone", "px4", "ardupilot")
"""Where a recording comes from, as a calibration's ``source`` says it (the page offers its use first by it,
app/web/uses.py): a board printing its readings, a phone, a flight controller's firmware."""

SOURCE_OF_FORMAT = {
    ulog.NAME: "px4",
    dataflash.NAME: "ardupilot",
    generic_csv.ARDUINO: "board",
    tagged_lines.NAME: "board",
    phyphox.NAME: "phone",
    sensor_logger.NAME: "phone",
    gnss_logger.NAME: "phone",
    physics_toolbox.NAME: "phone",
    sensorlog.NAME: "phone",
}
"""The source of a recording of each format (:data:`SOURCES`); a plain CSV or JSON says none."""


def source_of_format(fmt: str) -> str | None:
    """The source of a recording read in ``fmt`` (:data:`SOURCE_OF_FORMAT`); several files' formats joined by ``+``
    (``csv+phyphox``) give the first that has one."""
    return next(filter(None, map(SOURCE_OF_FORMAT.get, str(fmt).split("+"))), None)


CANONICAL_COLUMNS = (
    *(f"{s}_{a}" for s in ("acc", "gyr", "mag") for a in "xyz"),
    "time_s",
    "time_ms",
    "time_us",
    "time_ns",
    "temp_c",
)
"""Names a column can be mapped to with ``columns``."""
TIME_NAMES = ("t", "time")
"""Names of a time column whose unit is inferred from its step (a list of ``columns``)."""


FILE_COLUMNS = ";"
"""Between the files' entries of ``columns`` for several files uploaded together: ``NAME=COLUMNS;NAME=COLUMNS``."""


def columns_of_file(columns, name: str):
    """The ``columns`` a file is read with: the upload's, or, where it names files (``a.csv=t,gyr_x,gyr_y,gyr_z;
    b.csv=…``, one entry per file uploaded together), this file's entry (None for a file it does not name: its
    header or its data decide)."""
    if not isinstance(columns, str) or "=" not in columns:
        return columns
    entries = {}
    for entry in filter(None, (e.strip() for e in columns.split(FILE_COLUMNS))):
        file, sep, value = entry.partition("=")
        if not sep or not file.strip() or not value.strip():
            raise LogFormatError(
                f"columns entry {entry!r} is not NAME=COLUMNS: for several files give one entry per file, e.g. "
                "gyroscope.txt=t,gyr_x,gyr_y,gyr_z;accelerometer.txt=t,acc_x,acc_y,acc_z"
            )
        entries[file.strip()] = value.strip()
    return entries.get(name)


def parse_columns(columns: str | dict | list | None) -> dict | list | None:
    """``columns`` as a mapping ``{"acc_x": "north", ...}`` or as a list of names, one per column.

    ``"acc_x:north,acc_y:east"`` (or a dict) maps canonical names to the file's header names;
    ``"t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z"`` (or a list) names every column in order — a table
    without a header row, or one whose header row is replaced — with the canonical names, ``t`` or
    ``time`` (time, unit inferred) and ``-`` (a column left out).

    Raises
    ------
    LogFormatError
        An entry without ``:`` among mapped ones, a canonical name trical does not know, a name
        given twice, no accelerometer x, y, z, or part of a gyroscope or magnetometer triple.
    """
    if not columns:
        return None
    if isinstance(columns, str):
        entries = [e.strip() for e in columns.split(",")]
        mapped = [":" in e for e in entries]
        if not any(mapped):
            return parse_column_names(entries)
        pairs = {}
        for entry in entries:
            canonical, sep, column = entry.partition(":")
            if not sep or not canonical.strip() or not column.strip():
                raise LogFormatError(
                    f"columns entry {entry!r} is not canonical:column, e.g. acc_x:north: give either a mapping "
                    "(acc_x:north,acc_y:east,acc_z:down) or one name per column (t,acc_x,acc_y,acc_z)"
                )
            pairs[canonical.strip().lower()] = column.strip()
        columns = pairs
    if isinstance(columns, (list, tuple)):
        return parse_column_names(list(columns))
    unknown = [k for k in columns if k not in CANONICAL_COLUMNS]
    if unknown:
        raise LogFormatError(
            f"columns maps {', '.join(unknown)}, which trical does not know: map to {', '.join(CANONICAL_COLUMNS)}"
        )
    return dict(columns)


def parse_column_names(names: list[str]) -> list[str]:
    """One name per column, checked (see :func:`parse_columns`)."""
    names = [str(n).strip().lower() for n in names]
    known = (*CANONICAL_COLUMNS, *TIME_NAMES, SKIP)
    unknown = [n for n in names if n not in known]
    if unknown:
        raise LogFormatError(
            f"columns names {', '.join(repr(n) for n in unknown)}, which trical does not know: name each column, "
            f"in order, with one of {', '.join(known)} ({SKIP} leaves a column out), e.g. "
            "columns=t,acc_x,acc_y,acc_z"
        )
    twice = sorted({n for n in names if n != SKIP and names.count(n) > 1})
    times = [n for n in names if n in TIME_NAMES or n.startswith("time_")]
    if twice or len(times) > 1:
        raise LogFormatError(
            f"columns names {', '.join(twice or times)} more than once: give each name (and one "
            f"time column) once, {SKIP} for a column to leave out"
        )
    for sensor in ("acc", "gyr", "mag"):
        axes = [f"{sensor}_{a}" for a in "xyz"]
        given = [a for a in axes if a in names]
        if given and len(given) != 3:
            missing = ", ".join(a for a in axes if a not in names)
            raise LogFormatError(
                f"columns names {', '.join(given)} but not {missing}: name all three axes of "
                "each sensor, e.g. columns=t,acc_x,acc_y,acc_z"
            )
    if not any(f"{sensor}_x" in names for sensor in ("acc", "gyr", "mag")):
        raise LogFormatError(
            "columns names no sensor: name the three axes of at least one, e.g. "
            "columns=t,acc_x,acc_y,acc_z (or t,mag_x,mag_y,mag_z for a magnetometer alone)"
        )
    return names


def detect_format(s: Sniff) -> str:
    """The name of the format of a sniffed upload.

    Raises
    ------
    LogFormatError
        A zip that is neither a phyphox nor a Sensor Logger export.
    """
    for fmt, accepts in DETECTORS:
        if accepts(s):
            return fmt
    listed = ", ".join(s.members[:12]) if s.members else "nothing"
    if any(m.startswith("xl/") for m in s.members or ()):
        raise LogFormatError(
            f"{s.name} is an Excel workbook: export the log as CSV (phyphox: 'CSV (Comma, "
            "decimal point)') and upload that",
            status=415,
        )
    raise LogFormatError(
        f"{s.name} is a zip holding {listed}: only phyphox exports (Raw Data.csv) and Sensor Logger "
        "exports (Metadata.csv with TotalAcceleration.csv or AccelerometerUncalibrated.csv) are read; "
        "upload the CSV itself otherwise",
        status=415,
    )


def read_log(path: Path, options: ReadOptions = ReadOptions(), *, name: str = "the file") -> LogData:
    """Read a log in any supported format into arrays.

    Parameters
    ----------
    path : pathlib.Path
        The uploaded file (text or zip).
    options : ReadOptions
        How to read it (:class:`app.io.readers.read_options.ReadOptions`: format, rate, units, counts per g, columns,
        sign, chips, a flight controller's instances and clock); by default the file decides.
    name : str
        How to call the file in messages.

    Returns
    -------
    LogData
        Readings as specific force with +g on the up axis (iOS signs flipped where the format or the
        header says so, or as ``options.sign`` asks), ``format`` naming the reader, ``sign`` the factor
        applied and ``notes`` what it decided.

    Raises
    ------
    LogFormatError
        Unknown format, a file the format cannot read (the message names the line or column and
        the fix), linear acceleration, inconsistent units or signs.
    """
    o = options
    if o.format not in FORMATS:
        raise LogFormatError(f"unknown format {o.format!r}: use one of {', '.join(FORMATS)}")
    from .arrays import is_array_file  # here: app.io.readers.arrays reads CSV through this package

    if o.clock not in CLOCKS:
        raise LogFormatError(f"unknown clock {o.clock!r}: use one of {', '.join(CLOCKS)}")
    if o.format in FLIGHT_FORMATS or (o.format == "auto" and starts_like_flight_log(path)):
        return read_flight_log(path, o, name=name)
    if o.instance is not None or o.mag_instance is not None:
        raise LogFormatError(
            f"instance and mag_instance choose a sensor of a flight controller's log (PX4 .ulg, "
            f"ArduPilot .bin); {name} is not one: leave them out"
        )
    if o.format == "auto" and is_array_file(path):  # .npy, Parquet, wearables: named by their suffix
        return _read_array_file(path, o, name)
    check_sign(o.sign)
    column_map = parse_columns(columns_of_file(o.columns, name))
    s = sniff(path, name)
    json_fmt = o.format if o.format in (betaflight_mag.NAME, json_samples.NAME) else None
    if o.format in ("auto", json_samples.NAME) and json_samples.detect(s):
        json_fmt = betaflight_mag.NAME if betaflight_mag.detect(s) else json_samples.NAME
    if json_fmt is not None:  # JSON: the export of a fit (refused), or an array of samples read as its table

        def read_table(table, table_name):
            return read_log(table, dataclasses.replace(o, format="auto", clock="imu"), name=table_name)

        return READERS[json_fmt](path, s, name=name, read_table=read_table)
    if (
        s.is_zip
        and o.format not in (phyphox.NAME, sensor_logger.NAME)
        and not (phyphox.detect(s) or sensor_logger.detect(s))
        and not any(m.startswith("xl/") for m in s.members or ())
    ):
        # A zip of pose files, one per pose (app.io.readers.parts): each read as the upload says, then joined.
        from .parts import read_parts_zip

        def read_part(part_path, part_name, part_columns=None):
            return read_log(
                part_path, dataclasses.replace(o, columns=part_columns or o.columns, clock="imu"), name=part_name
            )

        return read_parts_zip(path, s.members, read_part, name=name, columns_given=bool(o.columns))
    fmt = _text_format(s, o.format, column_map, name)
    return _read_text_log(path, s, fmt, column_map, o, name)


def _read_array_file(path: Path, o: ReadOptions, name: str) -> LogData:
    """A .npy, Parquet or wearable's file (:mod:`app.io.readers.arrays`): its samples in the unit given, timed and
    signed."""
    from .arrays import read_array_log

    if o.chip or o.lsb_per_g is not None:
        given = " and ".join(k for k, v in (("chip", o.chip), ("lsb_per_g", o.lsb_per_g)) if v)
        raise LogFormatError(
            f"{name} is an array file, whose samples trical takes in the unit given (acc_unit, gyr_unit or "
            f"mag_unit): {given} convert{'s' if ' and ' not in given else ''} the counts of text logs — divide the "
            "counts by the sensitivity before saving the array, or upload them as CSV"
        )
    check_sign(o.sign)
    log = read_array_log(path, sampling_rate_hz=o.sampling_rate_hz, units=o.units, name=name)
    return settle_sign(with_timing(log, o.sampling_rate_hz, name), o.sign)


def _text_format(s: Sniff, format: str, column_map, name: str) -> str:
    """The format a text log (or a phone app's zip) is read in: the one asked for, else the one detected; a
    generic CSV when its columns are mapped. Refuses a format the file cannot be."""
    if column_map and format not in ("auto", generic_csv.CSV, generic_csv.ARDUINO):
        raise LogFormatError(
            f"columns names the columns of a generic CSV; the {format} format has fixed columns: "
            "leave columns out, or use format=csv"
        )
    fmt = detect_format(s) if format == "auto" else format
    if column_map and fmt not in (generic_csv.CSV, generic_csv.ARDUINO):
        fmt = generic_csv.CSV
    if s.is_zip and fmt not in (phyphox.NAME, sensor_logger.NAME):
        raise LogFormatError(
            f"{name} is a zip archive, which the {fmt} format does not read: use format=auto, "
            "phyphox or sensor_logger, or upload the CSV itself",
            status=415,
        )
    if (
        not s.is_zip
        and fmt in (phyphox.NAME, sensor_logger.NAME, gnss_logger.NAME, physics_toolbox.NAME, sensorlog.NAME)
        and not dict(DETECTORS)[fmt](s)
    ):
        raise LogFormatError(
            f"{name} does not look like a {fmt} file (its header does not match): use "
            "format=auto, or map its columns as acc_x, acc_y, acc_z with format=csv"
        )
    return fmt


def _read_text_log(path: Path, s: Sniff, fmt: str, column_map, o: ReadOptions, name: str) -> LogData:
    """A text log (or a phone app's zip) read by the reader of ``fmt``, then timed, put in its units (the
    caller's, the header's, the format's, the chips' or the counts per g) and signed; linear acceleration is
    refused."""
    chips = parse_chips(o.chip)
    comment_lsb = None if s.is_zip else generic_csv.lsb_from_comments(s.lines)
    lsb = o.lsb_per_g if o.lsb_per_g is not None else comment_lsb
    extra: dict[str, Any] = {}
    if column_map:
        extra = {"column_names": column_map} if isinstance(column_map, list) else {"column_map": column_map}
    log = READERS[fmt](
        path, s, sampling_rate_hz=o.sampling_rate_hz, units=dict(o.units or {}), name=name, lsb_per_g=lsb, **extra
    )
    log = with_timing(log, o.sampling_rate_hz, name)  # the one decision of the rate (.timing)
    maker = fmt in MAKER_FORMATS
    if maker:  # a header row names the units, or nothing does
        stated = (
            {}
            if isinstance(column_map, list) or fmt == tagged_lines.NAME
            else generic_csv.header_units(s.text, column_map)
        )
    else:  # a phone app's format states its units
        stated = {k: v for k, v in log.units.items() if k not in (o.units or {})}
    log = settle_units(
        log,
        given=o.units,
        stated=stated,
        lsb_per_g=lsb,
        lsb_source="lsb_per_g" if o.lsb_per_g is not None else "the file's comment lsb_per_g",
        chips=chips,
        stated_by="the header" if maker else f"the {fmt} format",
        check_mag=maker,
        name=name,
    )
    notes = [] if fmt == log.format else [f"read as {fmt}"]
    log = dataclasses.replace(log, format=fmt, notes=tuple(log.notes) + tuple(notes))
    if log.acc is None:  # a magnetometer (or gyroscope) alone
        return log
    refuse_linear_acceleration(log.acc, log.units["acc"], name)
    return settle_sign(log, o.sign)


def starts_like_flight_log(path: Path) -> bool:
    """True for a file whose first bytes are a ULog header or a DataFlash FMT message."""
    from .table import BINARY_LOG_MAGICS

    with open(path, "rb") as f:
        return f.read(8).startswith(BINARY_LOG_MAGICS)


def read_flight_log(path: Path, options: ReadOptions, *, name: str) -> LogData:
    """A PX4 ULog or ArduPilot DataFlash log (:mod:`app.io.flight.ulog`, :mod:`app.io.flight.dataflash`): its units
    and frame are the format's, so the options of text logs (columns, chip, lsb_per_g, units, sign) are refused."""
    o = options
    own = {"acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}
    other_units = {k: v for k, v in (o.units or {}).items() if own.get(k) != v}
    given = [
        k
        for k, v in (
            ("columns", o.columns),
            ("chip", o.chip),
            ("lsb_per_g", o.lsb_per_g),
            ("units", other_units),
            ("sign", o.sign if o.sign != 1 else None),
        )
        if v
    ]
    if given:
        raise LogFormatError(
            f"{name} is a flight controller's log, whose units and frame the format states: "
            f"{', '.join(given)} {'is' if len(given) == 1 else 'are'} for text logs — leave "
            f"{'it' if len(given) == 1 else 'them'} out (its units: m/s^2, rad/s, uT)"
        )
    for what, value in (("instance", o.instance), ("mag_instance", o.mag_instance)):
        if value is not None and (isinstance(value, bool) or not isinstance(value, int) or value < 0):
            raise LogFormatError(f"{what} {value!r} is not an instance number: give a whole number from 0")
    s = sniff(path, name)
    fmt = detect_format(s) if o.format == "auto" else o.format
    if not dict(DETECTORS)[fmt](s):
        raise LogFormatError(
            f"{name} does not start as a {fmt} log (its first bytes are not the format's magic): "
            "use format=auto, or upload the .ulg / .bin file the vehicle wrote"
        )
    log = READERS[fmt](path, s, instance=o.instance, mag_instance=o.mag_instance, clock=o.clock, name=name)
    log = with_timing(log, o.sampling_rate_hz, name)
    log = settle_units(
        log,
        given=None,
        stated=dict(log.units),
        lsb_per_g=None,
        lsb_source="lsb_per_g",
        chips=None,
        stated_by=f"the {fmt} format",
        check_mag=False,
        name=name,
    )
    if log.acc is not None:  # a flight log's reader refuses a log without one
        refuse_linear_acceleration(log.acc, log.units["acc"], name)
    return settle_sign(log, None)
