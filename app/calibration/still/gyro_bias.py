"""The gyroscope's bias from the still captures of a wizard session.

At rest a gyroscope reads its bias plus the Earth's rotation (7.3e-5 rad/s = 0.004 °/s at most,
below a phone gyroscope's bias and its resolution; it is not removed). Each still capture k
gives a mean m_k of its n_k samples; the bias is their mean over the K captures, and its 95 %
interval comes from how the capture means scatter around it.

Why captures and not samples make the interval: a MEMS gyroscope's bias is not one constant over a
session. It wanders (bias instability and rate random walk, IEEE Std 952-1997, Annex C; Allan
variance, IEEE Std 1554-2005) and shifts with temperature and between turn-ons, so two captures a
minute apart differ by more than their within-capture standard errors σ/√n_k allow. The samples'
standard error ``σ/√N`` counts only the white noise and gives an interval that is too narrow; the
spread of the K capture means holds the white noise and the wander alike, so the Student-t
interval over captures (the standard one-sample interval of their mean, e.g. NIST/SEMATECH
e-Handbook of Statistical Methods, section 7.2.2.1) covers the session's mean bias at its nominal
level. With a single capture there is no between-capture spread to see: the interval is the
within-capture standard error, and ``interval_from`` says so ("samples").
"""

from __future__ import annotations

import numpy as np

from ..shared.errors import CalibrationError
from ..shared.uncertainty import CONFIDENCE, t_quantile

FORMULA_CAPTURES = "b = mean_k m_k; half-width = t(0.975, K-1) * s_K / sqrt(K), s_K the std of the K capture means"
FORMULA_SAMPLES = "b = m_1; half-width = t(0.975, n-1) * s / sqrt(n), s the std of the capture's n samples"


def gyroscope_bias(means_rad_s, stds_rad_s, counts, confidence: float = CONFIDENCE) -> dict:
    """The gyroscope bias of still captures and its two-sided confidence interval, per axis.

    Parameters
    ----------
    means_rad_s : array_like, shape (K, 3)
        Mean gyroscope reading of each still capture, rad/s.
    stds_rad_s : array_like, shape (K, 3)
        Sample standard deviation (``ddof=1``) of each capture's readings, rad/s; used only when
        K is 1.
    counts : array_like of int, shape (K,)
        Samples in each capture.
    confidence : float
        Two-sided coverage of the interval, 0.95 by default.

    Returns
    -------
    dict
        ``rad_s`` and ``deg_s`` (the bias, 3 each), ``half_width_rad_s`` and ``half_width_deg_s``
        (the interval's half-width), ``count`` (K), ``confidence``, ``interval_from``
        (``"captures"`` when K ≥ 2: t with K − 1 degrees of freedom on the spread of the capture
        means; ``"samples"`` when K is 1: t with n − 1 on the capture's standard error) and
        ``formula``.

    Raises
    ------
    CalibrationError
        Shapes that do not match, values that are not finite, no capture, or a single capture of
        fewer than two samples.

    Notes
    -----
    The capture means are treated as independent draws around the session's bias: the interval over
    captures includes the bias's wander between captures (bias instability, IEEE Std 952-1997,
    Annex C), which the samples' standard error would leave out.
    """
    m = np.asarray(means_rad_s, dtype=float)
    s = np.asarray(stds_rad_s, dtype=float)
    n = np.asarray(counts, dtype=float).reshape(-1)
    if m.ndim != 2 or m.shape[1] != 3 or m.shape[0] == 0:
        raise CalibrationError(f"the gyroscope means must have shape (K, 3) with K ≥ 1; got {m.shape}")
    if s.shape != m.shape or n.shape != (m.shape[0],):
        raise CalibrationError(
            f"give one std row (3) and one count per capture: {m.shape[0]} means, std shape {s.shape}, {n.size} counts"
        )
    if not (np.all(np.isfinite(m)) and np.all(np.isfinite(n))):
        raise CalibrationError("a gyroscope capture mean or count is not a finite number")
    if np.any(n < 1) or np.any(n != np.round(n)):
        raise CalibrationError("each capture's sample count must be a whole number of at least 1")
    k = m.shape[0]
    bias = m.mean(axis=0)
    if k >= 2:
        half = t_quantile(k - 1, confidence) * m.std(axis=0, ddof=1) / np.sqrt(k)
        source, formula = "captures", FORMULA_CAPTURES
    else:
        if n[0] < 2 or not np.all(np.isfinite(s)):
            raise CalibrationError(
                "a single gyroscope capture needs at least two samples and a finite std "
                "for its interval: capture longer, or capture more poses"
            )
        half = t_quantile(int(n[0]) - 1, confidence) * s[0] / np.sqrt(n[0])
        source, formula = "samples", FORMULA_SAMPLES
    return {
        "rad_s": bias.tolist(),
        "half_width_rad_s": half.tolist(),
        "deg_s": np.degrees(bias).tolist(),
        "half_width_deg_s": np.degrees(half).tolist(),
        "count": int(k),
        "confidence": float(confidence),
        "interval_from": source,
        "formula": formula,
    }
