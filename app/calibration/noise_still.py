"""The still part of a noise recording: the longest stretch in which the device rested.

With an accelerometer, its still segments (:func:`app.calibration.static.detect_static_segments`);
without one, the windows whose spread stays below four times the stream's own noise floor (the same
rule, :func:`app.calibration.static.window_stats`), knocks of up to a second merged.
"""

from __future__ import annotations

import numpy as np

from .static import MAX_GAP_S, NOISE_FACTOR, NOISE_PERCENTILE, WINDOW_S, detect_static_segments, window_stats

MIN_STILL_FRACTION = 0.5
"""Below half of the recording still, the recording is not a still one: ok is false."""


def longest_still(samples, sampling_rate_hz: float, *, accelerometer: bool, gravity: float | None = None):
    """``(start, end)`` sample indices (end exclusive) of the longest still stretch, or None.

    Parameters
    ----------
    samples : array_like, shape (N, 3)
    sampling_rate_hz : float
    accelerometer : bool
        The samples are specific force (the rest detection of uploads applies).
    gravity : float, optional
        Their reference magnitude, for an accelerometer.
    """
    n = len(samples)
    if accelerometer:
        segments = detect_static_segments(samples, sampling_rate_hz, gravity=gravity)
        if not segments:
            return None
        best = max(segments, key=lambda s: s.end - s.start)
        return int(best.start), int(best.end)
    w = max(2, int(round(WINDOW_S * sampling_rate_hz)))
    if n < 2 * w:
        return 0, n
    spread, _ = window_stats(np.asarray(samples, dtype=float), w)
    still = spread <= NOISE_FACTOR * np.percentile(spread, NOISE_PERCENTILE)
    gap = int(MAX_GAP_S * sampling_rate_hz)
    edges = np.diff(np.concatenate(([0], still.view(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) + w - 1
    if len(starts) == 0:
        return None
    runs = [[int(starts[0]), int(ends[0])]]
    for a, b in zip(starts[1:], ends[1:]):
        if a - runs[-1][1] <= gap:
            runs[-1][1] = int(b)
        else:
            runs.append([int(a), int(b)])
    a, b = max(runs, key=lambda r: r[1] - r[0])
    return a, min(b, n)
