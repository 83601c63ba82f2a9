"""Stationary (rest) segments of a long recording, as Farago et al. section II.B.1 detects them.

Farago et al. (IEEE Access), section II.B.1: the recording is cut into fixed segments (5 s in the
paper, independent of the sampling rate); a segment is at rest when the difference between the
maximum and the minimum of *one* axis stays below a threshold (0.12 g), and its calibration point is
the mean of the three axes over the segment.  Optionally every axis must pass (``all_axes=True``).

Two kinds of segments pass that test without being a measurement of gravity, and are refused:

- **NaN gaps** — a segment holding any NaN (a gap filled with NaN, a lost block) is not rest.
- **Idle-sleep runs** — devices such as ActiGraphs stop sampling when still and repeat the last
  value; a segment holding a run of identical consecutive samples (all three axes equal) lasting
  ``idle_min_run_s`` (1 s) or more is not rest.  A real sensor with noise of a few LSB almost
  never repeats the same triple for 100 samples; a very coarse, very quiet sensor can, and would
  then need a longer ``idle_min_run_s``.

For the comparison with GGIR (van Hees et al. 2014), the detector also gives GGIR's no-movement
windows: 10 s windows (``ggir_window_s``, whole numbers of segments on the recording's own grid)
whose standard deviation stays below 0.013 g on every axis.  They are computed from segments that
already passed the range test, so a window whose segments failed it is never a GGIR window either
(with a 0.013 g standard deviation a range above 0.12 g needs a 9σ spike).

Memory stays bounded whatever the length: :class:`RestAccumulator` is fed chunks of samples (a
memory-mapped array sliced in pieces, batches of a Parquet file...) and keeps only a remainder
shorter than a segment plus a few numbers per rest segment.  Everything inside a chunk is
vectorised: the tested axis is copied out to contiguous rows for its max and min, the still segments
are gathered and summed by a matrix–vector product each (float32 stays float32 until those sums).  A
chunk (256 segments, 1.5 MB at 100 Hz) and its temporaries stay in a core's cache.
:func:`detect_rest_segments` splits a whole recording among threads (numpy releases the GIL), each
scanning whole chunks; every segment's numbers are computed the same way whatever the split, so the
result is the same to the bit.  A memory-mapped array's pages are released after each chunk
(:class:`_PageReleaser`), so the process's resident memory stays near 100 MB for a week at 100 Hz.
Detection of that week (60.5 M float32 samples) takes ~0.35 s of CPU (``bench/autocal.py``).
"""

from __future__ import annotations

import math
import mmap
import threading
from dataclasses import dataclass, field

import numpy as np

from ..shared.cores import usable_cores
from ..shared.errors import CalibrationError
from ..shared.validation import check_gravity

SEGMENT_S = 5.0
"""Segment length (Farago et al. section II.B.1)."""

THRESHOLD_G = 0.12
"""Largest max − min of the tested axis in a rest segment, in g (Farago et al. section II.B.1)."""

IDLE_MIN_RUN_S = 1.0
"""Identical consecutive samples lasting this long mark a segment as idle sleep, not rest."""

GGIR_WINDOW_S = 10.0
GGIR_SD_G = 0.013
"""GGIR's no-movement windows: 10 s, standard deviation below 0.013 g on each axis (van Hees 2014)."""

CHUNK_SEGMENTS = 256
"""Segments processed at a time by :func:`detect_rest_segments`: 1.5 MB of float32 at 100 Hz, so that a chunk and
its temporaries stay in a core's cache between the range test and the sums."""

MAX_THREADS = 4
"""Most threads :func:`detect_rest_segments` uses by default: the pass is bound by memory beyond a few cores."""

MIN_CHUNKS_PER_THREAD = 4
"""A recording is split among threads only when each gets at least this many chunks."""


