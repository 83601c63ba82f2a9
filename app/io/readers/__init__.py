"""Log formats of phone and microcontroller apps, recognised by their header, read into :class:`LogData`.

``read_log(path, options)`` sniffs the upload (the first 64 KiB, or the member names of a
zip), picks the first format whose ``detect`` accepts it — in the order of :data:`DETECTORS`, most
specific first — and calls that format's one reader (:func:`plan_read` decides, once, before any
reader runs).  Whatever the format, the result then goes through the same checks:
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
``betaflight_mag``        the Betaflight configurator's compass tumble (JSON; its characterization model refused)
``json``                  a JSON array of samples (:mod:`.json_samples`), read as the CSV table it makes
``arduino``               Serial Plotter ``ax:… ay:… az:…`` lines, or a ``lsb_per_g`` comment
``csv``                   any other header row, or none (:mod:`app.io.readers.generic_csv`)
(parts)                   any other zip: its log files, one per pose, read each as above and
                          joined as one recording in parts (:mod:`app.io.readers.parts`)
========================  =====================================================================

Each reader takes, besides the file, its sniffed head and ``name``, the options it reads as keyword-only
parameters and no others (:data:`READERS` names them; an option misspelled is a TypeError): a flight log's
``instance``, ``mag_instance`` and ``clock``; a phone app's format's and the tagged lines' ``units``; a generic
or Arduino CSV's ``sampling_rate_hz``, ``units`` and ``columns``; JSON none, its samples becoming a table read
as a CSV. The rest — the rate, counts per g, chips, the sign — ``read_log`` applies after the reader, the same
for every format, and an option a format has no use for is refused there with its remedy, or has no effect.

A flight controller's log holds several IMU and compass instances: ``instance`` and ``mag_instance``
choose them, and ``clock`` which sensor's times the samples are on (:mod:`app.io.flight.instances`).

Then the sign (:mod:`.ios_sign`): the caller's ``sign`` (+1 keeps, −1 negates the accelerations),
else −1 for a log whose header names Core Motion's columns in g (a note says so), else what the
reader decided (+1, or Sensor Logger's iOS flip).

What the package holds: how to read a log (:mod:`.read_options`), one module per app format over one CSV
stack (:mod:`.table`, :mod:`.generic_csv`, :mod:`.columns`), the rate (:mod:`.timing`), the units and the
chips' scales (:mod:`.units`, :mod:`.gyro_unit`, :mod:`.chips`), the sign (:mod:`.ios_sign`), JSON
(:mod:`.json_samples`, :mod:`.betaflight_mag`), arrays and wearables' files (:mod:`.arrays`, :mod:`.wearables`),
recordings in several files, one per pose or one per sensor (:mod:`.parts`, :mod:`.sensor_files`), the kinds
of file read (:mod:`.kinds`), and a recording read in chunks, its reading decided as here (:mod:`.chunks`). The
flight controllers' logs are read through :mod:`app.io.flight`.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import tempfile
from collections.abc import Callable, Mapping
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal, cast

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

Family = Literal["flight", "text", "json"]

READER_OPTIONS = ("units", "sampling_rate_hz", "columns", "instance", "mag_instance", "clock")
"""The options a reader may take, each a keyword-only parameter of that name besides ``name``, given by
:func:`read_log` from the :class:`~app.io.readers.read_options.ReadOptions` (:func:`reader_options`): the caller's
``units`` by sensor, the caller's ``sampling_rate_hz``, the ``columns`` as :func:`parse_columns` gives them, and a
flight controller's ``instance``, ``mag_instance`` and ``clock``. The other options (counts per g, chips, sign, the
rate of the samples read) are applied by :func:`read_log` itself after the reader, the same for every format."""


@dataclass(frozen=True)
class Reader:
    """A format of :data:`READERS`: how it is recognised, which function reads it and the options it honours.

    Attributes
    ----------
    family : {"flight", "text", "json"}
        How :func:`read_log` reads it: a flight controller's log (its units and frame are the format's, so the
        options of text logs are refused), a text log (the reader's samples then timed, put in their units and
        signed), or JSON, whose reader returns its samples as a table (:class:`.json_samples.Samples`) that is
        then read as a text log.
    detect : callable
        ``detect(sniff) -> bool``: whether a sniffed upload is in this format (:data:`DETECTORS`).
    read : callable
        ``read(path, sniff, *, name, **honoured)``; no catch-all ``**kwargs``: an option it does not declare is a
        TypeError.
    honours : tuple of str
        The options of :data:`READER_OPTIONS` it takes: its keyword-only parameters besides ``name``, and what
        :meth:`call` passes it.

    Raises
    ------
    TypeError
        ``honours`` names an option that is not one of :data:`READER_OPTIONS`, or is not what ``read`` declares
        (the table and the readers' signatures cannot drift apart), or ``read`` takes ``**kwargs``.
    """

    family: Family
    detect: Callable[[Sniff], bool]
    read: Callable[..., Any]
    honours: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        params = inspect.signature(self.read).parameters.values()
        declared = {p.name for p in params if p.kind is p.KEYWORD_ONLY} - {"name"}
        catch_all = [p.name for p in params if p.kind is p.VAR_KEYWORD]
        unknown = sorted(set(self.honours) - set(READER_OPTIONS))
        if catch_all or unknown or declared != set(self.honours):
            raise TypeError(
                f"{self.read.__module__}.{self.read.__qualname__} declares {sorted(declared)}"
                + (f" and **{catch_all[0]}" if catch_all else "")
                + f", but the table says it honours {list(self.honours)}"
                + (f" ({', '.join(unknown)} not among {', '.join(READER_OPTIONS)})" if unknown else "")
            )

    def call(self, path: Path, s: Sniff, *, name: str, options: Mapping[str, Any]) -> Any:
        """``read(path, s, name=name)`` with the options it honours, taken from ``options`` (every one of
        :data:`READER_OPTIONS`: :func:`reader_options`)."""
        return self.read(path, s, name=name, **{k: options[k] for k in self.honours})


_FLIGHT = ("instance", "mag_instance", "clock")
_APP = ("units",)
_TABLE = ("sampling_rate_hz", "units", "columns")

READERS: dict[str, Reader] = {
    ulog.NAME: Reader("flight", ulog.detect, ulog.read, _FLIGHT),
    dataflash.NAME: Reader("flight", dataflash.detect, dataflash.read, _FLIGHT),
    phyphox.NAME: Reader("text", phyphox.detect, phyphox.read, _APP),
    sensor_logger.NAME: Reader("text", sensor_logger.detect, sensor_logger.read, _APP),
    gnss_logger.NAME: Reader("text", gnss_logger.detect, gnss_logger.read, _APP),
    physics_toolbox.NAME: Reader("text", physics_toolbox.detect, physics_toolbox.read, _APP),
    sensorlog.NAME: Reader("text", sensorlog.detect, sensorlog.read, _APP),
    betaflight_mag.NAME: Reader("json", betaflight_mag.detect, betaflight_mag.read),
    json_samples.NAME: Reader("json", json_samples.detect, json_samples.read),
    tagged_lines.NAME: Reader("text", tagged_lines.detect, tagged_lines.read, _APP),
    generic_csv.ARDUINO: Reader("text", generic_csv.detect_arduino, generic_csv.read_arduino, _TABLE),
    generic_csv.CSV: Reader("text", generic_csv.detect_csv, generic_csv.read_csv, _TABLE),
}
"""Every format by name, in the order of detection (most specific first), with the options its reader honours:
the one place that says which format reads which option. A flight log's reader reads the instances and the clock;
a phone app's (and the tagged lines') the caller's units, its columns and time being the app's; a generic or an
Arduino CSV the units, the rate (a time column whose unit is unclear is then left out) and the columns; JSON none:
its samples become a table, read as a CSV with these."""

DETECTORS = tuple((fmt, reader.detect) for fmt, reader in READERS.items())
"""Detection order: the first format whose detector accepts the sniffed file is read."""

FORMATS = ("auto", *READERS)
"""Values of the upload's ``format`` field."""
MAKER_FORMATS = (generic_csv.CSV, generic_csv.ARDUINO, tagged_lines.NAME)
"""Formats a maker's program writes, which state no unit (or a header's): the data decide each sensor's."""
FLIGHT_FORMATS = tuple(fmt for fmt, reader in READERS.items() if reader.family == "flight")
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


