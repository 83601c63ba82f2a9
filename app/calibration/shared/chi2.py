"""Quantiles of the χ² distribution, from numpy and the standard library alone.

The χ²_ν value exceeded with probability p is 2y, where y solves Q(a, y) = p for a = ν/2, with
P(a, y) = γ(a, y)/Γ(a) (Abramowitz and Stegun, *Handbook of Mathematical Functions*, 1964, eq. 6.5.1)
and Q = 1 − P the regularized incomplete gamma functions: P(χ²|ν) = P(ν/2, χ²/2) (Press, Teukolsky,
Vetterling and Flannery, *Numerical Recipes*, 3rd ed. 2007, §6.2). It is what ``scipy.special.chdtri(ν,
p)`` computes, without the quarter of a second that importing scipy.special costs (its array-API layer
loads numpy.f2py, numpy.ma and numpy.testing).

- P and Q: the series of γ(a, y) below y = a + 1 + 2√a, the continued fraction of Γ(a, y) above it
  (A&S eqs. 6.5.29 and 6.5.31; Numerical Recipes §6.2, ``gser`` and ``gcf``, the fraction by the
  modified Lentz method, §5.2). The series runs over whole blocks of terms as array operations, so the
  O(√a) terms it needs near y ≈ a cost no Python loop per term; the continued fraction, which would need
  thousands of steps there for a ≈ 10⁷, starts two standard deviations (√a) further out, where it takes
  about a hundred.
- Their common factor yᵃ e^{−y} / Γ(a + 1) without cancellation for large a: with r = y/a, its logarithm
  is a (ln r − (r − 1)) − (ln Γ(a + 1) − a ln a + a), the last term from Stirling's series (A&S eq.
  6.1.40) for a ≥ :data:`STIRLING_FROM`.
- The root: Halley's method (as Numerical Recipes' inverse of P(a, x), §6.2.1) on ln T(y) = ln p in
  u = ln y, T the smaller tail (P for the lower, Q for the upper, so that no digit of a small p is lost),
  from the Wilson–Hilferty approximation (E. B. Wilson and M. M. Hilferty, *The distribution of
  chi-square*, PNAS 17 (1931) 684–688; A&S eq. 26.4.17). Both ln P and ln Q are concave in ln y, so
  Newton's steps, taken where Halley's are not yet safe, approach the root from one side and never diverge.
"""

from __future__ import annotations

import math

import numpy as np

from .errors import CalibrationError

STIRLING_FROM = 10.0
"""Shapes a from which ln Γ(a + 1) − (a ln a − a) comes from Stirling's series: its terms up to a⁻¹³
leave less than 3·10⁻¹⁷ there; below, math.lgamma's own values are small enough to subtract."""

STIRLING = (1.0 / 12.0, -1.0 / 360.0, 1.0 / 1260.0, -1.0 / 1680.0, 1.0 / 1188.0, -691.0 / 360360.0, 1.0 / 156.0)
"""B₂ₖ / (2k (2k − 1)) for k = 1 … 7, the coefficients of a^{−(2k−1)} in Stirling's series (A&S eq. 6.1.40)."""

SERIES_REACH = 2.0
"""The series serves y < a + 1 + 2√a (the continued fraction's y ≥ a + 1 of Numerical Recipes, moved out
by two standard deviations of the gamma distribution, where the continued fraction converges fast)."""

FIRST_BLOCK = 32
"""Terms of the series in its first block; each next block is twice as long."""

MAX_STEPS = 100
"""Steps of the root finding at most; from the Wilson–Hilferty start two or three suffice."""

STEP_TOL = 1e-11
"""|Δ ln y| of a Halley step below which the iteration has converged: the error it leaves is of the order of
a·|Δ ln y|³ (cubic convergence, its constant ∝ (h''/h')² ∝ a), under 10⁻²⁴ for every a up to 10⁸."""

NOISE_STEP = 1e-9
"""|Δ ln y| below which a step that is not an eighth of the one before is rounding noise, not progress."""

MAX_TERMS = 1 << 27
"""Terms of the series at most (it needs about 9√a, 90 000 for ν = 10⁸)."""

MAX_FRACTION = 10_000
"""Steps of the continued fraction at most (it needs at most a few hundred where it is used)."""

EPS = float(np.finfo(float).eps)
TINY = float(np.finfo(float).tiny)


