"""Gyroscope of Särkkä et al. (eqs. (4)-(5), (9)-(11), Appendix B) on simulated rotations (section V-A)."""

import numpy as np
import pytest
from scipy import stats

from app.calibration import CalibrationError, InsufficientDataError
from app.calibration.cube import quaternion as quat
from app.calibration.cube.accmag import decompose
from app.calibration.cube.gyro import GyroCalibration, fit_gyroscope
from simulations.cube import simulate_session, true_parameters


def _rotations(session, pad_s=0.2):
    fs = session.sampling_rate_hz
    pad = int(pad_s * fs)
    segs = session.static_segments
    p = session.protocol
    rots = [session.gyr[segs[k][1] - pad : segs[k + 1][0] + pad] for k in range(p.n_positions - 1)]
    still = np.vstack([session.gyr[a:b] for a, b in segs])
    return rots, p.quaternions[:-1], p.quaternions[1:], still


def test_quaternion_helpers_agree():
    rng = np.random.default_rng(0)
    q = rng.normal(size=(5, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w = rng.normal(size=(5, 3))
    # W(ω) q = Ξ(q) ω = q ⊗ [0, ω]  (Särkkä et al. eq. (2))
    np.testing.assert_allclose(quat.omega_matrix(w) @ q[:, :, None], quat.xi_matrix(q) @ w[:, :, None])
    np.testing.assert_allclose(
        (quat.omega_matrix(w) @ q[:, :, None])[:, :, 0], quat.multiply(q, np.c_[np.zeros(5), w]), atol=1e-12
    )
    for qq in q:
        R = quat.to_matrix(qq)
        np.testing.assert_allclose(abs(quat.from_matrix(R) @ qq), 1.0, atol=1e-12)
    # A constant rate of 2π over 1 s ends on the negative branch: 360° is not 0°.
    end = quat.integrate(np.tile([0.0, 0.0, 2 * np.pi], (1001, 1)), 1e-3, [1, 0, 0, 0])[-1]
    np.testing.assert_allclose(end, [-1, 0, 0, 0], atol=1e-9)


def test_noise_free_rotations_recover_the_parameters_at_1_khz():
    s = simulate_session(
        np.random.default_rng(1), sampling_rate_hz=1000.0, with_mag=False, noise_var={"gyr": 1e-16, "acc": 1e-16}
    )
    rots, qs, qe, still = _rotations(s)
    g = fit_gyroscope(rots, qs, qe, sampling_rate_hz=1000.0, noise_cov=np.eye(3) * 1e-16, bias0=still.mean(0))
    S, b = true_parameters("gyr")
    # Only the trapezoidal rule's O(h²) error remains.
    np.testing.assert_allclose(g.S, S, atol=2e-6)
    np.testing.assert_allclose(g.b, b, atol=1e-7)
    assert g.ok and g.metrics["max_end_error_deg"] < 1e-3
    D, _M = decompose(S)
    np.testing.assert_allclose(g.D, D, atol=2e-6)  # Table VI diag(D_ω) 0.9581, 0.9539, 0.9765
    np.testing.assert_allclose(g.D, [0.9581, 0.9539, 0.9765], atol=2e-4)
    back = GyroCalibration.from_dict(g.to_dict())
    np.testing.assert_allclose(back.S_inv, g.S_inv)
    assert back.uncertainty() == g.uncertainty()


def test_lambda_saturation_rule_and_fixed_lambda_agree():
    s = simulate_session(np.random.default_rng(2), sampling_rate_hz=50.0, with_mag=False)
    rots, qs, qe, still = _rotations(s)
    auto = fit_gyroscope(rots, qs, qe, sampling_rate_hz=50.0, noise_cov=np.cov(still.T), bias0=still.mean(0))
    path = auto.metrics["lambda_path"]
    assert path[-1]["max_change"] < 1e-7  # saturated (Särkkä et al. section IV-A-1)
    fixed = fit_gyroscope(rots, qs, qe, sampling_rate_hz=50.0, noise_cov=np.cov(still.T), bias0=still.mean(0), lam=1e4)
    np.testing.assert_allclose(auto.S_inv, fixed.S_inv, atol=1e-6)
    np.testing.assert_allclose(auto.b, fixed.b, atol=1e-6)


def test_simulation_unbiased_and_appendix_b_intervals_cover_at_95_percent():
    runs = 100
    rng = np.random.default_rng(3)
    S, b = true_parameters("gyr")
    truth = np.r_[S.ravel(), b]
    est, hws = [], []
    for _ in range(runs):
        s = simulate_session(rng, sampling_rate_hz=40.0, with_mag=False)
        rots, qs, qe, still = _rotations(s)
        g = fit_gyroscope(rots, qs, qe, sampling_rate_hz=40.0, noise_cov=np.cov(still.T), bias0=still.mean(0), lam=1.0)
        u = g.uncertainty()
        est.append(np.r_[g.S.ravel(), g.b])
        hws.append(np.r_[np.ravel(u["S"]), u["b"]])
    est, hws = np.array(est), np.array(hws)
    z = (est.mean(0) - truth) / (est.std(0, ddof=1) / np.sqrt(runs))
    assert np.all(np.abs(z) < 4.0), z
    ratio = hws.mean(0) / (1.96 * est.std(0, ddof=1))
    assert np.all((ratio > 0.75) & (ratio < 1.3)), ratio
    cover = (np.abs(est - truth) <= hws).mean(0)
    assert np.all(cover >= stats.binom.ppf(0.0005, runs, 0.95) / runs), cover
    assert 0.93 <= cover.mean() <= 0.97, cover.mean()


def test_gyroscope_input_errors():
    rot = np.zeros((10, 3))
    q = np.array([[1.0, 0, 0, 0]])
    with pytest.raises(InsufficientDataError, match="rotations"):
        fit_gyroscope([rot, rot], np.tile(q, (2, 1)), np.tile(q, (2, 1)), sampling_rate_hz=100, noise_cov=np.eye(3))
    with pytest.raises(CalibrationError, match="N×3"):
        fit_gyroscope(
            [rot[:, :2]] * 4, np.tile(q, (4, 1)), np.tile(q, (4, 1)), sampling_rate_hz=100, noise_cov=np.eye(3)
        )
