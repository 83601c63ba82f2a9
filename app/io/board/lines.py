"""The lines a board prints, read as they arrive: the format recognised from the first lines, each line
turned into a reading stamped with the host's arrival time (and the board's own time when the line has
one), boot text skipped and counted.

The formats (:mod:`app.io.board.formats` holds their constants):

- ``raw``: MotionCal's and Adafruit SensorLab's ``Raw:ax,ay,az,gx,gy,gz,mx,my,mz``, nine int16 counts
  at MotionCal's fixed scales, read into m/s² (standard gravity), °/s and µT;
- ``uni``: ``Uni:`` and the same nine values in m/s², rad/s and µT (Adafruit's Unified Sensor units);
- ``csv``: a header line naming the columns as trical's log readers know them
  (:func:`app.io.readers.generic_csv.map_columns`), then rows of numbers;
- ``numbers``: bare numbers in 3, 6 or 9 columns (accelerometer, gyroscope, magnetometer x, y, z in that
  order), optionally after a leading time (4, 7 or 10 columns), separated by commas, semicolons, tabs
  or spaces.

Lines end in CR, LF or CRLF. The rate is the board's: from its time column when the lines have one
(:func:`app.io.readers.timing.decide_timing`); else, for lines read live, from the count of readings
against their arrival over several seconds (:class:`StreamRate`), never from the arrival of one burst. The
units are checked at rest by the rules of every log
(:func:`app.io.readers.units.settle_units`) when the readings become a log (:func:`to_log`).
"""

from __future__ import annotations

import csv
import dataclasses
import itertools
import math
import re
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...calibration.shared.gravity import STANDARD_GRAVITY
from ..errors import LogFormatError
from ..log import LogData
from ..readers.generic_csv import map_columns
from ..readers.table import WHITESPACE, guess_delimiter, split_row
from ..readers.timing import decide_timing, time_scale
from ..readers.units import settle_units
from .formats import ADAFRUIT_UNI, MOTIONCAL_RAW, RATE_AGREE, RATE_MIN_S, RATE_STEPS, RATE_WINDOW_S

FORMATS = ("auto", "raw", "uni", "csv", "numbers")
"""The names a caller chooses a format by (``--format``); ``auto`` recognises it from the first lines."""

FORMAT_WORDS = {
    "raw": "MotionCal Raw: counts",
    "uni": "Uni: (m/s², rad/s, µT)",
    "csv": "CSV with a header line",
    "numbers": "bare numbers",
}

DETECT_LINES = 20
"""Lines held while the format is not yet known; past them, lines that fit none are skipped."""

NUMBER_WIDTHS = {3: ("acc",), 6: ("acc", "gyr"), 9: ("acc", "gyr", "mag")}
"""Bare numbers by their column count (without a leading time): the sensors, in order."""

SENSORS = ("acc", "gyr", "mag")
_LINE_END = re.compile(r"\r\n|\r|\n")
_NUMBER = re.compile(r"^[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?$")
_SPLIT = re.compile(r"[,;\t ]+")


@dataclass(frozen=True)
class BoardReading:
    """One line's reading.

    Attributes
    ----------
    arrival_s : float
        The host's clock when the line's last byte arrived (seconds, any origin).
    board_time : float or None
        The board's own time from the line, in the unit the board prints (see :attr:`LineFormat.time_scale`).
    values : dict
        ``acc``, ``gyr``, ``mag`` → (x, y, z), in the format's units (:attr:`LineFormat.units`).
    """

    arrival_s: float
    board_time: float | None
    values: dict


@dataclass(frozen=True)
class LineFormat:
    """A recognised format: its name, the sensors its lines hold and their units (None: the data decide).

    ``columns`` maps each sensor to its three column indices (and ``time_col`` the board's time) for
    ``csv`` and ``numbers``; ``time_scale`` is seconds per unit of the board's time when a header names it.
    """

    name: str
    sensors: tuple
    units: dict
    width: int | None = None
    columns: dict | None = None
    time_col: int | None = None
    time_scale: float | None = None
    delimiter: str | None = None
    header: tuple = ()

    def words(self) -> str:
        sensors = ", ".join(self.sensors)
        timed = ", with the board's time" if self.time_col is not None else ""
        return f"{FORMAT_WORDS[self.name]} ({sensors}{timed})"


