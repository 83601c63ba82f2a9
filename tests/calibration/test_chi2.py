"""The χ² quantiles of app/calibration/shared/chi2.py against scipy.special.chdtri, and, where scipy's own are off
(the lower tail of ν = 10⁸), against the incomplete gamma function summed to 40 digits."""

from decimal import Decimal, localcontext
from fractions import Fraction

import numpy as np
import pytest
from scipy.special import chdtri

from app.calibration.noise.allan import FLICKER, RANDOM_WALK, WHITE, chi2_interval, edf_simple, tau_grid
from app.calibration.shared.chi2 import chi2_upper_quantile
from app.calibration.shared.errors import CalibrationError

RTOL = 1e-12
DOF_GRID = np.concatenate([[1.0, 1.5, 2.0], np.geomspace(3.0, 1e8, 400)])
P_GRID = (0.0005, 0.005, 0.025, 0.05, 0.16, 0.5, 0.84, 0.95, 0.975, 0.995, 0.9995)


@pytest.mark.parametrize("p", P_GRID)
def test_the_quantiles_of_a_dense_grid_of_dof_are_scipys(p):
    np.testing.assert_allclose(chi2_upper_quantile(DOF_GRID, p), chdtri(DOF_GRID, p), rtol=RTOL, atol=0)


def test_dof_and_probabilities_broadcast_and_scalars_give_a_scalar():
    dof = np.array([[1.0], [7.5], [1e5]])
    p = np.array([0.025, 0.5, 0.975])
    x = chi2_upper_quantile(dof, p)
    assert x.shape == (3, 3)
    np.testing.assert_allclose(x, chdtri(dof, p), rtol=RTOL, atol=0)
    assert chi2_upper_quantile(4.0, 0.5).shape == ()
    assert float(chi2_upper_quantile(2.0, 0.5)) == pytest.approx(2.0 * np.log(2.0), rel=RTOL)  # χ²₂ is exponential


def _edf_of_the_noise_method(n_samples: int, sampling_rate_hz: float) -> np.ndarray:
    """The degrees of freedom characterise_noise gives its τ grid, for each of the three noise terms."""
    ms = tau_grid(n_samples, sampling_rate_hz)
    return np.concatenate([edf_simple(n_samples + 1, ms, alpha) for alpha in (WHITE, FLICKER, RANDOM_WALK)])


@pytest.mark.parametrize("n_samples", [20_000, 3 * 3600 * 200])
@pytest.mark.parametrize("confidence", [0.95, 0.5, 0.683, 0.99, 0.999])
def test_the_intervals_of_the_noise_method_are_scipys(n_samples, confidence):
    # The τ grid's and, for the terms read on their own, Satterthwaite's (any value from 1 up).
    edf = np.concatenate([_edf_of_the_noise_method(n_samples, 200.0), [1.0, 1.37, 2.5, 17.2, 3.1e4]])
    tail = (1.0 - confidence) / 2.0
    lo, hi = chi2_interval(edf, confidence)
    np.testing.assert_allclose(lo, edf / chdtri(edf, tail), rtol=RTOL, atol=0)
    np.testing.assert_allclose(hi, edf / chdtri(edf, 1.0 - tail), rtol=RTOL, atol=0)
    assert np.all(lo < 1.0) and np.all(hi > 1.0)


def test_a_scalar_edf_gives_scalar_factors():
    lo, hi = chi2_interval(12.5)
    assert lo.shape == hi.shape == ()
    assert float(lo) == pytest.approx(12.5 / chdtri(12.5, 0.025), rel=RTOL)
    assert float(hi) == pytest.approx(12.5 / chdtri(12.5, 0.975), rel=RTOL)


@pytest.mark.parametrize("p", [1e-300, 1e-100, 1e-20, 1e-10, 1e-6, 1 - 1e-6, 1 - 1e-10, 1 - 2**-53])
def test_one_degree_of_freedom_far_in_either_tail_is_scipys(p):
    # From 1e-300 to 1 − 2⁻⁵³ (the largest float below 1): x from 1374 down to 2·10⁻³².
    assert float(chi2_upper_quantile(1.0, p)) == pytest.approx(float(chdtri(1.0, p)), rel=RTOL)


