"""The one place that decides a log's sampling rate, from the caller, the file's time column or nothing.

A time column is read in the unit its header names (``time_ms``), else the one its step suggests
(:func:`time_scale`: seconds, milliseconds, microseconds or nanoseconds).  The rate is then taken
from the span of the column, ``(N − 1) / (t_last − t_first)`` with the time lost in gaps left out,
never from the median step: a sensor logged over a serial port (USB CDC, a UART bridge) is often
stamped by the host when its bytes *arrive*, and they arrive in bursts — steps of 1 to 70 ms
around a 10 ms interval, a median step of 2 ms — so the median says 500 Hz of a sensor that gives
100.  The sensor's clock is what the span measures: bursts shift samples, they do not add or drop
them.  When the steps scatter by more than :data:`JITTER_MAX` of the interval a note gives the
figure.

A gap is a step after which the samples stay late: the lower envelope of ``t_i − i·Δt`` (the
arrival's lag behind a steady clock, least in each run of :data:`GAP_WINDOW` samples) jumps by more
than :data:`GAP_INTERVALS` intervals — samples were lost (a full serial buffer, a paused logger).
A burst's long step is followed by samples that catch up, so it is no gap.  Gaps are reported with
their place and length; still segments do not span them and the noise characterisation says when
they make its Allan deviation unreliable.

The caller's ``sampling_rate_hz`` wins (a note says when the time column disagrees by more than
1 %); a rate the file's own metadata states (a wearable's header) comes next.  A log with neither a
rate nor a time column has none: ``sampling_rate_hz`` is None, and only the methods that need one
(noise, cube, autocal) ask for it.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import LogFormatError

if TYPE_CHECKING:  # app.io.log imports this module's Timing
    from ..log import LogData

JITTER_MAX = 0.2
"""Steps that scatter by more than this fraction of the interval (their standard deviation over
the mean, less the timestamps' rounding) are host arrival times, not a sensor's clock: a note says
so, with the figure."""

GAP_INTERVALS = 5.0
"""A lag that grows by more than this many intervals at one step is a gap (samples lost)."""

GAP_WINDOW = 32
"""Samples on each side of a step whose least lag is compared: longer than a burst of a serial
host (a few to ten samples), short enough that a clock error of 1 % moves the lag by a third of an
interval only."""

RATE_RANGE_HZ = (1.0, 10_000.0)
"""Plausible sampling rates, for inferring a time column's unit."""
TYPICAL_RATE_HZ = 80.0
"""A time column of whole numbers in more than one plausible unit takes the one whose rate is
nearest this (in decades): ``1, 2, 3`` is milliseconds at 1 kHz rather than seconds at 1 Hz."""
TIME_UNITS = (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 1e-9))


@dataclass(frozen=True)
class Gap:
    """Samples lost between ``index − 1`` and ``index``: ``missing_s`` seconds, at ``t_s`` from the start."""

    index: int
    t_s: float
    missing_s: float

    def to_dict(self) -> dict[str, Any]:
        return {"index": self.index, "t_s": self.t_s, "missing_s": self.missing_s}


@dataclass(frozen=True)
class Timing:
    """How a log's rate was decided, and what its time column showed.

    Attributes
    ----------
    sampling_rate_hz : float or None
        None when neither the caller, the file nor a time column gives one.
    source : str
        ``sampling_rate_hz`` (the caller's), ``file`` (the file's metadata), ``time column`` or ``none``.
    jitter : float or None
        Standard deviation of the time column's steps (gaps left out) over the interval.
    median_step_s : float or None
    gaps : tuple of Gap
    notes : tuple of str
    """

    sampling_rate_hz: float | None
    source: str
    jitter: float | None = None
    median_step_s: float | None = None
    gaps: tuple[Gap, ...] = ()
    notes: tuple[str, ...] = field(default=())

    @property
    def missing_s(self) -> float:
        return float(sum(g.missing_s for g in self.gaps))

    def to_dict(self) -> dict[str, Any]:
        return {
            "source": self.source,
            "sampling_rate_hz": self.sampling_rate_hz,
            "jitter": self.jitter,
            "median_step_s": self.median_step_s,
            "gaps": [g.to_dict() for g in self.gaps],
            "missing_s": self.missing_s,
        }