@dataclass(frozen=True)
class RestSegments:
    """The rest segments of one recording and what the detector saw.

    Attributes
    ----------
    start : numpy.ndarray of int64, shape (M,)
        First sample of each rest segment.
    mean : numpy.ndarray, shape (M, 3)
        Mean of each rest segment (the candidate calibration point), in the recording's unit.
    range : numpy.ndarray, shape (M,)
        Largest max − min over the tested axes, in the recording's unit.
    segment_samples : int
        Samples per segment.
    sampling_rate_hz, gravity, threshold : float
        ``threshold`` in the recording's unit (``threshold_g · gravity``).
    axes : tuple of int
        The tested axes.
    n_samples, n_segments, n_moving, n_nan, n_idle : int
        Samples seen, complete segments, and segments refused for motion, NaN or idle sleep.
    ggir_mean, ggir_std : numpy.ndarray, shape (W, 3)
        GGIR no-movement windows (module docstring).
    """

    start: np.ndarray
    mean: np.ndarray
    range: np.ndarray
    segment_samples: int
    sampling_rate_hz: float
    gravity: float
    threshold: float
    axes: tuple
    n_samples: int
    n_segments: int
    n_moving: int
    n_nan: int
    n_idle: int
    ggir_mean: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    ggir_std: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    @property
    def n_rest(self) -> int:
        return int(len(self.start))

    def summary(self) -> dict:
        """Counts and settings as plain JSON."""
        return {
            "n_samples": self.n_samples,
            "n_segments": self.n_segments,
            "n_rest": self.n_rest,
            "n_moving": self.n_moving,
            "n_nan": self.n_nan,
            "n_idle": self.n_idle,
            "n_ggir_windows": int(len(self.ggir_mean)),
            "segment_s": self.segment_samples / self.sampling_rate_hz,
            "segment_samples": self.segment_samples,
            "threshold": self.threshold,
            "axes": ["xyz"[a] for a in self.axes],
        }


@dataclass
class _Scanned:
    """What the detector keeps of a run of whole segments: counts, and the rest segments' numbers."""

    n: int
    n_nan: int
    n_moving: int
    n_idle: int = 0
    start: np.ndarray | None = None
    mean: np.ndarray | None = None
    range: np.ndarray | None = None
    sq: np.ndarray | None = None