@pytest.mark.parametrize("p", [1e-300, 1e-100, 1e-20, 1e-10, 1e-6])
def test_1e8_degrees_of_freedom_far_in_the_upper_tail_are_scipys(p):
    assert float(chi2_upper_quantile(1e8, p)) == pytest.approx(float(chdtri(1e8, p)), rel=RTOL)


# Γ(a + 1) by Stirling's series (A&S eq. 6.1.40), B₂ₖ for k = 1 … 8: its error for a ≥ 10⁷ is far below 40 digits.
BERNOULLI = (
    Fraction(1, 6),
    Fraction(-1, 30),
    Fraction(1, 42),
    Fraction(-1, 30),
    Fraction(5, 66),
    Fraction(-691, 2730),
    Fraction(7, 6),
    Fraction(-3617, 510),
)
TWO_PI = Decimal("6.283185307179586476925286766559005768394338798750211641950")


def lower_tail_40_digits(dof: float, x: float) -> Decimal:
    """P(χ²_ν ≤ x) = P(ν/2, x/2) to 40 digits, for ν ≥ 2·10⁷ and x < ν: yᵃ e^{−y} / Γ(a + 1) times the
    series Σ yⁿ / ((a + 1)…(a + n)) (A&S eq. 6.5.29), in decimal arithmetic."""
    with localcontext() as ctx:
        ctx.prec = 45
        a, y = Decimal(dof) / 2, Decimal(x) / 2
        assert a >= 10**7 and y < a
        log_gamma = (a + Decimal("0.5")) * a.ln() - a + TWO_PI.ln() / 2
        for k, b in enumerate(BERNOULLI, start=1):
            log_gamma += Decimal(b.numerator) / Decimal(b.denominator) / (2 * k * (2 * k - 1) * a ** (2 * k - 1))
        total = term = Decimal(1)
        n = 0
        while term > total * Decimal("1e-42"):
            n += 1
            term = term * y / (a + n)
            total += term
        return (a * y.ln() - y - log_gamma + total.ln()).exp()


@pytest.mark.parametrize("p", [0.9995, 1 - 1e-6, 1 - 1e-10, 1 - 2**-53])
def test_1e8_degrees_of_freedom_far_in_the_lower_tail_hold_the_probability_to_1e_12(p):
    """Here scipy 1.17's chdtri is off by up to 8·10⁻⁶ (its P at its own quantile, gammainc, agrees with it, but
    not with the series summed to 40 digits); the quantile x is checked by P(x (1 ∓ 10⁻¹²)) bracketing 1 − p."""
    x = float(chi2_upper_quantile(1e8, p))
    target = Decimal(1) - Decimal(p)
    assert lower_tail_40_digits(1e8, x * (1 - RTOL)) < target < lower_tail_40_digits(1e8, x * (1 + RTOL))


def test_the_lower_tail_of_less_than_one_degree_of_freedom_may_lie_below_the_floats():
    # P(χ²_ν ≤ x) ≈ (x/2)^{ν/2} / Γ(ν/2 + 1): the quantile of 10⁻¹⁰ for ν = 0.05 is about 10⁻⁴⁰⁰.
    assert float(chi2_upper_quantile(0.05, 1 - 1e-10)) == 0.0
    np.testing.assert_allclose(chi2_upper_quantile([0.1, 0.5], 0.9995), chdtri([0.1, 0.5], 0.9995), rtol=RTOL)


@pytest.mark.parametrize("dof", [0.0, -1.0, np.nan, np.inf, -np.inf])
def test_degrees_of_freedom_not_positive_and_finite_are_refused(dof):
    with pytest.raises(CalibrationError, match="positive, finite degrees of freedom"):
        chi2_upper_quantile([5.0, dof], 0.5)


@pytest.mark.parametrize("p", [0.0, 1.0, -0.1, 1.5, np.nan])
def test_probabilities_outside_0_1_are_refused(p):
    with pytest.raises(CalibrationError, match="strictly between 0 and 1"):
        chi2_upper_quantile(5.0, [0.5, p])


@pytest.mark.parametrize("confidence", [0.0, 1.0, -0.5, 1.2, np.nan])
def test_a_confidence_outside_0_1_is_refused(confidence):
    with pytest.raises(CalibrationError, match="confidence lies strictly between 0 and 1"):
        chi2_interval([3.0, 40.0], confidence)
