"""Static-interval detection in a raw triaxial accelerometer stream.

A sample belongs to a rest when a moving window around it is still: the spread of the window (the
root of the summed per-axis variances) stays under a threshold taken from the stream's own noise
floor.  Runs of still windows are trimmed at their transition edges, halves of a rest split by a
short knock are merged (the knock's samples are left out), and a run is kept only when it lasts
long enough, its mean norm is plausible for gravity, and its direction does not drift (a slow turn
through a pose is not a rest).  Each rest is labelled with the axis that points up
(:func:`~app.calibration.shared.orientations.nearest_orientation`, the 20° rule of docs/rest.md).

Everything is O(N): the moving windows use cumulative sums and the edge trimming is vectorised over
all runs; 10⁷ samples with ~10⁴ rests take ~4.5 s on a shared 2-core machine (bench/static_segments.py).
The unit may be m/s², g or raw counts; thresholds are fractions of a reference magnitude, which is
``gravity`` when given, else the median norm of the still windows.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from ..shared.errors import CalibrationError, InsufficientDataError
from ..shared.orientations import LABEL_MAX_ANGLE_DEG, nearest_orientation
from ..shared.validation import as_vectors, check_gravity

WINDOW_S = 0.5
"""Moving-window length: long enough to average noise (50–100 samples), short enough to see a turn."""

MIN_DURATION_S = 1.5
"""Shortest rest kept, counting only the samples used (knocks excluded)."""

NOISE_PERCENTILE = 10.0
"""The noise floor is this percentile of the windowed spread (a calibration log is mostly rests)."""

NOISE_FACTOR = 4.0
"""Still windows have a spread up to this multiple of the noise floor."""

FLOOR_G = 0.01
"""Absolute floor of the threshold, in g (≈ 0.1 m/s²: one browser quantisation step, whose
rounding can make the spread of a rest exactly 0)."""

CAP_G = 0.05
"""Absolute cap of the threshold, in g (0.5 m/s²): above it a window is never still, whatever the
noise floor says (a stream that is all motion)."""

MAX_GAP_S = 1.0
"""Two still runs separated by at most this gap and agreeing in mean are one rest (a knock)."""

MAX_DRIFT_DEG_PER_S = 0.2
"""Largest rate of change of a rest's direction (plus four standard deviations of its noise): a
temperature drift of 0.3 m/s² per minute is 0.03 °/s, a turn slow enough to look still is
0.3–4 °/s."""

NORM_RANGE_G = (0.5, 1.5)
"""A rest's mean norm must lie in this range of the reference magnitude (else free fall, a
vehicle, or a wrong unit)."""

EDGE_SMOOTH_S = 0.1
"""Smoothing of the samples when trimming transition edges."""


@dataclass(frozen=True)
class StaticSegment:
    """One rest found in a stream.

    Attributes
    ----------
    start, end : int
        Sample indices, ``end`` exclusive.
    mean, std : numpy.ndarray
        Shape (3,), mean and standard deviation per axis of the samples used, in the stream's unit.
    count : int
        Samples used: ``end − start`` minus the samples of the gaps.
    up : str or None
        The axis that points up (``+x`` … ``-z``), or None when the direction is more than 20°
        from every axis.
    gaps : tuple of (int, int)
        Sample ranges inside the segment left out of the statistics (knocks), ``end`` exclusive.
    drift_deg_per_s : float
        Rate of change of the direction between the first and last thirds of the segment.
    """

    start: int
    end: int
    mean: np.ndarray
    std: np.ndarray
    count: int
    up: str | None
    gaps: tuple = ()
    drift_deg_per_s: float = 0.0

    def duration_s(self, sampling_rate_hz: float) -> float:
        """Length of the segment in seconds, ``(end − start) / sampling_rate_hz``."""
        return (self.end - self.start) / float(sampling_rate_hz)

    def to_dict(self) -> dict:
        """Plain-JSON form of docs/rest.md: ``start``, ``end``, ``acc_mean``, ``acc_std``, ``up``."""
        return {
            "start": int(self.start),
            "end": int(self.end),
            "acc_mean": [float(v) for v in self.mean],
            "acc_std": [float(v) for v in self.std],
            "up": self.up,
        }


def _positive(value, name: str, *, allow_zero: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise CalibrationError(f"{name} must be a number; got {value!r}") from None
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise CalibrationError(
            f"{name} must be a {'non-negative' if allow_zero else 'positive'} finite number; got {value!r}"
        )
    return v


def window_stats(samples: np.ndarray, window: int) -> tuple[np.ndarray, np.ndarray]:
    """Spread and mean norm of every window of ``window`` consecutive samples, in O(N).

    Parameters
    ----------
    samples : numpy.ndarray
        Shape (N, 3), finite.
    window : int
        Window length in samples, 2 ≤ window ≤ N.

    Returns
    -------
    spread : numpy.ndarray
        Shape (N − window + 1,): ``sqrt(var_x + var_y + var_z)`` of window i = samples[i:i+window].
    norm : numpy.ndarray
        Same shape: the norm of the window's mean.
    """
    n = len(samples)
    m = n - window + 1
    var_sum = np.zeros(m)
    norm2 = np.zeros(m)
    # Centre each axis first so that the cumulative sums of squares do not lose the variance.
    centre = np.median(samples[:: max(1, n // 100_000)], axis=0)
    c = np.empty(n + 1)
    c[0] = 0.0
    for k in range(3):
        col = samples[:, k] - centre[k]
        np.cumsum(col, out=c[1:])
        mean = c[window:] - c[:-window]
        mean /= window
        np.square(col, out=col)
        np.cumsum(col, out=c[1:])
        sq = c[window:] - c[:-window]
        sq /= window
        sq -= mean * mean
        np.maximum(sq, 0.0, out=sq)
        var_sum += sq
        mean += centre[k]
        norm2 += mean * mean
    return np.sqrt(var_sum), np.sqrt(norm2)


def _ranges(starts: np.ndarray, lengths: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Concatenated sample indices of the ranges [starts, starts + lengths), their range number
    and the offset of each range in the concatenation."""
    reg = np.repeat(np.arange(len(starts)), lengths)
    offsets = np.concatenate(([0], np.cumsum(lengths)[:-1])).astype(np.int64)
    idx = np.arange(int(lengths.sum())) - offsets[reg] + starts[reg]
    return idx, reg, offsets


