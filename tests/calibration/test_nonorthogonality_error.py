"""Georgieva et al. (ESGI'95) section 2.3: the error of ignoring non-orthogonal axes (Problems 1, 2)."""

import numpy as np
import pytest

from app.calibration.shared.errors import CalibrationError
from app.calibration.still.nonorthogonal import gram_matrix
from app.calibration.still.nonorthogonality_error import (
    a_nonorth,
    a_orth,
    max_error_at_gravity,
    max_relative_error,
    nonorthogonality_error,
    relative_nonorthogonality_error,
)

HI = 1.02 * np.pi / 2  # 1.60221, the paper's maximising angle


@pytest.fixture(scope="module")
def problem1():
    return max_error_at_gravity(9.80665)


def test_eq_10_is_the_gram_form():
    rng = np.random.default_rng(0)
    a = rng.normal(size=(50, 3)) * 9.8
    ang = (1.55, 1.6, 1.58)
    Gi = np.linalg.inv(gram_matrix(*ang))
    expected = np.sqrt(np.einsum("ij,jk,ik->i", a, Gi, a))
    np.testing.assert_allclose(a_nonorth(a, *ang), expected, rtol=1e-12)
    np.testing.assert_allclose(a_nonorth(a, np.pi / 2, np.pi / 2, np.pi / 2), a_orth(a), rtol=1e-12)


def test_problem_1_value_and_maximiser(problem1):
    """0.3130299 m/s² in the paper at a_x = a_y = a_z ≈ 5.48114, φ = ψ = θ ≈ 1.60221."""
    assert problem1.value == pytest.approx(0.31303, abs=5e-6)
    assert problem1.value == pytest.approx(0.3130299, abs=1e-6)
    np.testing.assert_allclose(problem1.acceleration, [5.48114] * 3, atol=1e-5)
    np.testing.assert_allclose(problem1.angles, [1.60221] * 3, atol=1e-5)
    np.testing.assert_allclose(problem1.angles, HI, atol=1e-9)
    # The maximiser satisfies the constraint of (18) and attains the value.
    assert float(a_nonorth(problem1.acceleration, *problem1.angles)) == pytest.approx(9.80665, abs=1e-8)
    assert float(nonorthogonality_error(problem1.acceleration, *problem1.angles)) == pytest.approx(problem1.value)


def test_problem_1_closed_form(problem1):
    # a_orth / a_nonorth = sqrt(λ_min(G)) with λ_min = 1 + 2 cos(1.02 π/2) along (1, 1, 1).
    assert problem1.value == pytest.approx(9.80665 * (1 - np.sqrt(1 + 2 * np.cos(HI))), rel=1e-9)


def test_problem_2_relative_error():
    """≈ 3.192 % in the paper, the same for ±4 g, ±8 g and ±16 g."""
    res16 = max_relative_error(range_g=16)
    assert 100 * res16.value == pytest.approx(3.192, abs=5e-4)
    assert res16.value == pytest.approx(1 - np.sqrt(1 + 2 * np.cos(HI)), rel=1e-9)
    np.testing.assert_allclose(res16.angles, HI, atol=1e-9)
    a = res16.acceleration
    assert np.abs(a).max() == pytest.approx(16 * 9.80665)
    np.testing.assert_allclose(a / a[0], 1.0, atol=1e-6)  # along (1, 1, 1)
    assert float(relative_nonorthogonality_error(a, *res16.angles)) == pytest.approx(res16.value)
    assert max_relative_error(range_g=4).value == pytest.approx(res16.value, rel=1e-9)


def test_no_point_beats_the_maximum(problem1):
    rng = np.random.default_rng(5)
    ang = rng.uniform(0.98 * np.pi / 2, HI, size=(20000, 3))
    d = rng.normal(size=(20000, 3))
    a = d * (9.80665 / a_nonorth(d, ang[:, 0], ang[:, 1], ang[:, 2]))[:, None]
    err = nonorthogonality_error(a, ang[:, 0], ang[:, 1], ang[:, 2])
    assert err.max() <= problem1.value + 1e-12


def test_bad_box():
    with pytest.raises(CalibrationError):
        max_relative_error(nonorthogonality=0.0)
