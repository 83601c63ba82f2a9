"""Confidence intervals from a parameter covariance."""

import numpy as np

# The quantiles come from scipy.special (what scipy.stats.t.ppf and norm.ppf call), imported where
# used: scipy.stats takes ~0.5–1 s to import, which `trical autocal` on a week of data in under 3 s
# cannot afford.

CONFIDENCE = 0.95


def t_quantile(dof: float, confidence: float = CONFIDENCE) -> float:
    """Two-sided Student-t quantile for ``dof`` degrees of freedom, which may be fractional (Satterthwaite's)."""
    if dof <= 0:
        raise ValueError("a t quantile needs at least one degree of freedom")
    from scipy.special import stdtrit

    return float(stdtrit(dof, 0.5 + confidence / 2.0))


def half_widths(covariance: np.ndarray, dof: float, confidence: float = CONFIDENCE) -> np.ndarray:
    """Half-widths of two-sided confidence intervals from a covariance matrix.

    Parameters
    ----------
    covariance : numpy.ndarray, shape (p, p)
        Covariance of the parameter estimates.
    dof : float
        Degrees of freedom of the variance estimate behind the covariance (fractional where Satterthwaite's
        approximation gives them); ``numpy.inf``
        when the noise variance was known rather than estimated (normal quantile).
    confidence : float
        Two-sided coverage, 0.95 by default.

    Returns
    -------
    numpy.ndarray, shape (p,)
        ``t_{dof} · sqrt(diag(covariance))``.
    """
    from scipy.special import ndtri

    q = float(ndtri(0.5 + confidence / 2.0)) if np.isinf(dof) else t_quantile(float(dof), confidence)
    return q * np.sqrt(np.clip(np.diag(covariance), 0.0, None))


def covariance_from_jacobian(jacobian: np.ndarray, residuals: np.ndarray) -> tuple[np.ndarray | None, int, float]:
    """Parameter covariance of a (non-linear) least-squares fit from its Jacobian at the solution.

    Särkkä et al. (IEEE Sensors J. 2017), Appendix A: to first order ``V(ξ) = (Jᵀ V(ε)⁻¹ J)⁻¹`` (eq. (22));
    with independent residuals of one unknown variance σ², ``V(ε) = σ² I`` and σ² is estimated
    by ``RSS / (N − p)``, so ``V(ξ) = σ² (Jᵀ J)⁻¹``.

    Parameters
    ----------
    jacobian : numpy.ndarray, shape (N, p)
        Derivatives of the N residuals with respect to the p parameters at the solution.
    residuals : numpy.ndarray, shape (N,)
        Residuals at the solution.

    Returns
    -------
    covariance : numpy.ndarray of shape (p, p), or None
        None when there is no residual degree of freedom (N ≤ p) or Jᵀ J is singular.
    dof : int
        Residual degrees of freedom, ``max(N − p, 0)``.
    sigma2 : float
        Residual variance estimate (nan without degrees of freedom).
    """
    J = np.asarray(jacobian, dtype=float)
    r = np.asarray(residuals, dtype=float).ravel()
    n, p = J.shape
    dof = max(n - p, 0)
    if dof == 0:
        return None, 0, float("nan")
    sigma2 = float(r @ r) / dof
    jtj = J.T @ J
    # Scale the columns before inverting: parameters of different units give a badly scaled JᵀJ.
    d = np.sqrt(np.diag(jtj))
    if not np.all(np.isfinite(d)) or np.any(d == 0.0):
        return None, dof, sigma2
    scaled = jtj / np.outer(d, d)
    if np.linalg.cond(scaled) > 1e14:
        return None, dof, sigma2
    cov = sigma2 * np.linalg.inv(scaled) / np.outer(d, d)
    return 0.5 * (cov + cov.T), dof, sigma2
