"""The capture on a board's port behind ``trical capture PORT`` (:mod:`app.cli.capture` opens the port): the guided
calibration of a board in the terminal.

The board's lines are read as they arrive (:mod:`app.io.board.lines`), timed on the board's clock — its
time column, else its rate counted over several seconds of arrivals (:class:`app.io.board.lines.StreamRate`),
so that lines handed over in bursts are neither motion nor gaps — written to a CSV log and watched by the
hands-free capture engine the page uses: the device is still when the per-axis
spread of the accelerometer over a moving window (and the mean rotation rate, when the lines carry a
gyroscope) falls below the page's thresholds, and moving again above their higher limits (hysteresis);
held still for the page's hold time in a new pose, a capture starts, and it is done after the capture
length unless the board moves (refused, and it starts again once still). A capture that makes no progress
for :data:`app.io.board.formats.STALL_S` says what it waits for and what it sees. The thresholds are the
page's own, the Python constants
:func:`app.guided.capture_rules.capture_thresholds`, which the page's tables render for it.

Then the log is calibrated (``auto``, or the protocol's method) and the verdict printed. The six and free
flows calibrate from their own captures, as a wizard session does: the log's rows of each capture are its
still segment (:func:`capture_segments`), not stretches found again in the log — a capture is as long as
the person was asked to hold still (``--capture-s``), which may be shorter than the stretch the log's
segment detector asks for. The cube flow's method finds its rests and turns in the log itself.

Nothing here opens a port: the caller gives an object with ``read(n)`` (pyserial's ``Serial``, or a
pseudo-terminal in the tests).
"""

from __future__ import annotations

import math
import time
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from app.calibration.shared.gravity import STANDARD_GRAVITY
from app.calibration.shared.orientations import UP_VECTORS, nearest_orientation
from app.guided.capture_rules import CAPTURE_S_DEFAULT, CAPTURE_S_RANGE, capture_thresholds
from app.guided.protocols import BOARD_PROTOCOLS, Protocol
from app.io.board.formats import DEFAULT_BAUD, SILENCE_S, STALL_S
from app.io.board.lines import BoardLineReader, LogWriter, StreamRate, board_rate, to_log
from app.io.errors import LogFormatError
from app.io.readers.timing import time_scale

CHECK_S = 1.0
"""Seconds of readings the unit is checked on, at rest, before any capture."""


@dataclass
class Event:
    kind: str  # "start", "done", "refused"
    label: str | None = None
    text: str = ""