def _numbers(line: str) -> list[float] | None:
    """The numbers of a line of numbers only (separated by commas, semicolons, tabs or spaces), else None."""
    fields = [f for f in _SPLIT.split(line.strip()) if f]
    if not fields or not all(_NUMBER.match(f) for f in fields):
        return None
    return [float(f) for f in fields]


def _prefixed(line: str, prefix: str, n: int) -> list[float] | None:
    if not line.startswith(prefix):
        return None
    values = _numbers(line[len(prefix) :])
    return values if values is not None and len(values) == n else None


RAW_SCALES = {
    "acc": MOTIONCAL_RAW["acc_g_per_count"] * STANDARD_GRAVITY,
    "gyr": MOTIONCAL_RAW["gyr_dps_per_count"],
    "mag": MOTIONCAL_RAW["mag_ut_per_count"],
}
"""MotionCal's counts into m/s², °/s and µT."""

RAW_FORMAT = LineFormat("raw", SENSORS, {"acc": "m/s^2", "gyr": "deg/s", "mag": "uT"})
UNI_FORMAT = LineFormat("uni", SENSORS, dict(ADAFRUIT_UNI["units"]))


def _printed(fmt: LineFormat, values: list[float]) -> LineFormat:
    """The Raw: or Uni: format with the sensors a board prints: a sensor it lacks (an MPU-6050 has no
    magnetometer) is printed as zeros, and is left out."""
    sensors = tuple(s for i, s in enumerate(SENSORS) if any(v != 0 for v in values[3 * i : 3 * i + 3]))
    return dataclasses.replace(fmt, sensors=sensors or SENSORS)


def numbers_format(width: int) -> LineFormat | None:
    """Bare numbers of ``width`` columns: 3, 6, 9, or 4, 7, 10 with a leading time; None for other widths."""
    timed = width - 1 in NUMBER_WIDTHS and width not in NUMBER_WIDTHS
    sensors = NUMBER_WIDTHS.get(width - 1 if timed else width)
    if sensors is None:
        return None
    first = 1 if timed else 0
    columns = {s: tuple(first + 3 * i + a for a in range(3)) for i, s in enumerate(sensors)}
    return LineFormat("numbers", sensors, {}, width, columns, 0 if timed else None)


def csv_format(line: str) -> LineFormat | None:
    """A header line naming accelerometer, gyroscope or magnetometer columns as trical's log readers
    know them; None when the line is not one."""
    if _numbers(line) is not None or not line.strip() or line.lstrip().startswith("#"):
        return None
    delimiter = guess_delimiter(line)
    if line.count(delimiter) == 0:
        delimiter = WHITESPACE
    names = split_row(line, delimiter)
    if len(names) < 3:
        return None
    try:
        channels, time_col, scale, units = map_columns(names)
    except LogFormatError:
        return None
    columns = {s: tuple(channels[s][a] for a in "xyz") for s in SENSORS if s in channels}
    return LineFormat("csv", tuple(columns), dict(units), len(names), columns, time_col, scale, delimiter, tuple(names))


