"""Georgieva et al. (ESGI'95), Approach 1: non-orthogonal axes model, fit of section 2.2, section 2.4."""

from pathlib import Path

import numpy as np
import pytest

from app.calibration.shared.errors import CalibrationError, InsufficientDataError
from app.calibration.still.nonorthogonal import (
    NonOrthogonalCalibration,
    affine_matrix,
    calibration_matrix,
    fit_nonorthogonal,
    gram_matrix,
    orthonormal_matrix,
)

DATA = Path(__file__).resolve().parents[1] / "data"

# Georgieva et al. section 2.4: the paper's scales are recovered with g = 9.806 (see test_paper_gravity_is_9_806).
G_PAPER = 9.806


def table(k: int) -> np.ndarray:
    return np.loadtxt(DATA / f"000_table{k}.csv", delimiter=",", skiprows=2)[:, 1:]


# (dataset, first position, last position) → s1..s3, b1..b3 (printed negative), φ, ψ, θ.
PRINTED = {
    (1, 1, 20): ([0.304496, 0.321482, -1.08995], [-1.00457, -1.00147, -0.989292], [1.57646, 1.57096, 1.57301]),
    (1, 3, 23): ([0.318321, 0.322794, -1.09059], [-1.00472, -1.00124, -0.989255], [1.56932, 1.5709, 1.57296]),
    (2, 1, 20): ([-0.469784, 0.608425, 0.208206], [-0.999573, -0.989443, -1.01176], [1.56219, 1.56969, 1.57057]),
    (2, 3, 23): ([-0.466405, 0.616422, 0.207149], [-0.999212, -0.989644, -1.01181], [1.55782, 1.56827, 1.57215]),
}


@pytest.mark.parametrize("key", sorted(PRINTED))
def test_section_2_4_parameters(key):
    k, first, last = key
    s, b, angles = PRINTED[key]
    cal = fit_nonorthogonal(table(k)[first - 1 : last], gravity=G_PAPER)
    np.testing.assert_allclose(cal.s, s, atol=2e-4)
    # The paper prints b < 0; flipping all three signs leaves (17) and the angles unchanged and
    # trical keeps b > 0 (module docstring), so the magnitudes are compared.
    np.testing.assert_allclose(cal.b, np.abs(b), atol=2e-4)
    np.testing.assert_allclose([cal.phi, cal.psi, cal.theta], angles, atol=1e-4)
    assert cal.ok, cal.reasons
    assert cal.metrics["converged"]


def test_paper_gravity_is_9_806():
    """The printed scales fit g = 9.806 within 2e-5; with 9.80665 or 9.81 they are off by > 5e-5."""
    m = table(1)[:20]
    printed = np.abs(PRINTED[(1, 1, 20)][1])
    dev = {g: np.abs(fit_nonorthogonal(m, gravity=g).b - printed).max() for g in (9.806, 9.80665, 9.81)}
    assert dev[9.806] < 2e-5
    assert dev[9.80665] > 5e-5 and dev[9.81] > 3e-4


def test_dataset_3_max_relative_error_and_near_duplicate():
    """Georgieva et al. section 2.4, Dataset 3: 0.26 % (positions 1–20) and 0.98 % (3–23) over all positions.

    The paper's figures are the maxima 0.2694 % and 0.9888 % cut (not rounded) to two decimals;
    they do not depend on g (the scales absorb it).
    """
    m = table(3)
    cal1 = fit_nonorthogonal(m[0:20], gravity=G_PAPER)
    cal2 = fit_nonorthogonal(m[2:23], gravity=G_PAPER)
    e1 = 100 * cal1.evaluate(m)["norm_error_max"]
    e2 = 100 * cal2.evaluate(m)["norm_error_max"]
    assert np.floor(100 * e1) / 100 == pytest.approx(0.26)
    assert np.floor(100 * e2) / 100 == pytest.approx(0.98)
    assert e1 == pytest.approx(0.2694, abs=1e-4)
    assert e2 == pytest.approx(0.9888, abs=1e-4)
    assert not any("near-duplicate" in w for w in cal1.warnings)
    # Positions 3 and 21 of Table 3 are readings 0 and 18 of the subset 3–23.
    dup = [w for w in cal2.warnings if "near-duplicate" in w]
    assert len(dup) == 1 and "readings 0 and 18" in dup[0]
    e_same_g = 100 * fit_nonorthogonal(m[2:23], gravity=9.80665).evaluate(m)["norm_error_max"]
    assert e_same_g == pytest.approx(e2, abs=1e-6)


def test_dataset_1_and_2_error_figures():
    """Recomputed error figures of Georgieva et al. section 2.4 for Datasets 1 and 2.

    The paper says "less than 0.21 %" (Dataset 1) and "below 0.45 %" (Dataset 2).  That holds over
    the fitted positions (0.197 %, 0.170 %; 0.296 %, 0.236 %), not over all 27/29 positions, where
    the held-out position 27 reaches 0.320 % (Dataset 1, 1–20) and 0.482 % (Dataset 2, 1–20).
    """
    fitted, every = [], []
    for k in (1, 2):
        m = table(k)
        for sl in (slice(0, 20), slice(2, 23)):
            cal = fit_nonorthogonal(m[sl], gravity=G_PAPER)
            fitted.append(100 * cal.metrics["norm_error_max"])
            every.append(100 * cal.evaluate(m)["norm_error_max"])
    np.testing.assert_allclose(fitted, [0.1968, 0.1700, 0.2959, 0.2357], atol=1e-3)
    np.testing.assert_allclose(every, [0.3200, 0.2173, 0.4817, 0.4108], atol=1e-3)
    assert max(fitted[:2]) < 0.21 and max(fitted[2:]) < 0.45


