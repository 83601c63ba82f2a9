"""The still part of a noise recording: the longest stretch in which the device rested.

The half-second blocks whose spread stays below four times the stream's own noise floor (the rule
of the upload's rest detection, app.calibration.segments.static), knocks of up to a second merged — on every
sensor the recording holds (:func:`common_still_runs`): a vehicle put down rests at once by its
accelerometer while its gyroscope rings for a second more, and a compass turned about gravity moves
no accelerometer.  The still segments of
an upload (:func:`app.calibration.segments.static.detect_static_segments`) are not used: they end where the
mean leaves the segment's by more than a threshold, which is how they tell orientations apart — and a
still recording's slow bias drift is what the noise characterisation measures (a night of a phone
accelerometer with 1 mg of bias instability broke into stretches of seconds).
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from ..segments.static import MAX_GAP_S, NOISE_FACTOR, NOISE_PERCENTILE, WINDOW_S, quantisation_step
from .allan import cores

MIN_STILL_FRACTION = 0.5
"""Below half of the recording still, the recording is not a still one: ok is false."""
NOISE_REST_S = 5.0
"""A still stretch this long counts as a rest: two or more of them are separate rests (poses, handling),
and only the longest is characterised. It is also the least rest the noise is read from (:data:`NOISE_MIN_S`)."""
NOISE_MIN_S = NOISE_REST_S
"""One rest long enough for the noise: its white noise shows from a few seconds at tens of hertz (the real PX4
sample's 7.5 s rest gives the density of its whole 61 s within 15 %; half a second gives an interval spanning a
factor of six); the verdict says how long a filter's random walk needs (app.verdict). Shorter, the recording lists
the noise as not ready and the method answers ok false."""


def still_runs(samples, sampling_rate_hz: float) -> list[tuple[int, int]]:
    """``(start, end)`` sample indices (end exclusive) of every still stretch, in order.

    A stretch is a run of still half-second blocks (knocks of up to a second merged) whose mean stays
    at one level: where the means of two consecutive still blocks differ by more than four times the
    noise floor the run is cut there — the device rests in another orientation (an accelerometer's
    or a magnetometer's level), or was turned at a steady rate between rests (a gyroscope's: its
    spread stays small while it turns, its mean does not). A drifting bias moves the mean by far less
    from one half second to the next.

    Parameters
    ----------
    samples : array_like, shape (N, 3)
        One sensor's samples.
    sampling_rate_hz : float
    """
    n = len(samples)
    w = max(2, int(round(WINDOW_S * sampling_rate_hz)))
    if n < 2 * w:
        return [(0, n)]
    # Consecutive blocks of one window, not every window: a half-second resolution is plenty for the
    # still part of a long recording, and one pass over it (a night at 200 Hz in a tenth of a second),
    # about 2¹⁵ rows at a time so that the variance's temporaries stay in a core's cache, on a thread per
    # core (numpy releases the GIL; each block's figures do not depend on how many are taken together).
    blocks = n // w
    spread = np.empty(blocks)
    means = np.empty((blocks, np.shape(samples)[1]))
    step = max(1, (1 << 15) // w)

    threads = cores()
    # One buffer per thread for the chunks laid across, filled again chunk after chunk: a fresh one
    # each time is fresh pages each time (their first touch costs as much as the sums).
    across = np.empty((threads, w, means.shape[1], step)) if means.shape[1] > 1 else None

    def spreads_from(thread: int) -> None:
        for start in range(thread * step, blocks, threads * step):
            stop = min(blocks, start + step)
            part = np.asarray(samples[start * w : stop * w], dtype=float).reshape(stop - start, w, -1)
            if across is None:
                _block_spreads(part, spread[start:stop], means[start:stop])
            else:
                _block_spreads_across(part, spread[start:stop], means[start:stop], across[thread, ..., : stop - start])

    with ThreadPoolExecutor(max_workers=threads) as pool:
        list(pool.map(spreads_from, range(threads)))
    floor = max(float(np.percentile(spread, NOISE_PERCENTILE)), 0.5 * quantisation_step(samples))
    still = spread <= NOISE_FACTOR * floor
    gap = int(math.ceil(MAX_GAP_S * sampling_rate_hz / w))
    edges = np.diff(np.concatenate(([0], still.view(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    if len(starts) == 0:
        return []
    runs = [[int(starts[0]), int(ends[0])]]
    for a, b in zip(starts[1:], ends[1:]):
        if a - runs[-1][1] <= gap:
            runs[-1][1] = int(b)
        else:
            runs.append([int(a), int(b)])
    level = NOISE_FACTOR * max(floor, np.finfo(float).tiny)
    cut: list[tuple[int, int]] = []
    for a, b in runs:
        idx = a + np.flatnonzero(still[a:b])
        jumps = np.flatnonzero(np.linalg.norm(np.diff(means[idx], axis=0), axis=1) > level)
        cut += [(int(g[0]), int(g[-1]) + 1) for g in np.split(idx, jumps + 1)]
    # The samples after the last whole block go with it.
    return [(p * w, n if q == blocks else q * w) for p, q in cut]


def _block_spreads(part: np.ndarray, spread: np.ndarray, means: np.ndarray) -> None:
    """Each block's spread (the root of its axes' summed variances) and mean, into ``spread`` and ``means``.

    ``part`` is float, shape (blocks, w, k): the variances as numpy's var computes them, from the means
    just taken (not taken twice)."""
    w = part.shape[1]
    mean = part.mean(axis=1)
    dev = part - mean[:, None, :]
    np.multiply(dev, dev, out=dev)
    spread[:] = np.sqrt((dev.sum(axis=1) / w).sum(axis=1))
    means[:] = mean


def _block_spreads_across(
    part: np.ndarray, spread: np.ndarray, means: np.ndarray, across: np.ndarray | None = None
) -> None:
    """:func:`_block_spreads` of blocks of two or more axes, with the same figures to the last bit.

    numpy sums a block of shape (w, k) (rows of k > 1 axes) over its w rows one row after the other,
    with the k axes in its innermost loop: a loop of 3 for every sample of a gyroscope, a tenth of a
    second for a night at 200 Hz. Here the blocks are laid across (shape (w, k, blocks), one copy of a
    chunk that stays in cache) and summed over the same w rows in the same order, with all the
    chunk's blocks in the innermost loop. ``across``, of shape (w, k, blocks), is used for that copy
    when given.
    """
    w = part.shape[1]
    if across is None:
        across = np.empty((w, part.shape[2], part.shape[0]))
    across[...] = part.transpose(1, 2, 0)
    mean = np.add.reduce(across, axis=0)
    mean /= w
    np.subtract(across, mean, out=across)
    np.multiply(across, across, out=across)
    var = np.add.reduce(across, axis=0)
    var /= w
    spread[:] = np.sqrt(np.add.reduce(var, axis=0))
    means[:] = mean.T


def _intersect(first: list[tuple[int, int]], second: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """The stretches [a, b) inside a stretch of both lists (each in order, not overlapping itself)."""
    out, i, j = [], 0, 0
    while i < len(first) and j < len(second):
        a, b = max(first[i][0], second[j][0]), min(first[i][1], second[j][1])
        if a < b:
            out.append((a, b))
        if first[i][1] < second[j][1]:
            i += 1
        else:
            j += 1
    return out


def common_still_runs(sensors, sampling_rate_hz: float) -> list[tuple[int, int]]:
    """``(start, end)`` sample indices (end exclusive) of every stretch still on every sensor, in order.

    Each sensor's still stretches (:func:`still_runs`, on its own noise floor) are intersected: still
    means still on all of them — the accelerometer's rests cut where the gyroscope rings after a touch
    (a vehicle put down: its gyroscope oscillates at a few hertz for a second while the accelerometer
    already reads gravity alone) or where the compass turns.

    Parameters
    ----------
    sensors : sequence of array_like, each shape (N, 3)
        The sensors' samples on one clock (the rows of one recording).
    sampling_rate_hz : float
    """
    sensors = list(sensors)
    runs = still_runs(sensors[0], sampling_rate_hz)
    for samples in sensors[1:]:
        runs = _intersect(runs, still_runs(samples, sampling_rate_hz))
    return runs


def longest_still(samples, sampling_rate_hz: float):
    """``(start, end)`` sample indices (end exclusive) of the longest still stretch, or None.

    Parameters
    ----------
    samples : array_like, shape (N, 3), or a list of them
        One sensor's samples (:func:`still_runs`), or every sensor's on one clock
        (:func:`common_still_runs`: still on all of them).
    sampling_rate_hz : float
    """
    runs = (
        common_still_runs(samples, sampling_rate_hz)
        if isinstance(samples, (list, tuple))
        else still_runs(samples, sampling_rate_hz)
    )
    return max(runs, key=lambda r: r[1] - r[0]) if runs else None