class BoardLineReader:
    """Feed it the bytes a board sends, in chunks of any size; it returns the readings of the lines completed.

    Parameters
    ----------
    fmt : str
        One of :data:`FORMATS`; ``auto`` recognises the format from the first lines.
    clock : callable
        The host's clock for the arrival times (``time.monotonic``).

    Attributes
    ----------
    format : LineFormat or None
        The format, once recognised.
    lines : int
        Lines seen (empty lines are not counted).
    skipped : int
        Lines that were not readings (boot text, a header printed again, a truncated line).
    last_unreadable : str or None
        The last of them, for messages.
    """

    def __init__(self, fmt: str = "auto", clock=time.monotonic):
        if fmt not in FORMATS:
            raise LogFormatError(f"unknown board line format {fmt!r}: use one of {', '.join(FORMATS)}")
        self.choice = fmt
        self.clock = clock
        self._chosen = {"raw": RAW_FORMAT, "uni": UNI_FORMAT}.get(fmt)  # known once its first reading comes
        self.format: LineFormat | None = None
        self.lines = 0
        self.skipped = 0
        self.last_unreadable: str | None = None
        self._rest = ""
        self._held: list[tuple[str, float]] = []
        self._header: LineFormat | None = None
        self._header_line = ""

    # -- bytes to lines -------------------------------------------------------------------------
    def feed(self, data: bytes | str, arrival_s: float | None = None) -> list[BoardReading]:
        """The readings of the lines that ``data`` completes, stamped ``arrival_s`` (else the clock now)."""
        now = self.clock() if arrival_s is None else float(arrival_s)
        text = data if isinstance(data, str) else data.decode("utf-8", errors="replace")
        text = self._rest + text.replace("\x00", "")
        parts = _LINE_END.split(text)
        self._rest = parts.pop()
        out: list[BoardReading] = []
        for line in parts:
            out += self.line(line, now)
        return out

    def finish(self, arrival_s: float | None = None) -> list[BoardReading]:
        """The reading of a last line that ended without a line end (the port closed)."""
        rest, self._rest = self._rest, ""
        now = self.clock() if arrival_s is None else float(arrival_s)
        out = self.line(rest, now) if rest.strip() else []
        if self.format is None:
            self._skip_held()
            if self._header is not None:
                self._skip(self._header_line)
                self._header = None
        return out

    # -- one line -------------------------------------------------------------------------------
    def line(self, line: str, arrival_s: float) -> list[BoardReading]:
        """The reading of one line (without its line end): a list of none or one (or, when the line
        decides the format, the readings of the lines held until then)."""
        line = line.strip()
        if not line:
            return []
        self.lines += 1
        if self.format is None and self._chosen is not None:  # raw or uni: the first reading says which sensors
            prefix = MOTIONCAL_RAW["prefix"] if self._chosen.name == "raw" else ADAFRUIT_UNI["prefix"]
            values = _prefixed(line, prefix, 9)
            if values is None:
                self._skip(line)
                return []
            self.format = _printed(self._chosen, values)
        if self.format is None:
            return self._detect(line, arrival_s)
        reading = self._parse(line, arrival_s)
        if reading is None:
            self._skip(line)
            return []
        return [reading]

    def _skip(self, line: str) -> None:
        self.skipped += 1
        self.last_unreadable = line[:200]

    def _detect(self, line: str, arrival_s: float) -> list[BoardReading]:
        choice = self.choice
        found = None
        if choice == "auto" and (values := _prefixed(line, MOTIONCAL_RAW["prefix"], 9)) is not None:
            found = _printed(RAW_FORMAT, values)
        elif choice == "auto" and (values := _prefixed(line, ADAFRUIT_UNI["prefix"], 9)) is not None:
            found = _printed(UNI_FORMAT, values)
        elif choice in ("auto", "csv") and (header := csv_format(line)) is not None:
            self._skip_held()  # boot text before the header (and an earlier header never confirmed)
            if self._header is not None:
                self._skip(self._header_line)
            self._header, self._header_line = header, line  # confirmed by the next row of as many numbers
            return []
        elif choice in ("auto", "csv", "numbers") and (values := _numbers(line)) is not None:
            if self._header is not None and len(values) == self._header.width:
                found = self._header
            elif choice != "csv" and numbers_format(len(values)) is not None:
                # two lines in a row of as many numbers make bare numbers
                last = self._held[-1][0] if self._held else None
                prev = _numbers(last) if last is not None else None
                if prev is not None and len(prev) == len(values):
                    found = numbers_format(len(values))
        if found is None:
            self._held.append((line, arrival_s))
            if len(self._held) > DETECT_LINES:
                self._skip(self._held.pop(0)[0])
            return []
        self.format = found
        held, self._held = self._held, []
        out = []
        for old, at in held:
            reading = self._parse(old, at)
            if reading is None:
                self._skip(old)
            else:
                out.append(reading)
        reading = self._parse(line, arrival_s)
        return out + ([reading] if reading is not None else [])

    def _skip_held(self) -> None:
        for old, _ in self._held:
            self._skip(old)
        self._held = []

    def _parse(self, line: str, arrival_s: float) -> BoardReading | None:
        f = self.format
        assert f is not None, "lines are parsed once their format is known"
        if f.name in ("raw", "uni"):
            prefix = MOTIONCAL_RAW["prefix"] if f.name == "raw" else ADAFRUIT_UNI["prefix"]
            values = _prefixed(line, prefix, 9)
            if values is None:
                return None
            scale = RAW_SCALES if f.name == "raw" else dict.fromkeys(SENSORS, 1.0)
            return BoardReading(
                arrival_s,
                None,
                {
                    s: tuple(v * scale[s] for v in values[3 * i : 3 * i + 3])
                    for i, s in enumerate(SENSORS)
                    if s in f.sensors
                },
            )
        if f.name == "csv":
            try:
                delimiter = f.delimiter or WHITESPACE  # csv_format always names one
                row = next(csv.reader([line], delimiter=delimiter)) if delimiter != WHITESPACE else line.split()
                values = [float(v) for v in row] if len(row) == f.width else None
            except ValueError:
                values = None
        else:
            values = _numbers(line)
        if values is None or len(values) != f.width or not all(math.isfinite(v) for v in values):
            return None
        board_time = values[f.time_col] if f.time_col is not None else None
        assert f.columns is not None, "csv and numbers formats map their columns"
        return BoardReading(arrival_s, board_time, {s: tuple(values[c] for c in cols) for s, cols in f.columns.items()})