def test_matrices_are_the_papers():
    phi, psi, theta = 1.55, 1.6, 1.58
    G = gram_matrix(phi, psi, theta)
    np.testing.assert_allclose(affine_matrix(phi, psi, theta), np.linalg.inv(G), atol=1e-12)  # eq. (5) solves (8)
    E = orthonormal_matrix(phi, psi, theta)
    np.testing.assert_allclose(E.T @ E, G, atol=1e-12)  # columns are unit axes with the angles
    np.testing.assert_allclose(np.linalg.norm(E, axis=0), 1.0)


def _synthetic(rng, n=20, noise=0.0):
    s = np.array([0.2, -0.15, 0.3])
    b = np.array([1.02, 0.97, 1.01])
    angles = np.array([1.58, 1.56, 1.575])
    g = 9.80665
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    M = calibration_matrix(b, *angles)
    raw = s + np.linalg.solve(M, (g * d).T).T + noise * rng.normal(size=(n, 3))
    return raw, s, b, angles, g


def test_recovers_synthetic_parameters_and_apply_is_eq_16():
    rng = np.random.default_rng(3)
    raw, s, b, angles, g = _synthetic(rng)
    cal = fit_nonorthogonal(raw, gravity=g)
    np.testing.assert_allclose(cal.s, s, atol=1e-8)
    np.testing.assert_allclose(cal.b, b, atol=1e-9)
    np.testing.assert_allclose([cal.phi, cal.psi, cal.theta], angles, atol=1e-9)
    out = cal.apply(raw)
    np.testing.assert_allclose(np.linalg.norm(out, axis=1), g, rtol=1e-10)
    # eq. (16) written out term by term
    T = np.diag(1 / cal.b)
    Tb, To = affine_matrix(*angles), orthonormal_matrix(*angles)
    np.testing.assert_allclose(out[0], To @ Tb @ T @ raw[0] - To @ Tb @ (cal.s / cal.b), atol=1e-10)
    assert cal.apply(raw[0]).shape == (3,)
    assert cal.metrics["norm_error_max"] < 1e-10


def test_intervals_cover_truth():
    rng = np.random.default_rng(11)
    hits, total = 0, 0
    for _ in range(40):
        raw, s, b, angles, g = _synthetic(rng, n=20, noise=0.02)
        cal = fit_nonorthogonal(raw, gravity=g)
        u = cal.uncertainty()
        hw = np.r_[u["s"], u["b"], u["phi"], u["psi"], u["theta"]]
        hits += int(np.sum(np.abs(cal.params - np.r_[s, b, angles]) <= hw))
        total += 9
    assert 0.88 <= hits / total <= 0.99


def test_dict_round_trip():
    cal = fit_nonorthogonal(table(1)[:20], gravity=G_PAPER)
    d = cal.to_dict()
    assert d["model"]["type"] == "nonorthogonal"
    assert set(d["model"]) == {"type", "s", "b", "phi", "psi", "theta"}
    assert len(d["uncertainty"]["s"]) == 3 and isinstance(d["uncertainty"]["phi"], float)
    back = NonOrthogonalCalibration.from_dict(d)
    np.testing.assert_allclose(back.apply(table(1)), cal.apply(table(1)))
    assert back.dof == cal.dof == 11
    np.testing.assert_allclose(back.uncertainty()["b"], cal.uncertainty()["b"])


def test_fewer_than_nine_positions():
    with pytest.raises(InsufficientDataError, match="at least 9"):
        fit_nonorthogonal(table(1)[:8], gravity=G_PAPER)


def test_nan_is_rejected():
    m = table(1)[:20].copy()
    m[4, 1] = np.nan
    with pytest.raises(CalibrationError, match="row 4"):
        fit_nonorthogonal(m, gravity=G_PAPER)


def test_identical_positions_are_rejected():
    m = np.tile(table(1)[0], (20, 1)) + 1e-4 * np.arange(60).reshape(20, 3)
    with pytest.raises(InsufficientDataError, match="distinct"):
        fit_nonorthogonal(m, gravity=G_PAPER)


def test_one_hemisphere_is_not_ok():
    m = table(1)
    upper = m[m[:, 2] > 0.5]
    upper = np.vstack([upper, upper[:4] + [0.5, -0.5, 0.0]])
    assert len(upper) >= 9
    cal = fit_nonorthogonal(upper, gravity=G_PAPER)
    assert not cal.ok
    assert any("one hemisphere" in r for r in cal.reasons)


def test_readings_in_g():
    m = table(2)[:20]
    si = fit_nonorthogonal(m, gravity=G_PAPER)
    in_g = fit_nonorthogonal(m / G_PAPER, gravity=1.0)
    np.testing.assert_allclose(in_g.s * G_PAPER, si.s, atol=1e-7)
    np.testing.assert_allclose(in_g.b, si.b, atol=1e-8)
    np.testing.assert_allclose([in_g.phi, in_g.psi, in_g.theta], [si.phi, si.psi, si.theta], atol=1e-8)