class RestAccumulator:
    """Streaming detector of Farago et al. rest segments: feed chunks of samples, then take :meth:`result`.

    Parameters
    ----------
    sampling_rate_hz : float
    gravity : float
        Reference magnitude in the samples' unit (1 for g, 9.80665 for m/s²); thresholds in g
        are multiplied by it.
    segment_s : float
        Segment length, 5 s (Farago et al. section II.B.1).
    threshold_g : float
        Largest max − min of a tested axis, 0.12 g (Farago et al. section II.B.1).
    axis : int
        The axis tested when ``all_axes`` is False (0 = x; Farago et al.: one axis is enough for a worn device).
    all_axes : bool
        Test every axis.
    idle_min_run_s : float or None
        Identical consecutive samples this long make a segment idle sleep; None to skip the test.
    ggir_window_s, ggir_sd_g : float
        GGIR no-movement windows for the comparison; ``ggir_window_s=None`` to skip them.

    Examples
    --------
    >>> acc = RestAccumulator(100.0)
    >>> for chunk in chunks:          # doctest: +SKIP
    ...     acc.feed(chunk)
    >>> rest = acc.result()           # doctest: +SKIP
    """

    def __init__(
        self,
        sampling_rate_hz: float,
        *,
        gravity: float = 1.0,
        segment_s: float = SEGMENT_S,
        threshold_g: float = THRESHOLD_G,
        axis: int = 0,
        all_axes: bool = False,
        idle_min_run_s: float | None = IDLE_MIN_RUN_S,
        ggir_window_s: float | None = GGIR_WINDOW_S,
        ggir_sd_g: float = GGIR_SD_G,
    ):
        try:
            rate = float(sampling_rate_hz)
        except (TypeError, ValueError):
            raise CalibrationError(f"sampling_rate_hz must be a number; got {sampling_rate_hz!r}") from None
        if not (math.isfinite(rate) and rate > 0):
            raise CalibrationError(f"sampling_rate_hz must be a positive number; got {sampling_rate_hz!r}")
        self.gravity = check_gravity(gravity)
        if not (math.isfinite(segment_s) and segment_s > 0):
            raise CalibrationError(f"segment_s must be positive; got {segment_s!r}")
        seg = int(round(segment_s * rate))
        if seg < 2:
            raise CalibrationError(
                f"a {segment_s} s segment at {rate} Hz holds {seg} sample(s): give the right sampling rate "
                "or a longer segment_s"
            )
        if not (math.isfinite(threshold_g) and threshold_g > 0):
            raise CalibrationError(f"threshold_g must be positive; got {threshold_g!r}")
        if axis not in (0, 1, 2):
            raise CalibrationError(f"axis must be 0, 1 or 2 (x, y, z); got {axis!r}")
        self.sampling_rate_hz = rate
        self.seg = seg
        self.threshold = float(threshold_g) * self.gravity
        self.axes = (0, 1, 2) if all_axes else (int(axis),)
        self.idle_run = None if idle_min_run_s is None else max(2, int(round(idle_min_run_s * rate)))
        self.ggir_group = None
        if ggir_window_s:
            self.ggir_group = max(1, int(round(ggir_window_s / (seg / rate))))
        self.ggir_sd = ggir_sd_g * self.gravity
        self._ones: np.ndarray | None = None
        self._carry = np.zeros((0, 3), dtype=np.float32)
        self._n_samples = 0
        self._n_segments = 0
        self._n_moving = self._n_nan = self._n_idle = 0
        self._start: list = []
        self._mean: list = []
        self._range: list = []
        self._sq: list = []

    # -- feeding --------------------------------------------------------------------------------
    def feed(self, chunk) -> None:
        """Process the next samples, shape (n, 3), in order; any float dtype (float32 stays float32)."""
        x = np.asarray(chunk)
        if x.ndim != 2 or x.shape[1] != 3:
            raise CalibrationError(f"samples must have shape N×3; got shape {tuple(x.shape)}")
        x = _as_float(x)
        if len(x) == 0:
            return
        self._n_samples += len(x)
        seg = self.seg
        if len(self._carry):
            need = seg - len(self._carry)
            if len(x) < need:
                self._carry = np.concatenate([self._carry, x.astype(self._carry.dtype, copy=False)])
                return
            first = np.concatenate([self._carry.astype(x.dtype, copy=False), x[:need]])
            self._carry = np.zeros((0, 3), dtype=x.dtype)
            self._process(first)
            x = x[need:]
        m = (len(x) // seg) * seg
        if m:
            self._process(x[:m])
        self._carry = np.array(x[m:])

    def _process(self, x: np.ndarray) -> None:
        """Whole segments only: x has a multiple of ``seg`` rows."""
        self._add(self._scan(x, self._n_segments))

    def _scan(self, x: np.ndarray, base: int) -> _Scanned:
        """The statistics of whole segments (x has a multiple of ``seg`` rows), the first being segment ``base``.

        Reads the accumulator's settings only, so two threads may scan two parts of a recording at once.
        """
        seg = self.seg
        n = len(x) // seg
        c = x.reshape(n, seg, 3)
        # Farago et al. section II.B.1: max − min of the tested axis (or axes) over the segment.  The axis
        # is copied out first: numpy's max and min along a contiguous row are several times faster than
        # along a strided one, and the copy of a block stays in the cache for the sums below.
        rng: np.ndarray | None = None
        for a in self.axes:
            ax = np.ascontiguousarray(c[:, :, a])
            r = ax.max(axis=1) - ax.min(axis=1)
            rng = r if rng is None else np.maximum(rng, r)
        assert rng is not None, "at least one axis is tested"
        # NaN propagates through max/min: such a segment fails the comparison.
        still = rng < self.threshold
        ones = self._ones_for(x.dtype)
        idx = np.flatnonzero(still)
        nan_range = np.isnan(rng)
        n_nan = int(nan_range.sum())
        out = _Scanned(n, n_nan, int(n - still.sum() - nan_range.sum()))
        if len(idx) == 0:
            return out
        # The mean of each still segment (accumulated sums, Farago et al. section II.B.1): the still segments are
        # gathered first (a copy within the cache), then one matrix–vector product each.
        cs = c[idx]
        sums = np.matmul(ones, cs).astype(np.float64)
        means = sums / seg
        keep = np.isfinite(means).all(axis=1)  # a NaN on an untested axis
        out.n_nan += int((~keep).sum())
        if self.idle_run is not None:
            idle = self._idle(c, idx) & keep
            out.n_idle = int(idle.sum())
            keep &= ~idle
        if not keep.all():
            idx, means = idx[keep], means[keep]
        if len(idx) == 0:
            return out
        out.start = (base + idx).astype(np.int64) * seg
        out.mean = means
        out.range = rng[idx].astype(np.float64)
        if self.ggir_group is not None:
            # Sums of squares for GGIR's standard deviations (float32 sums of ~1 g² terms: the
            # variance is good to ~1e-6 g², against GGIR's threshold of 1.7e-4 g²).
            if not keep.all():
                cs = cs[keep]
            out.sq = np.matmul(ones, cs * cs).astype(np.float64)
        return out

    def _ones_for(self, dtype) -> np.ndarray:
        ones = self._ones
        if ones is None or ones.dtype != dtype:
            ones = self._ones = np.ones(self.seg, dtype=dtype)
        return ones

    def _add(self, s: _Scanned) -> None:
        """Count a scanned part, the parts taken in the recording's order."""
        self._n_segments += s.n
        self._n_nan += s.n_nan
        self._n_moving += s.n_moving
        self._n_idle += s.n_idle
        if s.start is None:
            return
        self._start.append(s.start)
        self._mean.append(s.mean)
        self._range.append(s.range)
        if s.sq is not None:
            self._sq.append(s.sq)

    def _idle(self, c: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """Which segments ``c[idx]`` hold ``idle_run`` or more identical consecutive samples (all axes)."""
        run = min(self.idle_run, c.shape[1])
        a = self.axes[0]
        ca = c[:, :, a]
        # Cheap necessary condition first: a run of `run` identical samples holds run − 1 consecutive
        # equal neighbour pairs (j, j + 1), so one of the pairs at j = 0, run − 1, 2(run − 1), … is equal.
        cols = np.arange(0, c.shape[1] - 1, max(1, run - 1))
        rows = idx[:, None]
        cand = np.flatnonzero((ca[rows, cols] == ca[rows, cols + 1]).any(axis=1))
        out = np.zeros(len(idx), dtype=bool)
        if len(cand) == 0:
            return out
        sub = c[idx[cand]]
        e = (sub[:, 1:, :] == sub[:, :-1, :]).all(axis=2)
        # Longest run of True per row: cumulative count minus its value at the last False.
        cnt = np.cumsum(e, axis=1)
        reset = np.maximum.accumulate(np.where(~e, cnt, 0), axis=1)
        longest = (cnt - reset).max(axis=1)
        out[cand] = longest >= run - 1
        return out

    # -- result ---------------------------------------------------------------------------------
    def result(self) -> RestSegments:
        """The rest segments found so far (the incomplete last segment is ignored)."""
        start = np.concatenate(self._start) if self._start else np.zeros(0, dtype=np.int64)
        mean = np.vstack(self._mean) if self._mean else np.zeros((0, 3))
        rng = np.concatenate(self._range) if self._range else np.zeros(0)
        gm, gs = np.zeros((0, 3)), np.zeros((0, 3))
        if self.ggir_group is not None and len(start):
            gm, gs = self._ggir_windows(start, mean, np.vstack(self._sq))
        return RestSegments(
            start=start,
            mean=mean,
            range=rng,
            segment_samples=self.seg,
            sampling_rate_hz=self.sampling_rate_hz,
            gravity=self.gravity,
            threshold=self.threshold,
            axes=self.axes,
            n_samples=self._n_samples,
            n_segments=self._n_segments,
            n_moving=self._n_moving,
            n_nan=self._n_nan,
            n_idle=self._n_idle,
            ggir_mean=gm,
            ggir_std=gs,
        )

    def _ggir_windows(self, start, mean, sq):
        """GGIR windows: ``ggir_group`` consecutive rest segments on the grid, pooled mean and sd."""
        k = self.ggir_group
        seg_index = start // self.seg
        win = seg_index // k
        # Windows whose k segments are all rest: runs of k equal window numbers.
        _uniq, first, counts = np.unique(win, return_index=True, return_counts=True)
        full = first[counts == k]
        if len(full) == 0:
            return np.zeros((0, 3)), np.zeros((0, 3))
        rows = full[:, None] + np.arange(k)[None, :]
        n = k * self.seg
        wm = mean[rows].mean(axis=1)  # (W, 3)
        var = (sq[rows].sum(axis=1) / n - wm * wm) * (n / (n - 1))
        wsd = np.sqrt(np.maximum(var, 0.0))
        ok = (wsd < self.ggir_sd).all(axis=1)
        return wm[ok], wsd[ok]


class _PageReleaser:
    """Drop the pages of a memory-mapped array from the process once a chunk is done.

    The pages stay in the page cache (the file is not re-read), but no longer count in the
    process's resident memory, so a recording of any length costs a chunk of memory, not its size.
    """

    def __init__(self, x):
        self.mm = None
        b = x
        for _ in range(8):
            m = getattr(b, "_mmap", None)
            if isinstance(m, mmap.mmap):
                self.mm = m
                break
            if isinstance(b, mmap.mmap):
                self.mm = b
                break
            b = getattr(b, "base", None)
            if b is None:
                break
        if self.mm is not None:
            try:
                self.base = np.frombuffer(self.mm, dtype=np.uint8).ctypes.data
            except (TypeError, ValueError, BufferError):
                self.mm = None

    def release(self, chunk) -> None:
        if self.mm is None or chunk.size == 0:
            return
        try:
            low, high = np.lib.array_utils.byte_bounds(chunk)
            start = low - self.base
            start -= start % mmap.PAGESIZE
            self.mm.madvise(mmap.MADV_DONTNEED, start, high - self.base - start)
        except (AttributeError, OSError, ValueError):
            self.mm = None


def _as_float(x: np.ndarray) -> np.ndarray:
    """Samples as the detector takes them: float32 and float64 as they are, any other type as float64."""
    return x if x.dtype in (np.float32, np.float64) else x.astype(np.float64)


def detection_threads(workers: int | None = None) -> int:
    """Threads of :func:`detect_rest_segments`: ``workers`` when given, else the cores this process may use
    (at most :data:`MAX_THREADS`)."""
    if workers is not None:
        return max(1, int(workers))
    return usable_cores(MAX_THREADS)


def detect_rest_segments(
    samples,
    sampling_rate_hz: float,
    *,
    gravity: float = 1.0,
    chunk_segments: int = CHUNK_SEGMENTS,
    progress=None,
    workers: int | None = None,
    **options,
) -> RestSegments:
    """Rest segments of a whole recording, processed in chunks (Farago et al. section II.B.1).

    Parameters
    ----------
    samples : array_like, shape (N, 3)
        Accelerometer samples; a ``numpy.memmap`` is read a chunk at a time, so memory stays bounded.
    sampling_rate_hz : float
    gravity : float
        Reference magnitude in the samples' unit.
    chunk_segments : int
        Segments per chunk.
    progress : callable, optional
        Called as ``progress(done_samples, total_samples)`` after each chunk (from the scanning threads,
        one at a time).
    workers : int, optional
        Threads that scan parts of the recording at once (numpy releases the GIL in its loops); by
        default :func:`detection_threads`.  A recording shorter than a few chunks per thread is scanned by
        one.  The result does not depend on it.
    **options
        Passed to :class:`RestAccumulator` (``segment_s``, ``threshold_g``, ``axis``, ``all_axes``,
        ``idle_min_run_s``, ``ggir_window_s``, ``ggir_sd_g``).

    Returns
    -------
    RestSegments
    """
    x = samples if hasattr(samples, "shape") else np.asarray(samples, dtype=float)
    if len(x.shape) != 2 or x.shape[1] != 3:
        raise CalibrationError(f"samples must have shape N×3; got shape {tuple(x.shape)}")
    acc = RestAccumulator(sampling_rate_hz, gravity=gravity, **options)
    n = x.shape[0]
    step = max(1, int(chunk_segments)) * acc.seg
    pages = _PageReleaser(x)
    n_chunks = -(-n // step)
    threads = min(detection_threads(workers), n_chunks // MIN_CHUNKS_PER_THREAD)
    if threads <= 1:
        for s in range(0, n, step):
            chunk = x[s : s + step]
            acc.feed(chunk)
            pages.release(chunk)
            if progress is not None:
                progress(min(n, s + step), n)
        return acc.result()
    # Whole chunks to each thread, in the recording's order; the incomplete last segment is the tail's.
    whole = (n // acc.seg) * acc.seg
    cuts = [min(whole, (n_chunks * k // threads) * step) for k in range(threads + 1)]
    done = [0]
    lock = threading.Lock()

    def scan(lo: int, hi: int) -> list[_Scanned]:
        parts = []
        for s in range(lo, hi, step):
            chunk = x[s : min(s + step, hi)]
            c = _as_float(np.asarray(chunk))
            parts.append(acc._scan(c, s // acc.seg))
            pages.release(chunk)
            if progress is not None:
                with lock:
                    done[0] += len(c)
                    progress(done[0], n)
        return parts

    from concurrent.futures import ThreadPoolExecutor

    acc._ones_for(_as_float(x[:0]).dtype)  # made once, before the threads share it
    with ThreadPoolExecutor(threads) as pool:
        scanned = list(pool.map(scan, cuts[:-1], cuts[1:]))
    for parts in scanned:
        for part in parts:
            acc._add(part)
    acc._n_samples = whole
    tail = x[whole:]
    acc.feed(tail)  # shorter than a segment: counted, then ignored as the streaming detector does
    if progress is not None and len(tail):
        progress(n, n)
    return acc.result()