def time_scale(time: np.ndarray) -> tuple[float, str]:
    """Seconds per unit of a time column whose header names no unit, and the unit's name.

    The mean step (the span over N − 1: bursts of a serial host do not move it) must give a rate of
    1 Hz to 10 kHz.  A column of whole numbers (``millis()``, ``micros()``) fitting in more than one
    unit takes the one nearest :data:`TYPICAL_RATE_HZ`; a column with fractions takes the first of
    s, ms, µs, ns that fits.

    Raises
    ------
    LogFormatError
        A column that does not increase, or whose step fits no unit.
    """
    time = np.asarray(time, dtype=float)
    span = float(time[-1] - time[0]) if len(time) >= 2 else 0.0
    if not (math.isfinite(span) and span > 0):
        raise LogFormatError(
            "the time column does not increase from its first row to its last: give "
            "sampling_rate_hz or fix the time column"
        )
    step = span / (len(time) - 1)
    fits = [(name, scale) for name, scale in TIME_UNITS if RATE_RANGE_HZ[0] <= 1.0 / (step * scale) <= RATE_RANGE_HZ[1]]
    if not fits:
        raise LogFormatError(
            f"the time column's mean step {step:g} fits no unit (s, ms, µs, ns) for a rate between 1 Hz and "
            "10 kHz: name its unit in the header (time_s, time_ms, time_us, time_ns) or give sampling_rate_hz"
        )
    head = time[:10_000]
    if len(fits) > 1 and np.all(head == np.round(head)):
        name, scale = min(fits, key=lambda f: abs(math.log10(1.0 / (step * f[1]) / TYPICAL_RATE_HZ)))
    else:
        name, scale = fits[0]
    return scale, name


def _check_rate(rate: float) -> float:
    if not (rate is not None and np.isfinite(rate) and rate > 0):
        raise LogFormatError(f"sampling_rate_hz must be a positive number; got {rate}")
    return float(rate)


def find_gaps(time_s: np.ndarray, interval_s: float, steps: np.ndarray | None = None) -> tuple[Gap, ...]:
    """The steps after which the samples stay more than :data:`GAP_INTERVALS` intervals late.

    Parameters
    ----------
    time_s : numpy.ndarray
        Non-decreasing sample times in seconds.
    interval_s : float
        The sensor's sampling interval.
    steps : numpy.ndarray, optional
        ``numpy.diff(time_s)``, when the caller has it already.
    """
    n = len(time_s)
    if n < 3:
        return ()
    if steps is None:
        steps = np.diff(time_s)
    limit = GAP_INTERVALS * interval_s
    candidates = np.flatnonzero(steps > limit)  # the step from sample i to i + 1
    if len(candidates) == 0:
        return ()
    lag = time_s - np.arange(n) * interval_s
    w = GAP_WINDOW
    padded = np.concatenate([np.full(w, np.inf), lag, np.full(w, np.inf)])
    offsets = np.arange(w)
    jumps = np.empty(len(candidates))
    for a in range(0, len(candidates), 1 << 15):
        c = candidates[a : a + (1 << 15)]
        before = padded[(c + w)[:, None] - offsets].min(axis=1)  # samples c − w + 1 … c
        after = padded[(c + w + 1)[:, None] + offsets].min(axis=1)  # samples c + 1 … c + w
        jumps[a : a + len(c)] = after - before
    found = candidates[jumps > limit]
    gaps: list[Gap] = []
    for i in found:  # a gap's neighbours see part of its jump: the longest step within a window is the gap
        if gaps and i + 1 - gaps[-1].index < w:
            if steps[i] <= steps[gaps[-1].index - 1]:
                continue
            gaps.pop()
        gaps.append(Gap(index=int(i + 1), t_s=float(time_s[i] - time_s[0]), missing_s=float(steps[i] - interval_s)))
    return tuple(gaps)


MEDIAN_SAMPLE = 8192
"""Evenly spaced values of a long array whose middle two per cent bound its median (:func:`exact_median`)."""


