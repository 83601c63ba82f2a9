"""Norm errors of still readings: the one place every still-readings model measures how far its calibrated
readings are from gravity's magnitude.

At rest a calibrated reading has the magnitude of gravity, so the relative norm error
``| |a| − g | / g`` of each still reading is what every model is judged on: Georgieva et al., ESGI'95,
section 2.4 (approach 1) and section 3.5 (approach 2), and Farago, Maczak and Gingl, IEEE Access, Table 3
(mean | |r| − 1 g | in mg) and eq. (21) (the improvement ratio).
"""

from __future__ import annotations

import numpy as np

from .validation import as_vectors


def relative_norm_errors(vectors, gravity: float) -> np.ndarray:
    """``| |v| − g | / g`` of each row of ``vectors`` (N × 3)."""
    v = np.asarray(vectors, dtype=float).reshape(-1, 3)
    return np.abs(np.linalg.norm(v, axis=1) - gravity) / gravity


def evaluate_still(means, apply, gravity: float, *, what: str = "means") -> dict:
    """Norm errors of still readings before and after a calibration.

    Parameters
    ----------
    means : array_like, shape (M, 3)
        Still readings (held-out positions, control points); their true norm is ``gravity``.
    apply : callable
        The calibration: readings (M × 3) to calibrated readings.
    gravity : float
        The reference magnitude, in the readings' unit.
    what : str
        The readings' name, for the message of a malformed array.

    Returns
    -------
    dict
        ``count``; ``norm_error_max`` and ``norm_error_max_raw`` (the largest relative error after and
        before, Georgieva et al. section 3.5); ``error_before_mg`` and ``error_after_mg`` (the mean
        | |a| − g | in thousandths of g, Farago et al. Table 3); ``improvement`` (before / after, Farago et
        al. eq. (21) as a fraction; None when nothing is left after).
    """
    m = as_vectors(means, what)
    before = relative_norm_errors(m, gravity)
    after = relative_norm_errors(apply(m), gravity)
    return {
        "count": int(len(m)),
        "norm_error_max": float(after.max()),
        "norm_error_max_raw": float(before.max()),
        "error_before_mg": float(1000.0 * before.mean()),
        "error_after_mg": float(1000.0 * after.mean()),
        "improvement": float(before.mean() / after.mean()) if after.mean() > 0 else None,
    }


def norm_errors(means, apply, gravity: float) -> dict:
    """``count``, ``error_before_mg``, ``error_after_mg`` (mean | |r| − 1 g |, mg) and ``improvement_pct``
    (Farago et al. eq. (21): R = |r − 1| / |r̂ − 1| · 100 %) of still readings."""
    m = as_vectors(means, "means")
    g = float(gravity)
    before = float(1000.0 * np.mean(relative_norm_errors(m, g)))
    after = float(1000.0 * np.mean(relative_norm_errors(apply(m), g)))
    return {
        "count": int(len(m)),
        "error_before_mg": before,
        "error_after_mg": after,
        "improvement_pct": 100.0 * before / after if after > 0 else None,
    }