def chi2_upper_quantile(dof, p) -> np.ndarray:
    """The χ²_ν value exceeded with probability ``p``: ``scipy.special.chdtri(dof, p)``, or
    ``scipy.stats.chi2.isf(p, dof)``.

    Parameters
    ----------
    dof : array_like
        Degrees of freedom ν, positive and finite, not necessarily integers (tested from 1 to 10⁸; the
        work grows as √ν).
    p : array_like
        Upper-tail probabilities, each in (0, 1); broadcast against ``dof``.

    Returns
    -------
    numpy.ndarray
        The quantiles x with P(χ²_ν > x) = p, of the broadcast shape (0-d for scalars); relative
        difference to scipy.special.chdtri at most 10⁻¹² (tests/calibration/test_chi2.py).

    Raises
    ------
    CalibrationError
        A degree of freedom not positive and finite, or a probability outside (0, 1).
    """
    nu, upper = np.broadcast_arrays(np.asarray(dof, dtype=float), np.asarray(p, dtype=float))
    if not np.all(np.isfinite(nu) & (nu > 0)):
        bad = nu[~(np.isfinite(nu) & (nu > 0))].flat[0]
        raise CalibrationError(f"χ² quantiles need positive, finite degrees of freedom, not {bad}")
    if not np.all((upper > 0) & (upper < 1)):
        bad = upper[~((upper > 0) & (upper < 1))].flat[0]
        raise CalibrationError(f"a χ² quantile needs a probability strictly between 0 and 1, not {bad}")
    a = 0.5 * nu.ravel()
    upper = upper.ravel()
    # The smaller tail is matched, so that its logarithm is exact: for p ≥ ½, 1 − p is exact (Sterbenz).
    lower_tail = upper > 0.5
    target = np.where(lower_tail, 1.0 - upper, upper)
    u = _log_gamma_quantile(a, np.log(target), lower_tail, _wilson_hilferty(a, upper))
    return (2.0 * np.exp(u)).reshape(nu.shape)


def _log_gamma_quantile(a: np.ndarray, log_target: np.ndarray, lower_tail: np.ndarray, u: np.ndarray) -> np.ndarray:
    """u = ln y with ln P(a, y) = ``log_target`` where ``lower_tail``, ln Q(a, y) = ``log_target`` elsewhere,
    by Halley's method from ``u``: h(u) = ln T − ln target, h'(u) = ± a yᵃ e^{−y} / (Γ(a + 1) T) (y times the
    derivative of P, y^{a−1} e^{−y} / Γ(a), A&S eq. 6.5.1). In u, a quantile below the smallest float (the
    lower tail of ν < 1) is found as well as any other."""
    u = u.copy()
    previous = np.full_like(u, np.inf)
    active = np.arange(len(a))
    for _ in range(MAX_STEPS):
        if len(active) == 0:
            return u
        ai, ui, low = a[active], u[active], lower_tail[active]
        yi = np.exp(ui)
        log_factor, log_p, log_q = _log_tails(ai, ui, yi)
        log_tail = np.where(low, log_p, log_q)
        # h = ln T − ln target in u = ln y; h' = ± a e^{L − ln T} (L the log of the common factor), and
        # h''/h' = a − y − h' (from dL/du = a − y).
        slope = ai * np.exp(log_factor - log_tail)
        slope = np.where(low, slope, -slope)
        newton = (log_tail - log_target[active]) / slope
        bend = 0.5 * newton * (ai - yi - slope)
        # Halley's step (cubic convergence; Press et al., Numerical Recipes, 3rd ed., §9.4.1) near the root,
        # Newton's where Halley's correction is large (far from it).
        step = np.where(np.abs(bend) <= 0.5, -newton / (1.0 - bend), -newton)
        u[active] = ui + step
        size = np.abs(step)
        # Done when the step is below STEP_TOL, or small but no longer shrinking as fast as it did: the
        # rounding of ln T (a few ε of its terms) is all that is left to chase.
        done = (size <= STEP_TOL) | ((size <= NOISE_STEP) & (size > previous[active] / 8.0))
        previous[active] = size
        active = active[~done]
    raise ArithmeticError(f"the χ² quantile did not converge in {MAX_STEPS} steps for ν = {2.0 * a[active]}")