def exact_median(values: np.ndarray) -> float:
    """``float(numpy.median(values))`` of a 1-D float array, the same to the last bit, without
    partitioning a copy of all of it (a 3 h log at 200 Hz: 2 M steps, 17 MB).

    The middle two per cent of :data:`MEDIAN_SAMPLE` evenly spaced values give a band ``[lo, hi]``;
    when the counts below and above it show that the middle order statistics lie inside it, only the
    values inside are partitioned (a band of one value, as a steady clock's steps give, needs none),
    and the two middle ones are averaged as numpy averages them (``numpy.median``: the mean of the
    middle one or two values of a partition, NaN when any value is NaN). Otherwise (a band that misses
    the middle, a NaN, fewer than 8 × :data:`MEDIAN_SAMPLE` values) numpy's median of all the values is
    returned.

    Parameters
    ----------
    values : numpy.ndarray
        1-D, float.
    """
    n = len(values)
    if n < 8 * MEDIAN_SAMPLE:
        return float(np.median(values))
    sample = np.sort(values[:: n // MEDIAN_SAMPLE])
    lo, hi = sample[int(0.49 * len(sample))], sample[int(0.51 * len(sample))]
    below, above = int(np.count_nonzero(values < lo)), int(np.count_nonzero(values > hi))
    first, second = (n - 1) // 2, n // 2  # numpy's middle order statistics: one when n is odd
    if not (below <= first and second < n - above):
        return float(np.median(values))
    inside = values == lo if lo == hi else (values >= lo) & (values <= hi)
    if np.count_nonzero(inside) != n - below - above:  # a NaN, in no count: numpy's median is NaN
        return float(np.median(values))
    middle = (
        np.array([lo, lo])  # a band of equal values
        if lo == hi
        else np.partition(values[inside], [first - below, second - below])[[first - below, second - below]]
    )
    return float(np.mean(middle[: 1 if first == second else 2]))


def _rate_of(time_s: np.ndarray, steps: np.ndarray) -> tuple[float, tuple[Gap, ...]]:
    """The rate from the span with the time of gaps left out, and the gaps (a few rounds: the gaps are
    found with the interval, the interval without the gaps)."""
    n = len(time_s)
    span = float(time_s[-1] - time_s[0])
    gaps: tuple[Gap, ...]
    interval, gaps = span / (n - 1), ()
    for _ in range(4):
        gaps = find_gaps(time_s, interval, steps)
        missing = sum(g.missing_s for g in gaps)
        new = (span - missing) / (n - 1)
        if not new > 0 or abs(new - interval) <= 1e-9 * interval:
            break
        interval = new
    return 1.0 / interval, gaps


def _jitter(time_s: np.ndarray, steps: np.ndarray, interval: float) -> float:
    """The steps' standard deviation over the interval, less what the timestamps' rounding explains:
    times rounded to a resolution q (``millis()``: 1 ms) scatter each step by q²/6 in variance even on a
    perfect clock (two independent roundings, uniform errors of variance q²/12 each). q is the largest
    power of ten, down to a hundredth of the interval, that every time is a whole multiple of."""
    if len(steps) == 0:
        return 0.0
    var = float(np.var(steps))
    head = time_s[:10_000] - time_s[0]
    q = 10.0 ** math.floor(math.log10(interval))
    while q >= interval / 100.0:
        if np.allclose(head / q, np.round(head / q), rtol=0.0, atol=1e-6):
            var = max(var - q * q / 6.0, 0.0)
            break
        q /= 10.0
    return math.sqrt(var) / interval


def _ms(seconds: float) -> str:
    return f"{seconds * 1e3:.3g} ms"


def _gap_note(gaps: tuple[Gap, ...], name: str) -> str:
    longest = max(gaps, key=lambda g: g.missing_s)
    total = sum(g.missing_s for g in gaps)
    return (
        f"{len(gaps)} gap{'s' if len(gaps) > 1 else ''} in the time column of {name} (the longest "
        f"{longest.missing_s:.3g} s at {longest.t_s:.1f} s, {total:.3g} s in all): samples were lost on the "
        "way (a full serial buffer, a paused logger); still segments do not span a gap"
    )


def decide_timing(
    time_s: np.ndarray | None,
    sampling_rate_hz: float | None = None,
    *,
    file_rate_hz: float | None = None,
    name: str = "the file",
) -> Timing:
    """The sampling rate of a log and what its time column shows (module docstring).

    Parameters
    ----------
    time_s : numpy.ndarray or None
        The time column in seconds (any origin), or None when the file has none.
    sampling_rate_hz : float, optional
        The caller's rate, which wins.
    file_rate_hz : float, optional
        A rate the file's own metadata states; wins over the time column.
    name : str
        How to call the file in messages.

    Returns
    -------
    Timing

    Raises
    ------
    LogFormatError
        A rate given that is not positive, or a time column that does not increase from its first
        row to its last.
    """
    given = None if sampling_rate_hz is None else _check_rate(sampling_rate_hz)
    stated = None if file_rate_hz is None else _check_rate(file_rate_hz)
    if time_s is None or len(time_s) < 2:
        if given is not None:
            return Timing(given, "sampling_rate_hz")
        if stated is not None:
            return Timing(stated, "file")
        return Timing(
            None,
            "none",
            notes=(
                f"{name} has no time column and sampling_rate_hz was not given: the still poses and the compass need "
                "no rate; the noise, cube and autocal methods ask for one (sampling_rate_hz)",
            ),
        )
    time_s = np.asarray(time_s, dtype=float)
    steps = np.diff(time_s)
    if not float(time_s[-1] - time_s[0]) > 0:
        raise LogFormatError(
            f"the time column of {name} does not increase from its first row to its last: give "
            "sampling_rate_hz or fix the time column"
        )
    notes: list[str] = []
    back = np.flatnonzero(steps < 0)
    if len(back):
        # A timer that wrapped, or files joined: the span means nothing; the median step is all there is.
        i = int(back[0])
        rate = 1.0 / exact_median(steps[steps > 0])
        notes.append(
            f"the time column of {name} goes back {len(back)} time(s), first after sample {i + 1} "
            f"({time_s[i]:.6g} → {time_s[i + 1]:.6g} s): its rate, {rate:.4g} Hz, is one over the median "
            "step; give sampling_rate_hz if that is not the sensor's rate"
        )
        return Timing(
            given or stated or rate,
            "sampling_rate_hz" if given else "file" if stated else "time column",
            median_step_s=exact_median(steps),
            notes=tuple(notes),
        )
    measured, gaps = _rate_of(time_s, steps)
    rate, source = (given, "sampling_rate_hz") if given else (stated, "file") if stated else (measured, "time column")
    if given or stated:
        gaps = find_gaps(time_s, 1.0 / rate, steps)
        if abs(measured / rate - 1.0) > 0.01:
            notes.append(
                f"the {'given' if given else 'file’s'} rate {rate:g} Hz is used; the time column's span "
                f"says {measured:.4g} Hz"
            )
    kept = np.delete(steps, [g.index - 1 for g in gaps]) if gaps else steps
    interval = 1.0 / rate
    median = exact_median(steps)
    jitter = _jitter(time_s, kept, interval)
    if jitter > JITTER_MAX:
        # No step is negative here: when none is 0 either, the positive ones are all of them.
        positive = steps if steps.min() > 0 else steps[steps > 0]
        median_rate = 1.0 / (median if positive is steps else exact_median(positive)) if len(positive) else math.inf
        notes.append(
            f"the timestamps of {name} are irregular: their steps scatter by {100 * jitter:.0f} % of the interval "
            f"(from {_ms(float(kept.min()))} to {_ms(float(kept.max()))}, median {_ms(median)}), as when a host stamps "
            f"a serial stream's bursts on arrival; "
            + (
                f"the rate is {rate:.4g} Hz from the span, (N − 1)/(t_last − t_first)"
                f"{' without the gaps' if gaps else ''}, not {median_rate:.4g} Hz from the median step: give "
                "sampling_rate_hz if you know the sensor's output data rate"
                if source == "time column"
                else f"the {'given' if given else 'file’s'} rate {rate:.4g} Hz is used, not {median_rate:.4g} Hz "
                "from the median step"
            )
        )
    if gaps:
        notes.append(_gap_note(gaps, name))
    return Timing(rate, source, jitter=jitter, median_step_s=median, gaps=gaps, notes=tuple(notes))


def with_timing(log: LogData, sampling_rate_hz: float | None = None, name: str = "the file") -> LogData:
    """``log`` (a :class:`~app.io.log.LogData`) with its rate decided by :func:`decide_timing` and the
    notes of that decision; a log whose timing is decided already is returned as it is. A reader
    leaves ``sampling_rate_hz`` None, or sets the rate its file's metadata states."""
    if log.timing is not None:
        return log
    timing = decide_timing(log.time_s, sampling_rate_hz, file_rate_hz=log.sampling_rate_hz, name=name)
    return dataclasses.replace(
        log, sampling_rate_hz=timing.sampling_rate_hz, timing=timing, notes=tuple(log.notes) + timing.notes
    )
