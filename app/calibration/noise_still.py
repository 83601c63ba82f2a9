"""The still part of a noise recording: the longest stretch in which the device rested.

The half-second blocks whose spread stays below four times the stream's own noise floor (the rule
of the upload's rest detection, app.calibration.static), knocks of up to a second merged.  The still segments of
an upload (:func:`app.calibration.static.detect_static_segments`) are not used: they end where the
mean leaves the segment's by more than a threshold, which is how they tell orientations apart — and a
still recording's slow bias drift is what the noise characterisation measures (a night of a phone
accelerometer with 1 mg of bias instability broke into stretches of seconds).
"""

from __future__ import annotations

import math

import numpy as np

from .static import MAX_GAP_S, NOISE_FACTOR, NOISE_PERCENTILE, WINDOW_S

MIN_STILL_FRACTION = 0.5
"""Below half of the recording still, the recording is not a still one: ok is false."""


def longest_still(samples, sampling_rate_hz: float):
    """``(start, end)`` sample indices (end exclusive) of the longest still stretch, or None.

    Parameters
    ----------
    samples : array_like, shape (N, 3)
        One sensor's samples (the accelerometer where there is one: it sees every handling).
    sampling_rate_hz : float
    """
    n = len(samples)
    w = max(2, int(round(WINDOW_S * sampling_rate_hz)))
    if n < 2 * w:
        return 0, n
    # Consecutive blocks of one window, not every window: a half-second resolution is plenty for the
    # still part of a long recording, and one pass over it (a night at 200 Hz in a tenth of a second).
    blocks = n // w
    spread = np.empty(blocks)
    for start in range(0, blocks, 1 << 14):
        stop = min(blocks, start + (1 << 14))
        part = np.asarray(samples[start * w:stop * w], dtype=float).reshape(stop - start, w, -1)
        spread[start:stop] = np.sqrt(part.var(axis=1).sum(axis=1))
    still = spread <= NOISE_FACTOR * np.percentile(spread, NOISE_PERCENTILE)
    gap = int(math.ceil(MAX_GAP_S * sampling_rate_hz / w))
    edges = np.diff(np.concatenate(([0], still.view(np.int8), [0])))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    if len(starts) == 0:
        return None
    runs = [[int(starts[0]), int(ends[0])]]
    for a, b in zip(starts[1:], ends[1:]):
        if a - runs[-1][1] <= gap:
            runs[-1][1] = int(b)
        else:
            runs.append([int(a), int(b)])
    a, b = max(runs, key=lambda r: r[1] - r[0])
    return a * w, (n if b == blocks else b * w)  # the samples after the last whole block go with it