def _wilson_hilferty(a: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """The starting ln y: Wilson and Hilferty's (χ²/ν)^{1/3} ≈ normal with mean 1 − 2/(9ν) and variance
    2/(9ν) (A&S eq. 26.4.17; here ν = 2a), or, where that is far from positive (the lower tail of few
    degrees of freedom), the first term of the series, P ≈ yᵃ / Γ(a + 1)."""
    z = _normal_upper_quantile(upper)
    base = 1.0 - 1.0 / (9.0 * a) + z / (3.0 * np.sqrt(a))
    lgamma1 = np.array([math.lgamma(v + 1.0) for v in a])
    first_term = (np.log1p(-upper) + lgamma1) / a
    return np.where(base > 0.1, np.log(a) + 3.0 * np.log(np.maximum(base, 0.1)), first_term)


def _normal_upper_quantile(upper: np.ndarray) -> np.ndarray:
    """z with 1 − Φ(z) = ``upper`` to 4.5·10⁻⁴ (A&S eq. 26.2.23, Hastings' rational approximation): a
    starting value only."""
    q = np.minimum(upper, 1.0 - upper)
    t = np.sqrt(-2.0 * np.log(q))
    z = t - (2.515517 + t * (0.802853 + t * 0.010328)) / (1.0 + t * (1.432788 + t * (0.189269 + t * 0.001308)))
    return np.where(upper > 0.5, -z, z)


def _log_tails(a: np.ndarray, u: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """ln(yᵃ e^{−y} / Γ(a + 1)), ln P(a, y) and ln Q(a, y); the tail the method does not give directly is
    its complement, which there is above 0.01 (Q below y = a + 1 + 2√a, P above it), so that the
    subtraction loses nothing."""
    log_factor = _log_power_factor(a, u, y)
    log_p = np.empty_like(y)
    log_q = np.empty_like(y)
    near = y < a + 1.0 + SERIES_REACH * np.sqrt(a)
    if near.any():
        log_p[near] = log_factor[near] + np.log(_lower_series(a[near], y[near]))
        log_q[near] = np.log1p(-np.exp(log_p[near]))
    far = ~near
    if far.any():
        log_q[far] = log_factor[far] + np.log(a[far] * _upper_fraction(a[far], y[far]))
        log_p[far] = np.log1p(-np.exp(log_q[far]))
    return log_factor, log_p, log_q


def _log_power_factor(a: np.ndarray, u: np.ndarray, y: np.ndarray) -> np.ndarray:
    """ln(yᵃ e^{−y} / Γ(a + 1)) = a (ln r − (r − 1)) − (ln Γ(a + 1) − a ln a + a), r = y/a: no term is large
    when y is near a, where the plain a ln y − y − ln Γ(a + 1) would lose ~ε·a to cancellation (10⁻⁸ for
    ν = 10⁸). ln r rather than ln(1 + t), t = r − 1, keeps the digits of a y far below a."""
    ratio = y / a
    with np.errstate(divide="ignore"):
        log_ratio = np.where(ratio >= TINY, np.log(ratio), u - np.log(a))  # u: y below the floats
    return a * (log_ratio - (ratio - 1.0)) - _stirling_remainder(a)


def _stirling_remainder(a: np.ndarray) -> np.ndarray:
    """ln Γ(a + 1) − (a ln a − a) = ½ ln(2πa) + Σ B₂ₖ / (2k (2k − 1) a^{2k−1}) (A&S eq. 6.1.40, with
    ln Γ(a + 1) = ln Γ(a) + ln a) for a ≥ :data:`STIRLING_FROM`; math.lgamma below."""
    out = np.empty_like(a)
    big = a >= STIRLING_FROM
    if big.any():
        ab = a[big]
        inv2 = 1.0 / (ab * ab)
        series = np.zeros_like(ab)
        for c in reversed(STIRLING):
            series = series * inv2 + c
        out[big] = 0.5 * np.log(2.0 * math.pi * ab) + series / ab
    small = ~big
    if small.any():
        out[small] = [math.lgamma(v + 1.0) - v * math.log(v) + v for v in a[small]]
    return out


def _lower_series(a: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Σ_{n≥0} yⁿ / ((a + 1)(a + 2)…(a + n)), which times yᵃ e^{−y} / Γ(a + 1) is P(a, y) (A&S eq. 6.5.29;
    Numerical Recipes §6.2, ``gser``): summed in blocks of terms, each block's terms the running products
    of its ratios y / (a + n) (numpy.cumprod), each block twice as long as the one before, until every
    sum's last term is below ε of it and falling. Near y ≈ a it takes about 9√a terms."""
    total = np.ones_like(y)
    last = np.ones_like(y)
    active = np.arange(len(y))
    n0, width = 0, FIRST_BLOCK
    while len(active):
        n = n0 + 1.0 + np.arange(width)
        ratios = y[active, None] / (a[active, None] + n)
        terms = last[active, None] * np.cumprod(ratios, axis=1)
        total[active] += terms.sum(axis=1)
        last[active] = terms[:, -1]
        done = (terms[:, -1] <= EPS * total[active]) & (ratios[:, -1] < 1.0)
        active = active[~done]
        n0, width = n0 + width, 2 * width
        if n0 > MAX_TERMS:
            raise ArithmeticError(f"the series of P(a, y) did not converge in {MAX_TERMS} terms for a = {a[active]}")
    return total


def _upper_fraction(a: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The continued fraction 1/(y + 1 − a − 1·(1 − a)/(y + 3 − a − 2·(2 − a)/(y + 5 − a − …))), which
    times yᵃ e^{−y} / Γ(a) is Q(a, y) (the even part of A&S eq. 6.5.31; Numerical Recipes §6.2, ``gcf``),
    by the modified Lentz method (Numerical Recipes §5.2), every element at once until each has converged."""
    b = y + 1.0 - a
    c = np.full_like(y, 1.0 / TINY)
    d = 1.0 / b
    h = d.copy()
    active = np.arange(len(y))
    i = 0
    while len(active):
        i += 1
        an = -i * (i - a[active])
        b[active] += 2.0
        dd = an * d[active] + b[active]
        dd[np.abs(dd) < TINY] = TINY
        cc = b[active] + an / c[active]
        cc[np.abs(cc) < TINY] = TINY
        dd = 1.0 / dd
        delta = dd * cc
        d[active], c[active] = dd, cc
        h[active] *= delta
        active = active[~(np.abs(delta - 1.0) <= EPS)]
        if i == MAX_FRACTION:
            raise ArithmeticError(f"the continued fraction of Q(a, y) did not converge for a = {a[active]}")
    return h