@dataclass
class StillEngine:
    """The page's capture machine for still poses, on the board's time (seconds) and readings normalised
    so that the accelerometer rests at g (m/s²) and the gyroscope in °/s (None when the lines have none)."""

    protocol: Protocol  # a posed one (``poses`` set): app.guided.protocols
    capture_s: float
    thresholds: dict = field(default_factory=capture_thresholds)
    window: deque = field(default_factory=deque)
    still: bool = False
    moved: bool = True
    hold_since: float | None = None
    capture_since: float | None = None
    label: str | None = None
    capture_from: int | None = None
    done: list = field(default_factory=list)  # (label, mean direction)
    rows: list = field(default_factory=list)  # (label, first row, row after the last) of each capture
    seen: tuple | None = None  # (spread m/s², rotation °/s or None, mean) of the last full window

    def update(self, t: float, acc: np.ndarray, gyr: np.ndarray | None, row: int = 0) -> list[Event]:
        """Take one reading (time ``t`` in s, the log's ``row``) and return what happened."""
        th = self.thresholds
        self.window.append((t, acc, gyr))
        while self.window and self.window[0][0] < t - th["windowMs"] / 1000.0:
            self.window.popleft()
        if len(self.window) < 5 or t - self.window[0][0] < 0.8 * th["windowMs"] / 1000.0:
            return []
        a = np.array([w[1] for w in self.window])
        spread = float(a.std(axis=0).max())
        rate = None if gyr is None else float(np.linalg.norm(np.mean([w[2] for w in self.window], axis=0)))
        self.seen = (spread, rate, a.mean(axis=0))
        if self.still:
            self.still = not (spread > th["spreadHigh"] or (rate is not None and rate > th["gyrHigh"]))
        else:
            self.still = spread < th["spreadLow"] and (rate is None or rate < th["gyrLow"])
        events: list[Event] = []
        if not self.still:
            self.moved = True
            self.hold_since = None
            if self.capture_since is not None:
                events.append(
                    Event(
                        "refused",
                        self.label,
                        f"{self.label}: the board moved during the capture; hold it still and it starts again",
                    )
                )
                self.capture_since = None
            return events
        mean = a.mean(axis=0)
        if self.capture_since is not None:
            if t - self.capture_since >= self.capture_s:
                self.done.append((self.label, mean / np.linalg.norm(mean)))
                self.rows.append((self.label, self.capture_from, row + 1))
                events.append(
                    Event("done", self.label, f"{self.label} captured ({len(self.done)} of {self.protocol.poses})")
                )
                self.capture_since = None
                self.moved = False
            return events
        label = self.protocol.label(mean, self.done, th["maxAngleDeg"]) if self.moved else None
        if label is None:
            self.hold_since = None
            return events
        if self.hold_since is None:
            self.hold_since = t
        if t - self.hold_since >= th["holdMs"] / 1000.0:
            self.capture_since, self.capture_from, self.label = t, row, label
            events.append(Event("start", label, f"{label}: capturing {self.capture_s:g} s, hold still"))
        return events

    @property
    def finished(self) -> bool:
        return self.protocol.poses is not None and len(self.done) >= self.protocol.poses

    def waiting_words(self) -> str:
        """What the engine waits for and what it sees now, for a capture that makes no progress: the poses
        asked and the stillness of the last window against the thresholds."""
        th = self.thresholds
        done = [d[0] for d in self.done]
        left = [p for p in getattr(self.protocol, "positions", ()) if p not in done]
        asked = f"waiting for {' or '.join(left)}" if left else "waiting for a new pose"
        if self.seen is None:
            return f"{asked}: no full window of readings yet"
        spread, rate, mean = self.seen
        limit_a = th["spreadHigh"] if self.still else th["spreadLow"]
        limit_w = th["gyrHigh"] if self.still else th["gyrLow"]
        if not self.still:
            if rate is not None and rate >= limit_w and spread < limit_a:
                seen = f"the board turns: {rate:.2g} °/s > {limit_w:g}"
            else:
                seen = f"the board moves: spread {spread:.2g} m/s² > {limit_a:g}"
            return f"{asked}: {seen}; hold it still in a pose asked"
        up = nearest_orientation(mean, 90.0)
        assert up is not None, "every direction is within 90° of an axis"
        axis = np.asarray(UP_VECTORS[up])
        angle = math.degrees(math.acos(max(-1.0, min(1.0, float(axis @ mean) / float(np.linalg.norm(mean))))))
        if up in done:
            return f"{asked}: the board is still with {up} up, captured already; turn it to a pose asked"
        if angle > th["maxAngleDeg"]:
            return (
                f"{asked}: the board is still, {angle:.0f}° from {up} (a pose is within {th['maxAngleDeg']:g}°); "
                "set it square on a side"
            )
        return f"{asked}: the board is still with {up} up; keep it so"


def capture_segments(acc: np.ndarray, rows: list) -> list[dict]:
    """The still segments of a captured log: one per capture, its rows as the engine captured them.

    Parameters
    ----------
    acc : numpy.ndarray, shape (N, 3)
        The log's accelerometer as read back (its unit settled as for any log), one row per reading received.
    rows : list of (label, start, end)
        Each capture's label and rows ``start:end`` (:attr:`StillEngine.rows`).

    Returns
    -------
    list of dict
        Segments in the plain form of ``POST /api/v1/recordings`` (``index``, ``start``, ``end``,
        ``acc_mean``, ``acc_std``, ``up``, ``count``), ``capture`` naming the engine's label; ``up`` is the
        axis within 20° of the mean, as for the segments found in a log.
    """
    segments: list[dict] = []
    for label, start, end in rows:
        window = np.asarray(acc[start:end], dtype=float)
        mean = window.mean(axis=0)
        segments.append(
            {
                "index": len(segments),
                "start": int(start),
                "end": int(end),
                "acc_mean": [float(v) for v in mean],
                "acc_std": [float(v) for v in window.std(axis=0)],
                "up": nearest_orientation(mean),
                "count": int(end - start),
                "capture": label,
            }
        )
    return segments


@dataclass
class CaptureOutcome:
    status: str  # "finished", "interrupted", "refused", "timeout"
    log_path: Path | None
    readings: int
    format: object = None
    rate_hz: float | None = None
    message: str = ""
    rows: list = field(default_factory=list)  # (label, start, end) of each capture


