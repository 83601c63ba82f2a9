"""Segmentation of one recording into still positions and the rotations between them.

Särkkä et al. (IEEE Sensors J. 2017) section II: the device rests about 5 s in each position and is turned
in about 2 s between positions.  A sample is *still* when the gyroscope rate, averaged over a
short window after removing the bias, stays below a threshold; still runs of at least
``min_static_s`` are the positions.  Their means are taken after trimming ``trim_s`` from both
ends; each rotation is integrated from ``pad_s`` before it starts to ``pad_s`` after it ends, so
that it begins and ends at rest (Särkkä et al. eq. (5) anchors both ends).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from ..shared.errors import InsufficientDataError

DEFAULT_THRESHOLD = 0.05
"""Smoothed rate (rad/s, about 3°/s) below which the device counts as still."""


@dataclass(frozen=True)
class Segmentation:
    """Still positions and rotations of a recording (sample indices, ends exclusive).

    Attributes
    ----------
    static : tuple of (int, int)
        Trimmed still intervals, the ones the position means come from.
    still : tuple of (int, int)
        The same intervals untrimmed.
    rotations : tuple of (int, int)
        Between consecutive still intervals, padded into both.
    gyro_bias : numpy.ndarray
        Mean gyroscope rate over the still intervals.
    threshold : float or None
        The threshold used (rate units); None for annotated sections.
    pad : int
        Samples each rotation reaches into the rests on either side.
    source : str
        ``detected`` (from the gyroscope) or ``sections`` (an annotated section list).
    n_still_found : int or None
        Still segments detected before they were matched to the protocol (:mod:`.matching`).
    handling : tuple of dict
        The rests and moves left out as handling: ``kind`` (``pause``, ``move``, ``tilted``),
        ``start``, ``end`` (samples), ``text``.
    """

    static: tuple
    still: tuple
    rotations: tuple
    gyro_bias: np.ndarray
    threshold: float | None
    pad: int = 0
    source: str = "detected"
    n_still_found: int | None = None
    handling: tuple = ()

    def to_dict(self) -> dict:
        """Plain form with ``static`` and ``rotations`` as ``[start, end]`` pairs."""
        return {
            "static": [list(s) for s in self.static],
            "rotations": [list(r) for r in self.rotations],
            "gyro_bias": self.gyro_bias.tolist(),
            "threshold": self.threshold,
            "source": self.source,
            "n_still_found": self.n_still_found,
            "handling": [dict(h) for h in self.handling],
        }


def _moving_mean(x: np.ndarray, n: int) -> np.ndarray:
    """Centred moving mean over n samples (shorter at the edges)."""
    c = np.cumsum(np.vstack([np.zeros((1, x.shape[1])), x]), axis=0)
    lo = np.clip(np.arange(len(x)) - n // 2, 0, len(x))
    hi = np.clip(np.arange(len(x)) + (n - n // 2), 0, len(x))
    return (c[hi] - c[lo]) / (hi - lo)[:, None]


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(start, end) of the runs of True."""
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(d == 1).tolist(), np.flatnonzero(d == -1).tolist()))


def segment_recording(
    gyr,
    *,
    sampling_rate_hz: float,
    threshold: float | None = None,
    window_s: float = 0.2,
    min_static_s: float = 1.0,
    trim_s: float = 0.3,
    pad_s: float = 0.2,
) -> Segmentation:
    """Find the still positions and the rotations between them from the gyroscope.

    Parameters
    ----------
    gyr : numpy.ndarray, shape (N, 3)
        Raw rates in (pre-adjusted) rad/s.
    sampling_rate_hz : float
    threshold : float, optional
        Still when the smoothed rate is below it; default the larger of 0.05 rad/s and six
        times the smoothed noise.
    window_s, min_static_s, trim_s, pad_s : float
        Smoothing window, shortest position, trim of the means, padding of the rotations.

    Returns
    -------
    Segmentation

    Raises
    ------
    InsufficientDataError
        Fewer than two still positions.
    """
    fs = float(sampling_rate_hz)
    g = np.asarray(gyr, dtype=float)
    n_win = max(1, int(round(window_s * fs)))
    # Per-axis noise from first differences (robust: median absolute deviation).
    d = np.diff(g, axis=0)
    sigma = 1.4826 * np.median(np.abs(d - np.median(d, axis=0)), axis=0) / np.sqrt(2.0)
    if threshold is None:
        threshold = max(DEFAULT_THRESHOLD, 6.0 * float(np.linalg.norm(sigma)) / np.sqrt(n_win))
    bias = np.median(g, axis=0)
    for _ in range(3):
        rate = np.linalg.norm(_moving_mean(g - bias, n_win), axis=1)
        still = rate < threshold
        if still.any():
            bias = g[still].mean(axis=0)
    min_len = int(round(min_static_s * fs))
    runs = [r for r in _runs(still) if r[1] - r[0] >= min_len]
    if len(runs) < 2:
        raise InsufficientDataError(
            f"found {len(runs)} still position(s) of at least {min_static_s:g} s in the recording: hold the "
            "device still for a few seconds in each position, and check that the gyroscope is in rad/s"
        )
    trim = int(round(trim_s * fs))
    pad = int(round(pad_s * fs))
    static = []
    for a, b in runs:
        t = min(trim, (b - a) // 4)
        static.append((a + t, b - t))
    rotations = []
    for (a0, b0), (a1, b1) in itertools.pairwise(runs):
        rotations.append((max(a0, b0 - pad), min(b1, a1 + pad)))
    return Segmentation(
        static=tuple(static),
        still=tuple(runs),
        rotations=tuple(rotations),
        gyro_bias=bias,
        threshold=float(threshold),
        pad=pad,
        n_still_found=len(runs),
    )
