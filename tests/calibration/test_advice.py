"""Which pose to add next (app.calibration.still.advice): D-optimal over a Fibonacci sphere."""

from __future__ import annotations

import numpy as np
import pytest

from app.calibration.still.advice import (
    MIN_SEPARATION_DEG,
    candidate_directions,
    describe_up,
    farthest_directions,
    fibonacci_sphere,
    next_poses,
)
from app.calibration.still.nonorthogonal import fit_nonorthogonal
from app.calibration.still.triangular import fit_triangular

G = 9.80665
# A phone's accelerometer: m = X a + y (X off the identity, y off zero), readings in m/s².
X_TRUE = np.array([[1.02, 0.01, -0.02], [0.005, 0.98, 0.015], [-0.01, 0.02, 1.01]])
Y_TRUE = np.array([0.15, -0.22, 0.31])
NOISE = 0.003  # m/s², a still pose's mean over a few seconds


def unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def readings(rng, ups) -> np.ndarray:
    """Still readings of the simulated phone with each of ``ups`` up."""
    ups = unit(ups)
    return (G * ups) @ X_TRUE.T + Y_TRUE + rng.normal(0.0, NOISE, (len(ups), 3))


def random_ups(rng, n) -> np.ndarray:
    return unit(rng.normal(size=(n, 3)))


def log_generalized_variance(result) -> float:
    """log det (JᵀJ)⁻¹ of a fit at its own solution: the D-criterion (σ² left out)."""
    J = result.jacobian(result.means)
    sign, logdet = np.linalg.slogdet(J.T @ J)
    assert sign > 0
    return -logdet


@pytest.mark.parametrize("fit", [fit_triangular, fit_nonorthogonal], ids=["triangular", "nonorthogonal"])
def test_poses_in_one_hemisphere_are_advised_the_other(fit):
    rng = np.random.default_rng(1)
    ups = random_ups(rng, 14)
    ups[:, 2] = np.abs(ups[:, 2]) + 0.15  # every pose with the screen more or less up
    result = fit(readings(rng, ups), gravity=G)
    assert not result.ok and "one hemisphere" in " ".join(result.reasons)
    advice = next_poses(result)
    assert len(advice) == 3
    assert advice[0].up[2] < 0, advice[0].words  # screen down, the half the poses never saw
    assert advice[0].gain > 0.5


def test_advised_pose_shrinks_the_generalized_variance_more_than_a_random_one():
    rng = np.random.default_rng(7)
    advised, random, wins = [], [], 0
    for _ in range(12):
        ups = random_ups(rng, 11)
        base = fit_triangular(readings(rng, ups), gravity=G)
        best = next_poses(base, count=1)[0]
        with_best = fit_triangular(np.vstack([base.means, readings(rng, best.up[None])]), gravity=G)
        with_random = fit_triangular(np.vstack([base.means, readings(rng, random_ups(rng, 1))]), gravity=G)
        before = log_generalized_variance(base)
        advised.append(before - log_generalized_variance(with_best))
        random.append(before - log_generalized_variance(with_random))
        wins += advised[-1] > random[-1]
    # Both shrink it; the advised pose by far more (log det, averaged over the scenarios).
    assert min(advised) > 0 and min(random) > 0
    assert np.mean(advised) > 2.0 * np.mean(random)
    assert wins >= 11


@pytest.mark.parametrize("fit", [fit_triangular, fit_nonorthogonal], ids=["triangular", "nonorthogonal"])
def test_gain_is_the_determinant_lemma_and_the_list_is_spread(fit):
    rng = np.random.default_rng(3)
    result = fit(readings(rng, random_ups(rng, 12)), gravity=G)
    advice = next_poses(result)
    assert len(advice) == 3
    J = result.jacobian(result.means)
    info = J.T @ J
    correction = result.correction
    for a in advice:
        # The reading the advised pose would give, and its row of the Jacobian: det shrinks by 1 − gain.
        m = np.linalg.solve(correction.M, G * a.up) + correction.o
        np.testing.assert_allclose(result.apply(m), G * a.up, atol=1e-9)
        j = result.jacobian(m[None])
        after = info + j.T @ j
        ratio = np.exp(np.linalg.slogdet(info)[1] - np.linalg.slogdet(after)[1])
        assert 1.0 - ratio == pytest.approx(a.gain, rel=1e-5)
        info = after  # the next advice assumes this pose was taken (Sherman–Morrison)
    gains = [a.gain for a in advice]
    assert gains == sorted(gains, reverse=True) and gains[-1] > 0
    ups = np.array([a.up for a in advice])
    taken = unit(result.apply(result.means))
    cos_min = np.cos(np.radians(MIN_SEPARATION_DEG))
    assert np.all(ups @ taken.T < cos_min)
    assert all(ups[i] @ ups[j] < cos_min for i in range(3) for j in range(i))


def test_nine_poses_without_covariance_still_get_advice():
    rng = np.random.default_rng(5)
    result = fit_triangular(readings(rng, random_ups(rng, 9)), gravity=G)
    assert result.covariance is None and result.dof == 0
    advice = next_poses(result)
    assert len(advice) == 3 and all(0 < a.gain < 1 for a in advice)


@pytest.mark.parametrize(
    "up, words",
    [
        ((0, 0, 1), "+z up (flat, screen up)"),
        ((0, 0, -1), "−z up (flat, screen down)"),
        ((0.02, 0.99, 0.03), "+y up (upright on its bottom edge (the charging port))"),
        (
            (np.cos(np.radians(30)), 0, -np.sin(np.radians(30))),
            "+x up (on its left edge as you face the screen, right edge up), tilted 30° towards −z",
        ),
        ((-0.2, -1.0, 0.03), "−y up (upside down on its top edge (the earpiece)), tilted 10° towards −x"),
        ((0.5, 0.5, -0.8), "−z up (flat, screen down), tilted 40° towards +x and +y"),
    ],
)
def test_words(up, words):
    assert describe_up(up) == words


def test_farthest_directions_before_a_fit():
    first = farthest_directions(np.zeros((0, 3)))
    assert [a.words.split(" up")[0] for a in first] == ["+x", "−x", "+y"] and first[0].gain is None
    taken = np.array([[0, 0, 9.8], [0.5, 0.1, 9.7], [9.8, 0, 0.2]])
    advice = farthest_directions(taken)
    assert advice[0].up @ unit(taken).mean(axis=0) < -0.5
    grid = fibonacci_sphere()
    assert grid.shape == (400, 3) and candidate_directions().shape == (406, 3)
    np.testing.assert_allclose(np.linalg.norm(grid, axis=1), 1.0)
    spacing = np.degrees(np.arccos(np.sort(grid @ grid.T, axis=1)[:, -2]))
    assert spacing.max() < 12
