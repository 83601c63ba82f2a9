"""Drift during the session (Särkkä et al. (IEEE Sensors J. 2017), section II).

After the last position the device returns to position 1; in the absence of drift a sensor then
reads what it read at the start.  With two observations the drift is modelled as an affine
function of time and removed from the raw measurements.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SIGNIFICANCE = 3.0
"""A change below this many standard errors is noise: removing it would only add noise."""


@dataclass(frozen=True)
class Drift:
    """Affine drift of one sensor: raw(t) gains ``rate · (t − t0)``.

    Attributes
    ----------
    rate : numpy.ndarray, shape (3,)
        Raw units per second.
    t0_s : float
        Time of the first observation (centre of position 1), seconds from the first sample.
    change : numpy.ndarray, shape (3,)
        Mean at the return minus mean at position 1, raw units.
    z : numpy.ndarray, shape (3,)
        ``change`` over its standard error from the two positions' sample variances.
    """

    rate: np.ndarray
    t0_s: float
    change: np.ndarray
    z: np.ndarray | None = None

    @property
    def significant(self) -> bool:
        """True when some axis changed by more than SIGNIFICANCE standard errors."""
        return self.z is None or bool(np.max(np.abs(self.z)) > SIGNIFICANCE)

    def remove(self, raw: np.ndarray, sampling_rate_hz: float) -> np.ndarray:
        """Raw samples with the drift removed (Särkkä et al. section II: the adjustment is on raw data)."""
        t = np.arange(len(raw)) / float(sampling_rate_hz)
        return raw - (t - self.t0_s)[:, None] * self.rate

    def to_dict(self) -> dict:
        return {
            "rate_per_s": self.rate.tolist(),
            "t0_s": self.t0_s,
            "change": self.change.tolist(),
            "z": None if self.z is None else self.z.tolist(),
            "significant": self.significant,
        }


def estimate_drift(raw, first: tuple[int, int], last: tuple[int, int], *, sampling_rate_hz: float) -> Drift:
    """Affine drift from the same position observed at the start and at the end (Särkkä et al. section II).

    Parameters
    ----------
    raw : numpy.ndarray, shape (N, 3)
        Raw samples of one sensor.
    first, last : (int, int)
        Sample intervals (end exclusive) of position 1 and of the return to it.
    sampling_rate_hz : float

    Returns
    -------
    Drift
    """
    raw = np.asarray(raw, dtype=float)
    fs = float(sampling_rate_hz)
    x0, x1 = raw[first[0] : first[1]], raw[last[0] : last[1]]
    m0, m1 = x0.mean(axis=0), x1.mean(axis=0)
    se = np.sqrt(x0.var(axis=0, ddof=1) / len(x0) + x1.var(axis=0, ddof=1) / len(x1))
    t0 = 0.5 * (first[0] + first[1] - 1) / fs
    t1 = 0.5 * (last[0] + last[1] - 1) / fs
    z = (m1 - m0) / np.where(se > 0, se, np.inf)
    return Drift(rate=(m1 - m0) / (t1 - t0), t0_s=float(t0), change=m1 - m0, z=z)