class StreamRate:
    """The board's rate from live lines without a time column: readings counted over their arrival.

    A board prints at its own rate; a USB-serial bridge's buffer or a loaded host hands its lines over in
    bursts (63 lines at once about every second from a board at 62.5 Hz), and a read may split a burst in
    two. Each chunk's arrival is a point (t, readings so far). A burst ends at a point whose next arrival
    comes after at least half the longest step seen (a split's parts come closer together); when a burst
    ends, every line printed until then has arrived. The rate is the readings counted between the end of
    the first burst and the end of the latest one, over the time between them — the span rule of uploads
    (:func:`app.io.readers.timing.decide_timing`: samples over time, never one step), taken between
    moments when the count is whole. A steady stream's every chunk ends a "burst". It is decided once
    those ends span :data:`app.io.board.formats.RATE_MIN_S` and :data:`~app.io.board.formats.RATE_STEPS`
    times the longest step among the arrivals of the last :data:`~app.io.board.formats.RATE_WINDOW_S`
    (bursts of 1–2 s: after 3–4 bursts) and the rates over the span's two halves agree within
    :data:`~app.io.board.formats.RATE_AGREE` (else once the arrivals fill the window), and stays decided.
    When the window's arrivals do not decide, those after its longest pause (a page busy drawing as the
    board connected, a host's hiccup) may, by the same rule with the halves agreeing, once their ends span
    what the window needs (``RATE_STEPS`` times that pause): a short pause is not waited out until it
    leaves the window.
    The page's twin is ``StreamRate`` of static/js/board_lines.js, on the same constants.
    """

    def __init__(self, min_s: float = RATE_MIN_S, steps: float = RATE_STEPS, window_s: float = RATE_WINDOW_S):
        self.min_s, self.steps, self.window_s = min_s, steps, window_s
        self.count = 0
        self.longest = 0.0
        self.points: list[tuple[float, int]] = []  # until decided: every arrival
        self.first: tuple[float, int] | None = None  # the end of the first burst, once decided
        self.end: tuple[float, int] | None = None  # the end of the latest
        self.last: tuple[float, int] | None = None  # the latest arrival

    def arrive(self, readings: int, arrival_s: float) -> None:
        """A chunk bringing ``readings`` readings arrived at ``arrival_s`` (seconds, any origin)."""
        if readings <= 0:
            return
        self.count += readings
        if self.first is not None and self.last is not None:  # decided: the latest burst's end moves on
            step = arrival_s - self.last[0]
            self.longest = max(self.longest, step)
            if step >= 0.5 * self.longest:
                self.end = self.last
        self.last = (arrival_s, self.count)
        if self.first is None:
            self.points.append(self.last)
            self.points = [p for p in self.points if p[0] >= arrival_s - self.window_s]
            gaps = [q[0] - p[0] for p, q in itertools.pairwise(self.points)]
            self.longest = max(gaps, default=0.0)
            decided = self._ends(self.points, gaps, full=arrival_s - self.points[0][0])
            if decided is None and len(gaps) > 1:
                # The arrivals since the window's longest pause (a page busy drawing as the board connected,
                # a host's hiccup) decide alone once they span what the whole window needs and their halves
                # agree: a short pause is not waited out for the whole window.
                after = gaps.index(self.longest) + 1
                decided = self._ends(self.points[after:], gaps[after:], full=None, pause=self.longest)
            if decided is not None:
                self.first, self.end, self.longest = decided
                self.points = []

    def _ends(self, points: list[tuple[float, int]], gaps: list[float], full: float | None, pause: float = 0.0):
        """The first and the latest burst end of ``points`` (``gaps`` apart) and their longest step, if they
        decide the rate: the ends span the needed time (for their longest step, or the ``pause`` before them)
        and the halves agree, or (``full``: the arrivals' age) fill the window."""
        longest = max(gaps, default=0.0)
        ends = [p for p, step in zip(points, gaps) if step >= 0.5 * longest]
        if len(ends) < 2 or ends[-1][0] - ends[0][0] < max(self.min_s, self.steps * max(longest, pause)):
            return None
        if self._halves_agree(ends) or (full is not None and full >= self.window_s - longest):
            return ends[0], ends[-1], longest
        return None

    @staticmethod
    def _slope(p: tuple[float, int], q: tuple[float, int]) -> float:
        return (q[1] - p[1]) / (q[0] - p[0])

    def _halves_agree(self, ends: list[tuple[float, int]]) -> bool:
        """The rates from the first end to the one nearest the middle and from there to the last agree within
        RATE_AGREE: no end among them read late by a lagging reader."""
        middle = 0.5 * (ends[0][0] + ends[-1][0])
        mid = min(ends[1:-1], key=lambda p: abs(p[0] - middle), default=None)
        if mid is None:
            return False
        a, b = self._slope(ends[0], mid), self._slope(mid, ends[-1])
        return abs(a - b) <= RATE_AGREE * 0.5 * (a + b)

    @property
    def span_s(self) -> float:
        """The arrivals' span the rate is counted over (0 while undecided)."""
        return 0.0 if self.first is None or self.end is None else self.end[0] - self.first[0]

    @property
    def needed_s(self) -> float:
        """The span of burst ends the rate is first decided on (longer for longer bursts)."""
        return max(self.min_s, self.steps * self.longest)

    @property
    def rate_hz(self) -> float | None:
        """Readings per second, or None while undecided."""
        if self.first is None or self.end is None:
            return None
        return (self.end[1] - self.first[1]) / (self.end[0] - self.first[0])