Columns = dict[str, str] | list[str]
"""The columns a caller named, parsed (:func:`parse_columns`): canonical names mapped to the header's, or one name
per column."""
ColumnsGiven = str | Columns | None
"""The columns as a caller gives them (``ReadOptions.columns``): text, a mapping or a list of names."""

FILE_COLUMNS = ";"
"""Between the files' entries of ``columns`` for several files uploaded together: ``NAME=COLUMNS;NAME=COLUMNS``."""


def columns_of_file(columns: ColumnsGiven, name: str) -> ColumnsGiven:
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


def parse_columns(columns: ColumnsGiven) -> Columns | None:
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


def detect_format(s: Sniff, families: tuple[Family, ...] = ("flight", "text", "json")) -> str:
    """The name of the format of a sniffed upload: the first of :data:`DETECTORS` of ``families`` that accepts it.

    Raises
    ------
    LogFormatError
        A zip that is neither a phyphox nor a Sensor Logger export.
    """
    for fmt, accepts in DETECTORS:
        if READERS[fmt].family in families and accepts(s):
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

    The format is decided first, once (:func:`plan_read`: a flight log's magic, an array file's suffix, a zip's
    members, a JSON file's kind and then its table's format, a text file's header), then one reader of
    :data:`READERS` reads it with the options it honours; a zip of several log files reads each member the same
    way and joins them (:mod:`app.io.readers.parts`).

    Parameters
    ----------
    path : pathlib.Path
        The uploaded file (text or zip).
    options : ReadOptions
        How to read it (:class:`app.io.readers.read_options.ReadOptions`: format, rate, units, counts per g, columns,
        sign, chips, a flight controller's instances and clock); by default the file decides. An option the
        format has no use for is refused with the remedy (the columns of a phone app's format, the text logs'
        options of a flight log, a flight log's instances of a text file) or has no effect, as documented per
        option.
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
    _check_options(options)
    with ExitStack() as stack:  # holds the table a JSON file's samples make while it is read
        plan = plan_read(path, options, name, stack)
        if plan.family == "parts":
            from .parts import read_parts_zip  # here: app.io.readers.parts reads its members through this package

            return read_parts_zip(
                path,
                # A zip's plan (plan_read): its sniff lists the zip's members.
                cast("tuple[str, ...]", plan.sniff.members) if plan.sniff is not None else (),
                functools.partial(_read_part, options),
                name=name,
                columns_given=bool(options.columns),
            )
        return _read_planned(plan, options, name)


def _check_options(o: ReadOptions) -> None:
    """Refuse a format or a clock that is none of the known ones."""
    if o.format not in FORMATS:
        raise LogFormatError(f"unknown format {o.format!r}: use one of {', '.join(FORMATS)}")
    if o.clock not in CLOCKS:
        raise LogFormatError(f"unknown clock {o.clock!r}: use one of {', '.join(CLOCKS)}")


def _read_part(options: ReadOptions, path: Path, name: str, columns: ColumnsGiven = None) -> LogData:
    """One file of a zip of log files (:func:`app.io.readers.parts.read_parts_zip`), read with the upload's options on
    the IMU's clock (``columns``, when given, replaces the upload's: a file named for one sensor)."""
    o = dataclasses.replace(options, columns=columns or options.columns, clock="imu")
    with ExitStack() as stack:
        plan = plan_read(path, o, name, stack)
        if plan.family == "parts":
            raise LogFormatError(
                f"{name} is a zip inside a recording of several files: give the files themselves, or one zip of them"
            )
        return _read_planned(plan, o, name)


@dataclass(frozen=True)
class Plan:
    """What :func:`plan_read` decided a file is, before any reader runs.

    Attributes
    ----------
    family : {"flight", "array", "text", "parts"}
        A flight controller's log, an array file (:mod:`app.io.readers.arrays`), a text log (or a phone app's zip, or
        the table of a JSON file's samples), or a zip of log files (:mod:`app.io.readers.parts`).
    path : pathlib.Path
        The file the reader reads: the upload, or the table a JSON file's samples make.
    fmt : str or None
        The format read (a key of :data:`READERS`); None for an array file or a zip of log files.
    sniff : Sniff or None
        The head of ``path`` (None for an array file).
    columns : dict or list of str, optional
        The columns the caller named for this file (:func:`parse_columns`).
    samples : json_samples.Samples, optional
        A JSON file's samples, whose note (and format) the log read from their table takes.
    """

    family: Literal["flight", "array", "text", "parts"]
    path: Path
    fmt: str | None = None
    sniff: Sniff | None = None
    columns: Columns | None = None
    samples: json_samples.Samples | None = None


def plan_read(path: Path, options: ReadOptions, name: str, stack: ExitStack) -> Plan:
    """Decide what a file is and which reader reads it: a flight log by its magic, an array file by its suffix, a
    JSON file's kind (its samples then written as a table, in a folder ``stack`` removes, whose format is decided
    as a text file's), a zip of log files, else a text log's format, asked or detected.

    Raises
    ------
    LogFormatError
        What :func:`read_log` refuses before reading: an option the file's family has no use for, a sign that is
        not ±1, columns that do not parse, a format the file cannot be, a JSON file that holds no samples.
    """
    o = options
    if o.format in FLIGHT_FORMATS or (o.format == "auto" and starts_like_flight_log(path)):
        return _flight_plan(path, o, name)
    if o.instance is not None or o.mag_instance is not None:
        raise LogFormatError(
            f"instance and mag_instance choose a sensor of a flight controller's log (PX4 .ulg, "
            f"ArduPilot .bin); {name} is not one: leave them out"
        )
    from .arrays import is_array_file  # here: app.io.readers.arrays reads CSV through this package

    if o.format == "auto" and is_array_file(path):  # .npy, Parquet, wearables: named by their suffix
        return Plan("array", path)
    check_sign(o.sign)
    columns = parse_columns(columns_of_file(o.columns, name))
    s = sniff(path, name)
    json_fmt = _json_format(s, o.format)
    if json_fmt is not None:  # JSON: the export of a fit (refused), or an array of samples read as its table
        samples: json_samples.Samples = READERS[json_fmt].call(path, s, name=name, options=reader_options(o, None))
        table = json_samples.write_table(samples, Path(stack.enter_context(tempfile.TemporaryDirectory())))
        s = sniff(table, name)
        return Plan("text", table, _text_format(s, "auto", columns, name), s, columns, samples)
    if (
        s.is_zip
        and o.format not in (phyphox.NAME, sensor_logger.NAME)
        and not (phyphox.detect(s) or sensor_logger.detect(s))
        and not any(m.startswith("xl/") for m in s.members or ())
    ):  # a zip of log files, one per pose or per sensor (app.io.readers.parts): each read as the upload says, joined
        return Plan("parts", path, sniff=s)
    return Plan("text", path, _text_format(s, o.format, columns, name), s, columns)


def _json_format(s: Sniff, format: str) -> str | None:
    """The JSON format a file is read in: the one asked for, or for ``auto`` or ``json`` the Betaflight tumble's
    when the file names it, else JSON samples; None for a file that is not JSON."""
    if format in (betaflight_mag.NAME, json_samples.NAME):
        json_fmt: str | None = format
    else:
        json_fmt = None
    if format in ("auto", json_samples.NAME) and json_samples.detect(s):
        json_fmt = betaflight_mag.NAME if betaflight_mag.detect(s) else json_samples.NAME
    return json_fmt


def reader_options(o: ReadOptions, columns: Columns | None) -> dict[str, Any]:
    """Every option of :data:`READER_OPTIONS`, from ``o`` and the parsed ``columns``: what :meth:`Reader.call` takes
    each reader's from."""
    return {
        "units": dict(o.units or {}),
        "sampling_rate_hz": o.sampling_rate_hz,
        "columns": columns,
        "instance": o.instance,
        "mag_instance": o.mag_instance,
        "clock": o.clock,
    }


def _read_planned(plan: Plan, o: ReadOptions, name: str) -> LogData:
    """The file as :func:`plan_read` decided: its one reader, then its timing, units and sign."""
    if plan.family == "array":
        return _read_array_file(plan.path, o, name)
    assert plan.sniff is not None and plan.fmt is not None  # a flight or a text log's plan holds both
    if plan.family == "flight":
        return _read_flight_log(plan.path, plan.sniff, plan.fmt, o, name)
    log = _read_text_log(plan.path, plan.sniff, plan.fmt, plan.columns, o, name)
    if plan.samples is None:
        return log
    return dataclasses.replace(log, notes=(plan.samples.note, *log.notes), format=plan.samples.format or log.format)


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


def _text_format(s: Sniff, format: str, column_map: Columns | None, name: str) -> str:
    """The format a text log (or a phone app's zip) is read in: the one asked for, else the one detected; a
    generic CSV when its columns are mapped. Refuses a format the file cannot be."""
    if column_map and format not in ("auto", generic_csv.CSV, generic_csv.ARDUINO):
        raise LogFormatError(
            f"columns names the columns of a generic CSV; the {format} format has fixed columns: "
            "leave columns out, or use format=csv"
        )
    # a text format: flight logs and JSON were told apart before (plan_read), and a JSON file's table is read as text
    fmt = detect_format(s, ("text",)) if format == "auto" else format
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
        and not READERS[fmt].detect(s)
    ):
        raise LogFormatError(
            f"{name} does not look like a {fmt} file (its header does not match): use "
            "format=auto, or map its columns as acc_x, acc_y, acc_z with format=csv"
        )
    return fmt


def _read_text_log(path: Path, s: Sniff, fmt: str, column_map: Columns | None, o: ReadOptions, name: str) -> LogData:
    """A text log (or a phone app's zip) read by the reader of ``fmt``, then timed, put in its units (the
    caller's, the header's, the format's, the chips' or the counts per g) and signed; linear acceleration is
    refused."""
    chips = parse_chips(o.chip)
    comment_lsb = None if s.is_zip else generic_csv.lsb_from_comments(s.lines)
    lsb = o.lsb_per_g if o.lsb_per_g is not None else comment_lsb
    log: LogData = READERS[fmt].call(path, s, name=name, options=reader_options(o, column_map))
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


def _flight_plan(path: Path, o: ReadOptions, name: str) -> Plan:
    """A PX4 ULog or ArduPilot DataFlash log (:mod:`app.io.flight.ulog`, :mod:`app.io.flight.dataflash`): its units
    and frame are the format's, so the options of text logs (columns, chip, lsb_per_g, units, sign) are refused, as an
    instance that is not a number; the format asked for must be the file's."""
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
    if not READERS[fmt].detect(s):
        raise LogFormatError(
            f"{name} does not start as a {fmt} log (its first bytes are not the format's magic): "
            "use format=auto, or upload the .ulg / .bin file the vehicle wrote"
        )
    return Plan("flight", path, fmt, s)


def _read_flight_log(path: Path, s: Sniff, fmt: str, o: ReadOptions, name: str) -> LogData:
    """A flight controller's log read by the reader of ``fmt`` (the instances and the clock asked for), timed, its
    units the format's."""
    log: LogData = READERS[fmt].call(path, s, name=name, options=reader_options(o, None))
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