def _edge_rms(xc, idx, reg, offsets, lengths, ref, half) -> np.ndarray:
    """RMS distance of the samples ``idx`` from their range's reference, over a centred window of
    half-width ``half`` that shrinks at the ends of each range."""
    d2 = ((xc[idx] - ref[reg]) ** 2).sum(axis=1)
    cs = np.concatenate(([0.0], np.cumsum(d2)))
    i = np.arange(len(d2))
    lo = np.maximum(i - half, offsets[reg])
    hi = np.minimum(i + half + 1, (offsets + lengths)[reg])
    return np.sqrt((cs[hi] - cs[lo]) / (hi - lo))


def _means(csum: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The mean of the samples [lo, hi) of each run, from their cumulative sum; NaN where the range is empty
    (a run of two samples has no inside to compare its edges with, and NaN is never above a tolerance)."""
    width = (hi - lo)[:, None]
    out = np.full((len(lo), csum.shape[1]), np.nan)
    return np.divide(csum[hi] - csum[lo], width, out=out, where=width > 0)


def _trim(xc, csum, a, b, max_trim: int, half: int, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Cut the transition edges of the still runs [a, b), all runs at once.

    Within ``k = min(max_trim, length // 3)`` samples of each end, the RMS distance of the samples
    (over a short centred window) from the mean of the run just inside that edge is compared with
    ``tol``; the edge moves inwards past the innermost sample where it is larger.  The RMS catches
    both the slow tail of a turn and the ringing tail of a knock.
    """
    n = b - a
    k = np.maximum(np.minimum(max_trim, n // 3), 1)
    long = n >= 2 * k + max_trim
    rs_a, rs_b = a + k, np.where(long, a + k + max_trim, b - k)
    re_a, re_b = np.where(long, b - k - max_trim, a + k), b - k
    ref_s, ref_e = _means(csum, rs_a, rs_b), _means(csum, re_a, re_b)
    length = np.minimum(k + half, n)

    idx, reg, off = _ranges(a, length)
    rms = _edge_rms(xc, idx, reg, off, length, ref_s, half)
    pos = idx - a[reg]
    cut = np.where((rms > tol) & (pos < k[reg]), pos + 1, 0)
    new_a = a + np.maximum.reduceat(cut, off)

    idx, reg, off = _ranges(b - length, length)
    rms = _edge_rms(xc, idx, reg, off, length, ref_e, half)
    pos = b[reg] - 1 - idx  # distance from the end
    cut = np.where((rms > tol) & (pos < k[reg]), pos + 1, 0)
    new_b = b - np.maximum.reduceat(cut, off)
    return new_a, new_b


def still_threshold(
    spread: np.ndarray,
    norm: np.ndarray,
    *,
    gravity: float | None = None,
    noise_percentile: float = NOISE_PERCENTILE,
    noise_factor: float = NOISE_FACTOR,
    floor_g: float = FLOOR_G,
    cap_g: float = CAP_G,
) -> tuple[float, float]:
    """Reference magnitude and stillness threshold from the windowed statistics.

    The threshold is ``noise_factor`` times the ``noise_percentile`` percentile of the spread,
    clipped to ``[floor_g, cap_g]`` times the reference magnitude.  Without ``gravity`` the
    reference is the median norm of the quietest quarter of the windows, then refined to the
    median norm of the still windows.

    Returns
    -------
    (reference, threshold) : tuple of float
        In the unit of the stream.
    """
    noise = float(np.percentile(spread, noise_percentile))
    if gravity is not None:
        g_ref = float(gravity)
    else:
        quiet = spread <= np.percentile(spread, 25.0)
        g_ref = float(np.median(norm[quiet]))
        if not g_ref > 0:
            raise CalibrationError(
                "the still parts of the stream read zero: it holds no gravity; check that the "
                "columns are the accelerometer's and that the unit is right"
            )
    thr = min(max(noise_factor * noise, floor_g * g_ref), cap_g * g_ref)
    if gravity is None:
        still = spread <= thr
        if still.any():
            g_ref = float(np.median(norm[still]))
            thr = min(max(noise_factor * noise, floor_g * g_ref), cap_g * g_ref)
    return g_ref, thr


def quantisation_step(samples) -> float:
    """The smallest non-zero change between consecutive samples (of the first 100 000): the step of a
    sensor quantised coarser than its noise, whose half-second blocks can all read one value (their
    spread, and the percentile of the spreads, then 0); for continuous readings a tiny number.

    Parameters
    ----------
    samples : array_like, shape (N, k)
    """
    head = np.asarray(samples[:100_000], dtype=float)
    steps = np.abs(np.diff(head, axis=0))
    steps = steps[np.isfinite(steps) & (steps > 0)]
    return float(steps.min()) if steps.size else 0.0


def others_still(
    others, w: int, noise_percentile: float = NOISE_PERCENTILE, noise_factor: float = NOISE_FACTOR
) -> np.ndarray | None:
    """Which windows of ``w`` samples are still on every other sensor (a gyroscope, a magnetometer on
    the accelerometer's clock), or None without one.

    A window is still on a sensor when its spread (:func:`window_stats`) stays under ``noise_factor``
    times the ``noise_percentile`` percentile of that sensor's own spreads — the accelerometer's rule,
    on the sensor's own noise floor and in its own unit —, that floor being at least half a
    quantisation step (a sensor quantised coarser than its noise:
    :func:`quantisation_step`), as in the noise method's still part.
    """
    still = None
    for samples in others:
        o = as_vectors(samples, "samples of another sensor")
        spread, _ = window_stats(o, w)
        thr = noise_factor * max(float(np.percentile(spread, noise_percentile)), 0.5 * quantisation_step(o))
        still = spread <= thr if still is None else still & (spread <= thr)
    # A window still only where those a quarter window either side are too: a move's first samples in
    # the last quarter of a window barely raise its spread (the accelerometer's edges are trimmed on its
    # own samples instead, :func:`_trim`).
    if still is None:
        return None
    k = max(1, w // 4)
    moving = np.concatenate(([0], np.cumsum(np.concatenate((np.zeros(k), ~still, np.zeros(k))))))
    return (moving[2 * k + 1 :] - moving[: len(still)]) == 0


def _still_runs(x: np.ndarray, w: int, others=(), **threshold) -> tuple[float, float, np.ndarray, np.ndarray]:
    """Steps 1–2 of :func:`detect_static_segments`: the reference magnitude, the threshold and the
    runs of still windows as sample ranges [a, b) (a run of windows [i, j) covers [i, j − 1 + w)),
    a window being still when it is still on the accelerometer and on every sensor of ``others``."""
    spread, norm = window_stats(x, w)
    g_ref, thr = still_threshold(spread, norm, **threshold)
    still = spread <= thr
    del spread, norm
    elsewhere = others_still(
        others, w, threshold.get("noise_percentile", NOISE_PERCENTILE), threshold.get("noise_factor", NOISE_FACTOR)
    )
    if elsewhere is not None:
        still &= elsewhere
    edges = np.diff(np.concatenate(([0], still.view(np.int8), [0])))
    del still
    run_a = np.flatnonzero(edges == 1)
    run_b = np.flatnonzero(edges == -1) - 1 + w
    return g_ref, thr, run_a, run_b


@dataclass(frozen=True)
class _Runs:
    """Still runs [a, b) after trimming, with the centred cumulative sums of the stream.

    The sums are centred on the stream's median so that the sums of any range, taken in O(1),
    do not lose the noise to cancellation.
    """

    x: np.ndarray
    centre: np.ndarray
    csum: np.ndarray
    a: np.ndarray
    b: np.ndarray
    sums: np.ndarray
    counts: np.ndarray

    @classmethod
    def trimmed(cls, x, run_a, run_b, *, w: int, half: int, thr: float, min_length: int) -> _Runs:
        """Step 3: the runs with their transition edges cut (:func:`_trim`), too short ones dropped."""
        n = len(x)
        centre = np.median(x[:: max(1, n // 100_000)], axis=0)
        xc = x - centre
        csum = np.zeros((n + 1, 3))
        np.cumsum(xc, axis=0, out=csum[1:])
        run_a, run_b = _trim(xc, csum, run_a, run_b, w, half, thr)
        keep = (run_b - run_a) >= min_length
        run_a, run_b = run_a[keep], run_b[keep]
        return cls(
            x=x, centre=centre, csum=csum, a=run_a, b=run_b, sums=csum[run_b] - csum[run_a], counts=run_b - run_a
        )

    def merged(self, max_gap: int, thr: float) -> list[list[int]]:
        """Step 4: groups of runs split by a knock (short gap, same mean: a bump is not an orientation)."""
        means = self.sums / self.counts[:, None]
        groups: list[list[int]] = []
        g_sum, g_cnt = np.zeros(3), np.zeros(())  # the last group's, from its first run on
        for i in range(len(self.a)):
            if (
                groups
                and self.a[i] - self.b[groups[-1][-1]] <= max_gap
                and np.linalg.norm(means[i] - g_sum / g_cnt) <= 2 * thr
            ):
                groups[-1].append(i)
                g_sum = g_sum + self.sums[i]
                g_cnt += self.counts[i]
                continue
            groups.append([i])
            g_sum, g_cnt = self.sums[i], self.counts[i]
        return groups

    def _thirds(self, grp: list[int], count: int, fs: float):
        """Means of the first and last thirds of a group, their time apart and its samples."""
        csum, centre = self.csum, self.centre
        k = max(1, count // 3)
        if len(grp) == 1:
            a, b = int(self.a[grp[0]]), int(self.b[grp[0]])
            m1 = (csum[a + k] - csum[a]) / k + centre
            m3 = (csum[b] - csum[b - k]) / k + centre
            return m1, m3, (count - k) / fs, self.x[a:b], k
        t = np.concatenate([np.arange(self.a[i], self.b[i]) for i in grp])
        xs = self.x[t]
        m1, m3 = xs[:k].mean(axis=0), xs[-k:].mean(axis=0)
        return m1, m3, (t[-k:].mean() - t[:k].mean()) / fs, xs, k

    def segment(
        self,
        grp: list[int],
        fs: float,
        *,
        min_samples: int,
        norm_range: tuple[float, float],
        max_drift_deg_per_s: float,
        label_max_angle_deg: float,
    ) -> StaticSegment | None:
        """Step 5: the rest of a group, or None when it is too short, its norm implausible, or its
        direction drifts (a slow turn, not a rest)."""
        count = int(self.counts[grp].sum())
        if count < min_samples:
            return None
        mean = self.sums[grp].sum(axis=0) / count + self.centre
        if not norm_range[0] <= float(np.linalg.norm(mean)) <= norm_range[1]:
            return None
        m1, m3, dt, xs, k = self._thirds(grp, count, fs)
        cosang = float(m1 @ m3 / (np.linalg.norm(m1) * np.linalg.norm(m3)))
        rate = math.degrees(math.acos(min(1.0, max(-1.0, cosang)))) / dt if dt > 0 else 0.0
        std = xs.std(axis=0)
        # The angle between two means of k noisy samples has a spread of about σ √(2 / k) / |g|.
        noise_rate = (
            math.degrees(float(np.sqrt(np.mean(std**2))) * math.sqrt(2.0 / k) / float(np.linalg.norm(mean))) / dt
            if dt > 0
            else 0.0
        )
        if rate > max_drift_deg_per_s + 4.0 * noise_rate:
            return None
        return StaticSegment(
            start=int(self.a[grp[0]]),
            end=int(self.b[grp[-1]]),
            mean=mean,
            std=std,
            count=count,
            up=nearest_orientation(mean, label_max_angle_deg),
            gaps=tuple((int(self.b[i]), int(self.a[j])) for i, j in itertools.pairwise(grp)),
            drift_deg_per_s=float(rate),
        )


def detect_static_segments(
    samples,
    sampling_rate_hz: float,
    *,
    gravity: float | None = None,
    window_s: float = WINDOW_S,
    min_duration_s: float = MIN_DURATION_S,
    noise_percentile: float = NOISE_PERCENTILE,
    noise_factor: float = NOISE_FACTOR,
    floor_g: float = FLOOR_G,
    cap_g: float = CAP_G,
    max_gap_s: float = MAX_GAP_S,
    max_drift_deg_per_s: float = MAX_DRIFT_DEG_PER_S,
    norm_range_g: tuple[float, float] = NORM_RANGE_G,
    label_max_angle_deg: float = LABEL_MAX_ANGLE_DEG,
    others=(),
) -> list[StaticSegment]:
    """Find the intervals where the device rests, and the axis that points up in each.

    1. Spread (root of the summed per-axis variances) of every window of ``window_s``, by
       cumulative sums.
    2. Threshold: ``noise_factor`` × the ``noise_percentile`` percentile of the spread, clipped to
       [``floor_g``, ``cap_g``] × g, g being ``gravity`` or the median norm of the still windows.
       A window is still when its spread is under it and it is still on every sensor of ``others``
       too (:func:`others_still`: a gyroscope ringing after a touch, a compass turning about gravity).
    3. Runs of still windows become sample ranges; their edges are trimmed where the smoothed
       samples leave the run's mean by more than the threshold (the tail of a turn).
    4. Runs separated by at most ``max_gap_s`` whose means agree within twice the threshold are
       merged, the gap (a knock) being left out of the statistics.
    5. A run is kept when its samples cover ``min_duration_s``, its mean norm lies within
       ``norm_range_g`` × g, and its direction changes by at most ``max_drift_deg_per_s``
       between its first and last thirds (a slow turn through a pose is not a rest).

    Parameters
    ----------
    samples : array_like, shape (N, 3)
        Raw accelerometer readings, in m/s², g or raw counts.
    sampling_rate_hz : float
        Positive.
    gravity : float, optional
        Reference magnitude in the unit of ``samples`` (9.80665 for m/s², 1 for g).  None: the
        median norm of the still windows, so that any unit works.
    window_s : float
        Length of the moving window, seconds.
    min_duration_s : float
        Shortest rest kept, seconds of samples used.
    noise_percentile, noise_factor : float
        Noise floor percentile of the windowed spread, and the factor that makes it a threshold.
    floor_g, cap_g : float
        Bounds of the threshold as fractions of the reference magnitude.
    max_gap_s : float
        Longest knock inside one rest, seconds.
    max_drift_deg_per_s : float
        Largest rate of change of a rest's direction, degrees per second, beyond four standard
        deviations of the rate that the segment's own noise makes.
    norm_range_g : (float, float)
        Plausible mean norm of a rest, as fractions of the reference magnitude.
    label_max_angle_deg : float
        Largest angle between a rest's mean and an axis for it to earn that axis's label.
    others : sequence of array_like, each shape (N, 3)
        The other sensors of the recording on the same clock (gyroscope, magnetometer), in any unit:
        a rest is still on every one of them.

    Returns
    -------
    list of StaticSegment
        In time order; empty when nothing is still.

    Raises
    ------
    CalibrationError
        Samples not N×3, NaN or infinite values, a non-positive rate or parameter.
    InsufficientDataError
        Fewer samples than one window.
    """
    x = as_vectors(samples, "samples")
    fs = _positive(sampling_rate_hz, "sampling_rate_hz")
    window_s = _positive(window_s, "window_s")
    min_duration_s = _positive(min_duration_s, "min_duration_s", allow_zero=True)
    max_gap_s = _positive(max_gap_s, "max_gap_s", allow_zero=True)
    g_given = None if gravity is None else check_gravity(gravity)
    w = max(2, int(round(window_s * fs)))
    n = len(x)
    if n < w:
        raise InsufficientDataError(
            f"the stream has {n} samples, fewer than one {window_s:g} s window ({w} samples at "
            f"{fs:g} Hz): record at least {min_duration_s:g} s still in each orientation, and check "
            "sampling_rate_hz"
        )
    others = [o for o in others if o is not None]
    if any(len(o) != n for o in others):
        raise CalibrationError("the other sensors' samples must be on the accelerometer's clock: as many rows as it")
    g_ref, thr, run_a, run_b = _still_runs(
        x,
        w,
        others,
        gravity=g_given,
        noise_percentile=noise_percentile,
        noise_factor=noise_factor,
        floor_g=floor_g,
        cap_g=cap_g,
    )
    min_samples = max(1, int(round(min_duration_s * fs)))
    min_piece = max(w, min_samples // 4)
    keep = (run_b - run_a) >= min_piece
    run_a, run_b = run_a[keep], run_b[keep]
    if len(run_a) == 0:
        return []
    runs = _Runs.trimmed(
        x, run_a, run_b, w=w, half=max(1, int(round(EDGE_SMOOTH_S * fs / 2))), thr=thr, min_length=min(min_piece, w)
    )
    lo_norm, hi_norm = norm_range_g[0] * g_ref, norm_range_g[1] * g_ref
    out: list[StaticSegment] = []
    for grp in runs.merged(int(round(max_gap_s * fs)), thr):
        seg = runs.segment(
            grp,
            fs,
            min_samples=min_samples,
            norm_range=(lo_norm, hi_norm),
            max_drift_deg_per_s=max_drift_deg_per_s,
            label_max_angle_deg=label_max_angle_deg,
        )
        if seg is not None:
            out.append(seg)
    return out
