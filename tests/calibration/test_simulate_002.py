"""Farago et al. (IEEE Access) section III.A: the simulation generator and the Cramér–Rao bound."""

import numpy as np
import pytest

from app.calibration.shared.errors import CalibrationError
from app.calibration.still.triangular import fit_triangular
from simulations.triangular import (
    bin_indices,
    cramer_rao_bound,
    draw_parameters,
    k_matrix,
    random_unit_vectors,
    select_points,
    simulate_scenario,
    uncalibrate,
)


def test_parameters_follow_eqs_17_18():
    rng = np.random.default_rng(0)
    P = np.array([draw_parameters(rng) for _ in range(2000)])
    assert np.all((P[:, :3] > 0.9) & (P[:, :3] < 1.1))
    T = P[:, 3:6] / P[:, [1, 2, 2]]  # k_xy = S_y T_xy, k_xz = S_z T_xz, k_yz = S_z T_yz
    assert np.all(np.abs(T) < 0.05) and np.abs(T).max() > 0.049
    assert np.all(np.abs(P[:, 6:]) < 0.1)
    np.testing.assert_allclose(P.mean(axis=0), [1, 1, 1, 0, 0, 0, 0, 0, 0], atol=0.01)
    again = draw_parameters(np.random.default_rng(0))
    np.testing.assert_array_equal(again, P[0])


def test_uncalibrate_inverts_the_model():
    rng = np.random.default_rng(1)
    p = draw_parameters(rng)
    a = random_unit_vectors(rng, 50)
    c = uncalibrate(p, a)
    np.testing.assert_allclose((c + p[6:]) @ k_matrix(p).T, a, atol=1e-14)


def test_selection_two_per_bin():
    sc = simulate_scenario(np.random.default_rng(2), noise_g=0.001)
    assert sc.points.shape == (18, 3)
    bins = bin_indices(sc.points)
    counts = np.zeros((3, 3), int)
    for row in bins:  # each point counted in the first bin it fills (module docstring)
        for axis in range(3):
            if row[axis] >= 0 and counts[axis, row[axis]] < 2:
                counts[axis, row[axis]] += 1
                break
    assert np.all(counts == 2)
    np.testing.assert_allclose(np.linalg.norm((sc.points + sc.p[6:]) @ k_matrix(sc.p).T, axis=1), 1.0, atol=0.01)
    # A seed fixes the scenario.
    sc2 = simulate_scenario(np.random.default_rng(2), noise_g=0.001)
    np.testing.assert_array_equal(sc.points, sc2.points)
    assert len(select_points(np.full((5, 3), 0.5))) == 0  # 0.5 g lies in no interval of eq. (10)


def test_crb_matches_the_projected_normal_form():
    """Eliminating the directions equals weighting the radial residual by its gradient."""
    sc = simulate_scenario(np.random.default_rng(3), noise_g=0.002)
    crb = cramer_rao_bound(sc.p, sc.directions, 0.002)
    K = k_matrix(sc.p)
    rows = []
    for a in sc.directions:
        c = uncalibrate(sc.p, a[None, :])[0]

        def f(q):
            return np.linalg.norm((c + q[6:]) @ k_matrix(q).T)  # noqa: B023 - called within this iteration

        grad_p = np.array([(f(sc.p + 1e-7 * e) - f(sc.p - 1e-7 * e)) / 2e-7 for e in np.eye(9)])
        grad_v = K.T @ a  # ∇ᵥ|K(v + o)| at |a| = 1
        rows.append(grad_p / np.linalg.norm(grad_v))
    J = np.array(rows)
    np.testing.assert_allclose(crb, np.linalg.inv(J.T @ J) * 0.002**2, rtol=1e-5)
    np.testing.assert_allclose(cramer_rao_bound(sc.p, sc.directions, 0.004), 4 * crb, rtol=1e-12)
    with pytest.raises(CalibrationError):
        cramer_rao_bound(sc.p, sc.directions, 0.0)


@pytest.mark.parametrize("noise_g", [0.001, 0.005])
def test_lm_reaches_the_cramer_rao_bound(noise_g):
    """RMS error of each parameter over 800 seeded scenarios within 10 % of sqrt(mean CRB).

    The CRB varies from scenario to scenario (heavy tail), so the Table-2 style ratio
    RMS / sqrt(mean CRB) spreads more than 1/sqrt(2N): with 400 scenarios single ratios were seen
    between 0.88 and 1.10 by chance; with 2000 scenarios all 18 lie within 0.96–1.04 (bench/sim_002.py).
    800 scenarios keep the spread near 2.5 %.  The per-scenario normalised error
    sqrt(mean(err² / CRB)) is checked too (it is not affected by the heavy tail).
    """
    rng = np.random.default_rng(2026 if noise_g == 0.001 else 2027)
    err, crb = [], []
    for _ in range(800):
        sc = simulate_scenario(rng, noise_g=noise_g)
        crb.append(np.diag(cramer_rao_bound(sc.p, sc.directions, noise_g)))
        err.append(fit_triangular(sc.points, gravity=1.0).p - sc.p)
    err, crb = np.array(err), np.array(crb)
    ratio = np.sqrt(np.mean(err**2, axis=0) / np.mean(crb, axis=0))
    assert np.all(np.abs(ratio - 1) <= 0.10), ratio
    z = np.sqrt(np.mean(err**2 / crb, axis=0))
    assert np.all(np.abs(z - 1) <= 0.10), z
