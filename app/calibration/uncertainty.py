"""Confidence intervals from a parameter covariance."""

import numpy as np
from scipy import stats

CONFIDENCE = 0.95


def t_quantile(dof: int, confidence: float = CONFIDENCE) -> float:
    """Two-sided Student-t quantile for ``dof`` degrees of freedom (normal when dof is inf)."""
    if dof <= 0:
        raise ValueError("a t quantile needs at least one degree of freedom")
    return float(stats.t.ppf(0.5 + confidence / 2.0, dof))


def half_widths(covariance: np.ndarray, dof: float, confidence: float = CONFIDENCE) -> np.ndarray:
    """Half-widths of two-sided confidence intervals from a covariance matrix.

    Parameters
    ----------
    covariance : numpy.ndarray, shape (p, p)
        Covariance of the parameter estimates.
    dof : float
        Degrees of freedom of the variance estimate behind the covariance; ``numpy.inf``
        when the noise variance was known rather than estimated (normal quantile).
    confidence : float
        Two-sided coverage, 0.95 by default.

    Returns
    -------
    numpy.ndarray, shape (p,)
        ``t_{dof} · sqrt(diag(covariance))``.
    """
    q = float(stats.norm.ppf(0.5 + confidence / 2.0)) if np.isinf(dof) else t_quantile(int(dof), confidence)
    return q * np.sqrt(np.clip(np.diag(covariance), 0.0, None))
