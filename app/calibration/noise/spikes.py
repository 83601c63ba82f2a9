"""Spikes in a still recording: single samples (or two) far off both their neighbours, replaced by them.

A register read in two transactions can pair the high byte of one sample with the low byte of the next
(a *torn read*): the reading jumps by a multiple of 256 counts for one sample and comes back. A sample
flipped in sign, or a bus error's stray value, does the same. White noise of standard deviation σ moves
one sample from the next by σ√2 typically; a jump of many times that, away and straight back, while the
neighbours on either side agree, is no sensor's noise. Left in, a few such spikes dominate the Allan
deviation's shortest averaging times and read as a white-noise density several times the sensor's.

The difference noise is the median absolute deviation of the first differences (robust: spikes are few),
taken over the differences that are not zero (a slow sensor's reading held between updates repeats),
σ = 1.4826 · MAD / √2 (Rousseeuw & Croux, "Alternatives to the median absolute deviation", JASA 88(424),
1993: 1.4826 makes the MAD consistent for the normal distribution), never below the readings' quantisation
step (a sensor quantised coarser than its noise has a MAD of zero).
"""

from __future__ import annotations

import numpy as np

SPIKE_SIGMAS = 12.0
"""A spike leaves both neighbours by more than this many σ (white noise never does: once in about 10³² samples;
a real MPU-6050's torn reads of 256 counts stand about 20 σ off its noise)."""
SPIKE_STEPS = 4.0
"""…and by more than this many quantisation steps (counts that mostly read one value)."""
NEIGHBOURS_AGREE = 0.5
"""The neighbours on either side of a spike differ by less than this fraction of the threshold: the
reading came back to where it was (a knock, a step or a turn does not)."""


MAD_SAMPLES = 200_000
"""The difference noise is read on at most this many differences, evenly spread (plenty for a median)."""


def _threshold(d: np.ndarray) -> float:
    """How far a spike leaves its neighbours, from the first differences ``d``: :data:`SPIKE_SIGMAS` times the
    difference noise, read on the non-zero differences (a reading held between a slow sensor's updates
    repeats, and zeros would make the noise look like none), and at least :data:`SPIKE_STEPS` quantisation
    steps."""
    d = d[:: max(1, len(d) // MAD_SAMPLES)]
    d = d[np.isfinite(d) & (d != 0)]
    if d.size == 0:
        return np.inf
    mad = float(np.median(np.abs(d - np.median(d))))
    quantum = float(np.abs(d).min())
    sigma = 1.4826 * mad / np.sqrt(2.0)
    return max(SPIKE_SIGMAS * sigma, SPIKE_STEPS * quantum)


def spike_mask(x) -> np.ndarray:
    """Which samples of one axis are spikes: one sample, or two in a row, off both neighbours by more than the
    threshold in the same direction, the neighbours agreeing with each other.

    Parameters
    ----------
    x : array_like, shape (N,)

    Returns
    -------
    numpy.ndarray of bool, shape (N,)
    """
    x = np.asarray(x, dtype=float)
    n = len(x)
    mask = np.zeros(n, dtype=bool)
    if n < 5:
        return mask
    d = np.diff(x)
    t = _threshold(d)
    if not np.isfinite(t):
        return mask
    jump = np.abs(d, out=d) > t  # a spike jumps away and back: only where two jumps stand close is anything checked
    for width in (1, 2):  # a sample alone, or two in a row (a torn read repeated)
        starts = np.flatnonzero(jump[: len(jump) - width] & jump[width:]) + 1  # the spike's first sample
        starts = starts[(starts >= 1) & (starts + width < n)]
        if starts.size == 0:
            continue
        before, after = x[starts - 1], x[starts + width]
        inner = np.stack([x[starts + k] for k in range(width)])
        agree = (np.abs(after - before) < NEIGHBOURS_AGREE * t) & ~mask[starts - 1] & ~mask[starts + width]
        agree &= _quiet_around(x, starts, width, NEIGHBOURS_AGREE * t)
        up = np.all(inner - np.maximum(before, after) > t, axis=0)
        down = np.all(np.minimum(before, after) - inner > t, axis=0)
        hit = starts[agree & (up | down)]
        for k in range(width):
            mask[hit + k] = True
    return mask


QUIET = 5
"""Samples on each side of a spike that must stay within the neighbours' agreement: a spike stands out of a
quiet stream (a torn read on a board at rest), not out of a hand's motion, whose fast samples look alike."""


def _quiet_around(x: np.ndarray, starts: np.ndarray, width: int, spread: float) -> np.ndarray:
    """Whether the :data:`QUIET` samples on each side of each candidate (not counting it) stay within ``spread``,
    the highest and the lowest of them left out (another spike nearby)."""
    offsets = np.concatenate([np.arange(-QUIET, 0), np.arange(width, width + QUIET)])
    rows = np.clip(starts[:, None] + offsets[None], 0, len(x) - 1)
    around = np.sort(x[rows], axis=1)
    return (around[:, -2] - around[:, 1]) < spread


def remove_spikes(samples) -> tuple[np.ndarray, np.ndarray]:
    """The samples with every spike (:func:`spike_mask`) replaced by the line through the samples on either side,
    and where the spikes were.

    Parameters
    ----------
    samples : array_like, shape (N, k)
        One sensor's samples (a memory map is read one column at a time, and copied only where it holds a
        spike).

    Returns
    -------
    cleaned : numpy.ndarray, shape (N, k)
        ``samples`` itself when it holds no spike.
    spikes : numpy.ndarray of bool, shape (N, k)
        The spiky samples of each axis.
    """
    spikes = np.column_stack([spike_mask(np.asarray(samples[:, k])) for k in range(np.shape(samples)[1])])
    if not spikes.any():
        return samples, spikes
    cleaned = np.array(samples, dtype=float)
    index = np.arange(len(cleaned))
    for k in range(cleaned.shape[1]):
        m = spikes[:, k]
        if m.any():
            cleaned[m, k] = np.interp(index[m], index[~m], cleaned[~m, k])
    return cleaned, spikes