def read_lines(lines, fmt: str = "auto", *, arrivals=None) -> tuple[list[BoardReading], BoardLineReader]:
    """All the readings of ``lines`` (text without line ends) as a reader of ``fmt`` makes them, stamped
    ``arrivals`` (one per line; 0, 1, 2 … when None)."""
    reader = BoardLineReader(fmt)
    out: list[BoardReading] = []
    for i, line in enumerate(lines):
        out += reader.line(line, float(i) if arrivals is None else float(arrivals[i]))
    out += reader.finish(float(len(lines)))
    return out, reader


def board_times_s(readings: list[BoardReading], fmt: LineFormat) -> tuple[np.ndarray | None, str | None]:
    """The board's own times in seconds from the first (None when the lines have none), and the unit
    read from the step when the header named none."""
    if fmt.time_col is None or len(readings) < 2:
        return None, None
    t = np.array([r.board_time for r in readings], dtype=float)
    scale, unit = (fmt.time_scale, None) if fmt.time_scale is not None else time_scale(t)
    return (t - t[0]) * scale, unit


def arrival_times_s(readings: list[BoardReading]) -> np.ndarray:
    t = np.array([r.arrival_s for r in readings], dtype=float)
    return t - t[0]


def board_rate(readings: list[BoardReading], fmt: LineFormat, name: str = "the board's lines"):
    """The board's rate (:class:`app.io.readers.timing.Timing`): from its time column, else from the span
    of the arrivals, never from their median step (bursts of a serial host do not change it)."""
    times, _ = board_times_s(readings, fmt)
    if times is None:
        times = arrival_times_s(readings) if len(readings) >= 2 else None
    return decide_timing(times, name=name)