class Capture:
    """Read a board's lines from ``port`` until the protocol is done, writing the log as received.

    Parameters
    ----------
    port
        An object with ``read(n) -> bytes`` returning what has arrived (pyserial with a timeout).
    protocol : str
        One of app.guided.protocols.BOARD_PROTOCOLS.
    out_path : Path
        The CSV log to write.
    say : callable
        Prints one line per step.
    live : callable or None
        Shows the current reading (one line rewritten), or None.
    """

    def __init__(
        self,
        port,
        *,
        protocol: str,
        out_path: Path,
        fmt: str = "auto",
        units: dict | None = None,
        minutes: float | None = None,
        capture_s: float | None = None,
        baud: int = DEFAULT_BAUD,
        say=print,
        bell=None,
        live=None,
        clock=time.monotonic,
    ):
        self.port, self.protocol, self.out_path = port, BOARD_PROTOCOLS[protocol], Path(out_path)
        self.reader = BoardLineReader(fmt, clock)
        self.units = units or {}
        self.seconds = 60.0 * (minutes if minutes is not None else self.protocol.minutes)
        self.capture_s = CAPTURE_S_DEFAULT if capture_s is None else max(CAPTURE_S_RANGE[0], capture_s)
        self.baud, self.say, self.bell, self.live, self.clock = baud, say, bell or (lambda: None), live, clock
        self.readings: list = []
        self.writer: LogWriter | None = None
        self.engine = StillEngine(self.protocol, self.capture_s) if self.protocol.poses else None
        self.checked = False
        self.acc_scale: float | None = None
        self.gyr_scale: float | None = None
        self.time_scale: float | None = None
        self.record_from: float | None = None
        self.stream = StreamRate()
        self.times: list[float] = []  # each reading's time on the board's clock (s), once the rate is known
        self.written = 0
        self.fed = 0
        self.progress_at: float | None = None
        self.silence_said = False  # the silence is said once
        self.last_live = 0.0  # when the live line was last rewritten

    def _step(self, text: str, bell: bool = False) -> None:
        if bell:
            self.bell()
        self.say(text)

    def _check_units(self) -> None:
        """The units at rest (the rules of every log) and the factors that put the readings in m/s² and °/s
        for the still detection."""
        fmt = self.reader.format
        assert fmt is not None, "the units are checked once the lines' format is known"
        log = to_log(self.readings, fmt, units=self.units, name="the board's first second")
        words = ", ".join(f"{s} {u}" for s, u in log.units.items())
        rate = self._rate()
        source = (
            "the board's time column"
            if fmt.time_col is not None
            else f"{len(self.readings)} readings counted over {self.stream.span_s:.1f} s of arrivals"
        )
        self._step(f"units checked at rest: {words}; rate {rate:.4g} Hz ({source})")
        for w in log.warnings:
            self._step(f"warning: {w}")
        if "acc" in fmt.sensors:
            raw = np.array([r.values["acc"] for r in self.readings], dtype=float)
            self.acc_scale = STANDARD_GRAVITY / float(np.median(np.linalg.norm(raw, axis=1)))
        gyr_unit = log.units.get("gyr")
        if "gyr" in fmt.sensors and gyr_unit in ("rad/s", "deg/s"):
            self.gyr_scale = 180.0 / math.pi if gyr_unit == "rad/s" else 1.0
        if fmt.time_col is not None:  # the board's clock, in the unit the header names or its step shows
            t = np.array([r.board_time for r in self.readings], dtype=float)
            self.time_scale = fmt.time_scale or time_scale(t)[0]
        self.checked = True

    def _rate(self) -> float | None:
        """The board's rate: its time column's (the upload rule) once it spans :data:`CHECK_S`, else the
        count of readings over their arrival (:class:`app.io.board.lines.StreamRate`); None while unknown."""
        fmt = self.reader.format
        if fmt is not None and fmt.time_col is not None:
            if len(self.readings) < 2:
                return None
            try:
                timing = board_rate(self.readings, fmt)
            except LogFormatError:
                return None
            span = (len(self.readings) - 1) / timing.sampling_rate_hz
            return timing.sampling_rate_hz if span >= CHECK_S else None
        return self.stream.rate_hz

    def _clock(self) -> None:
        """Times for the readings not yet timed: the board's own, else one interval of the rate after the
        last (a burst neither repeats a time nor makes a gap)."""
        rate = None if self.time_scale is not None else self._rate()
        for r in self.readings[len(self.times) :]:
            if self.time_scale is not None:
                self.times.append(float(r.board_time) * self.time_scale)
            else:
                assert rate is not None, "the clock runs once the board's time or rate is known"
                self.times.append(self.times[-1] + 1.0 / rate if self.times else 0.0)

    def _write(self) -> None:
        if self.writer is not None and self.written < len(self.times):
            self.writer.write(self.readings[self.written : len(self.times)], self.times[self.written :])
            self.written = len(self.times)

    def _feed_engine(self) -> None:
        while self.fed < len(self.times):
            row, r = self.fed, self.readings[self.fed]
            self.fed += 1
            if self.engine is None or "acc" not in r.values:
                continue
            acc = np.asarray(r.values["acc"], dtype=float) * self.acc_scale
            gyr = None if self.gyr_scale is None else np.asarray(r.values["gyr"], dtype=float) * self.gyr_scale
            for e in self.engine.update(self.times[row], acc, gyr, row):
                if e.kind in ("start", "done"):
                    self.progress_at = self.clock()
                self._step(e.text, bell=True)
            if self.engine.finished:
                return

    def _stalled(self, now: float) -> None:
        """Every :data:`app.io.board.formats.STALL_S` without a capture started or done: what the engine
        waits for, what it sees, and what to do."""
        if self.engine is None or self.progress_at is None or now - self.progress_at < STALL_S:
            return
        self.progress_at = now
        self._step(
            f"no capture for {STALL_S:g} s, {self.engine.waiting_words()}; Ctrl-C keeps the log "
            f"({self.out_path}) and says how to finish it",
            bell=True,
        )

    def run(self) -> CaptureOutcome:
        opened = self.clock()
        try:
            while True:
                now = self.clock()
                data = self.port.read(4096)
                new = self.reader.feed(data, now) if data else []
                self._open_log()
                self._arrive(new, now, now - opened)
                outcome = self._start(now) if not self.checked and self._rate() is not None else None
                if outcome is None and self.checked:
                    outcome = self._advance(now, new)
                if outcome is None and now - opened > self.seconds + (60.0 if self.engine is None else 0.0):
                    self._step(f"refused: {self.seconds / 60:g} min passed before the protocol was done", bell=True)
                    outcome = self._outcome("timeout")
                if outcome is not None:
                    return outcome
        except KeyboardInterrupt:
            return self._outcome("interrupted")
        finally:
            if self.writer is not None:
                self._write_rest()
                self.writer.close()

    def _open_log(self) -> None:
        """The log, once the lines' format is known (its header names their columns)."""
        if self.reader.format is None or self.writer is not None:
            return
        self.writer = LogWriter(self.out_path, self.reader.format)
        skipped = f"; {self.reader.skipped} lines that are not readings skipped" if self.reader.skipped else ""
        self._step(f"lines read as {self.reader.format.words()}{skipped}")

    def _arrive(self, new: list, now: float, waited_s: float) -> None:
        """The readings that arrived, counted for the rate; or, once, why none came after SILENCE_S."""
        if new:
            self.readings += new
            self.stream.arrive(len(new), now)
            return
        if self.readings or self.silence_said or waited_s <= SILENCE_S:
            return
        self.silence_said = True
        if self.reader.lines:
            self._step(
                f"lines arrive but none is a reading; the last: {self.reader.last_unreadable!r}: "
                "choose the format with --format, or check the sketch",
                bell=True,
            )
        else:
            self._step(
                f"Nothing arrives at {self.baud} baud: check the rate and that the board prints readings", bell=True
            )

    def _start(self, now: float) -> CaptureOutcome | None:
        """The units checked at rest once the rate is known, then the protocol's first words; a refusal ends it."""
        try:
            self._check_units()
        except LogFormatError as exc:
            self._step(f"refused: {exc}", bell=True)
            return self._outcome("refused", str(exc))
        self.record_from = self.progress_at = now
        if self.engine is None:
            self._step(f"recording {self.seconds:g} s: {self.protocol.words}", bell=True)
        else:
            self._step(self.protocol.words)
        return None

    def _advance(self, now: float, new: list) -> CaptureOutcome | None:
        """One step of a checked capture: the board's clock, the log, the poses, the live line; the end when the
        protocol is done or the recording is long enough."""
        self._clock()
        self._write()
        self._feed_engine()
        self._stalled(now)
        if self.live and new and now - self.last_live > 0.1:
            self.last_live = now
            self.live(_live_words(new[-1]))
        if self.engine is not None and self.engine.finished:
            self._step(f"all {self.protocol.poses} poses captured", bell=True)
            return self._outcome("finished")
        if self.engine is None and self.record_from is not None and now - self.record_from >= self.seconds:
            self._step(f"recorded {self.seconds:g} s", bell=True)
            return self._outcome("finished")
        return None

    def _write_rest(self) -> None:
        """The readings not yet written (the rate still unknown, or a capture stopped): on the rate once it
        is known, else on their arrival."""
        if self._rate() is not None or self.time_scale is not None:
            self._clock()
            self._write()
        elif self.written == 0 and self.readings and self.writer is not None:
            self.writer.write(self.readings)
            self.written = len(self.readings)

    def _outcome(self, status: str, message: str = "") -> CaptureOutcome:
        rate = self._rate()
        return CaptureOutcome(
            status,
            self.out_path if self.writer is not None else None,
            len(self.readings),
            self.reader.format,
            rate,
            message,
            [] if self.engine is None else list(self.engine.rows),
        )


def _live_words(r) -> str:
    parts = []
    for s, v in r.values.items():
        parts.append(f"{s} " + " ".join(f"{x:9.4g}" for x in v))
    return "  ".join(parts)