def to_log(
    readings: list[BoardReading],
    fmt: LineFormat,
    *,
    units: dict | None = None,
    chips: dict | None = None,
    lsb_per_g: float | None = None,
    name: str = "the board's lines",
) -> LogData:
    """The readings as a log, their rate decided (:func:`board_rate`) and their units settled at rest
    by the rules of every log (:func:`app.io.readers.units.settle_units`).

    Parameters
    ----------
    readings : list of BoardReading
    fmt : LineFormat
    units : dict, optional
        The caller's units per sensor (``--unit``), checked against the data as any log's are.
    chips, lsb_per_g : optional
        Scales of counts, as for an upload.
    name : str
        How to call the lines in messages.

    Raises
    ------
    LogFormatError
        No readings, or units the data contradict beyond what a warning can say.
    """
    if not readings:
        raise LogFormatError(f"{name} hold no readings: check the baud rate and that the board prints readings")
    arrays = {s: np.array([r.values[s] for r in readings], dtype=float) for s in fmt.sensors}
    times, unit = board_times_s(readings, fmt)
    source = "the board's time column" if times is not None else "the host's arrival times"
    if times is None:
        times = arrival_times_s(readings)
    notes = [f"read as {fmt.words()}"]
    if unit:
        notes.append(f"the board's time read in {unit} (from its step)")
    stated = {s: u for s, u in fmt.units.items() if s in arrays}
    default = {"acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}
    log = LogData(
        acc=arrays.get("acc"),
        gyr=arrays.get("gyr"),
        mag=arrays.get("mag"),
        time_s=times,
        sampling_rate_hz=None,
        units={s: stated.get(s, default[s]) for s in arrays},
        format=f"board-{fmt.name}",
        columns=list(fmt.header) or [f"{s}_{a}" for s in arrays for a in "xyz"],
        notes=tuple(notes),
    )
    timing = decide_timing(times, name=f"{name} ({source})")
    log = dataclasses.replace(
        log, sampling_rate_hz=timing.sampling_rate_hz, timing=timing, notes=log.notes + timing.notes
    )
    stated_by = "the header" if fmt.name == "csv" else f"the {FORMAT_WORDS.get(fmt.name, fmt.name)} format"
    return settle_units(
        log, given=units, stated=stated, chips=chips, lsb_per_g=lsb_per_g, stated_by=stated_by, name=name
    )


LOG_UNIT_WORDS = {"m/s^2": "m/s^2", "g": "g", "deg/s": "deg/s", "rad/s": "rad/s", "uT": "uT"}


class LogWriter:
    """Writes the readings to a CSV log as they are received, in the format's units (named in the header
    when the format states them), with the board's time column when the lines have one, else the time in
    seconds on the board's rate (the caller's ``times``; the host's arrival when none is given):
    ``trical calibrate LOG.csv`` reads it back with the board's rate."""

    def __init__(self, path: Path, fmt: LineFormat):
        self.path = Path(path)
        self.fmt = fmt
        self.file = open(self.path, "w", newline="", encoding="utf-8")  # noqa: SIM115 - open until close()
        self.first_arrival: float | None = None
        time_name = (fmt.header[fmt.time_col] if fmt.header else "time") if fmt.time_col is not None else "time_s"
        names = [time_name]
        for s in fmt.sensors:
            unit = fmt.units.get(s)
            suffix = f" ({LOG_UNIT_WORDS[unit]})" if unit in LOG_UNIT_WORDS else ""
            names += [f"{s}_{a}{suffix}" for a in "xyz"]
        self.file.write(",".join(names) + "\n")
        self.count = 0

    def write(self, readings: list[BoardReading], times=None) -> None:
        """Rows for ``readings``; without a time column, at ``times`` (seconds on the board's clock, from
        its rate: :class:`StreamRate`) when given, else at their arrival."""
        for i, r in enumerate(readings):
            if self.fmt.time_col is not None and r.board_time is not None:
                t = repr(r.board_time) if not float(r.board_time).is_integer() else str(int(r.board_time))
            elif times is not None:
                t = f"{times[i]:.6f}"
            else:
                if self.first_arrival is None:
                    self.first_arrival = r.arrival_s
                t = f"{r.arrival_s - self.first_arrival:.6f}"
            row = [t] + [repr(float(v)) for s in self.fmt.sensors for v in r.values[s]]
            self.file.write(",".join(row) + "\n")
            self.count += 1
        self.file.flush()

    def close(self) -> None:
        if not self.file.closed:
            self.file.close()
