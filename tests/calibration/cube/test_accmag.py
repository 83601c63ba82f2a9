"""Accelerometer and magnetometer GLS of Särkkä et al. (eqs. (6)-(8), (13), Appendix A, Tables VI-VII)."""

import numpy as np
import pytest
from scipy import stats

from app.calibration import CalibrationError, InsufficientDataError
from app.calibration.cube.accmag import (
    FieldSensorCalibration,
    decompose,
    decomposition_jacobian,
    expected_covariance,
    fit_field_sensor,
)
from app.calibration.cube.protocols import cube24
from simulations.cube import FIELD_UT, GRAVITY, TABLE_VI, simulate_position_means, true_parameters

REF = {"acc": GRAVITY, "mag": FIELD_UT}
# Factors from simulation raw units to the units of Table VII (µV/(m/s²) or V/T; mV).
TO_TABLE = {"acc": (1e6, 1e3), "mag": (1e6, 1e3)}


@pytest.mark.parametrize("sensor", ["acc", "mag"])
def test_table_vi_D_is_the_column_norm_of_S_within_the_table_rounding(sensor, table7):
    t = TABLE_VI[sensor]
    D = np.array(t["D"])
    S = D[:, None] * np.array(t["misalignment"])
    # Each element of D⁻¹S is rounded to 4 decimals: |ΔD_j| ≤ Σ_i D_i · 0.5e-4.
    assert np.all(np.abs(np.linalg.norm(S, axis=0) - D) <= 0.5e-4 * D.sum())
    # Table VII's means are the column norms of that S, to the printed digits.
    assert np.all(np.abs(np.linalg.norm(S, axis=0) - table7[sensor]["D"]) <= 0.5e-4 * D.sum() + 0.05)


def test_decomposition_jacobian_matches_finite_differences():
    S, _ = true_parameters("acc")
    JD, JM = decomposition_jacobian(S)
    eps = 1e-9
    for k in range(9):
        dS = np.zeros(9)
        dS[k] = eps
        D1, M1 = decompose(S + dS.reshape(3, 3))
        D0, M0 = decompose(S - dS.reshape(3, 3))
        np.testing.assert_allclose((D1 - D0) / (2 * eps), JD[:, k], atol=1e-5)
        np.testing.assert_allclose(((M1 - M0) / (2 * eps)).ravel(), JM[:, k], rtol=1e-5, atol=1e-3)


@pytest.mark.parametrize("sensor", ["acc", "mag"])
def test_table_vii_half_widths_are_reproduced_from_the_design(sensor, table7):
    """With per-axis noise variances chosen to give Table VII's bias half-widths (24 positions of
    5000 samples, α = 15°, β = 10°), the half-widths of D, α, β and the paper's D⁻¹S (error of D
    neglected, Appendix A) follow from eq. (22) and match the table to its printed digits."""
    S, b = true_parameters(sensor)
    kS, kb = TO_TABLE[sensor]
    n = 5000
    target = table7[sensor]["b_hw"] / kb
    var = (target / 1.96) ** 2 * 24 * n
    attitudes = cube24().attitudes
    for _ in range(20):  # b's half-width is nearly proportional to its own axis' noise
        cov = expected_covariance(S, b, 15, 10, attitudes, np.diag(var), n, reference=REF[sensor])
        var *= (target / (1.96 * np.sqrt(np.diag(cov)[9:12]))) ** 2
    hw = 1.96 * np.sqrt(np.diag(cov))
    np.testing.assert_allclose(hw[9:12] * kb, table7[sensor]["b_hw"], rtol=1e-6)
    JD, _ = decomposition_jacobian(S)
    hw_D = 1.96 * np.sqrt(np.diag(JD @ cov[:9, :9] @ JD.T)) * kS
    # Table VII prints two significant digits: the bias inputs carry up to ±5 % rounding and the
    # compared outputs up to ±3 %.
    np.testing.assert_allclose(hw_D, table7[sensor]["D_hw"], rtol=0.08)
    hw_M_paper = hw[:9].reshape(3, 3) / np.linalg.norm(S, axis=0)[:, None]
    for j, col in enumerate(("M1_hw", "M2_hw", "M3_hw")):
        np.testing.assert_allclose(hw_M_paper[:, j], table7[sensor][col], rtol=0.08)
    hw_angles = np.degrees(hw[12:])
    expected = {"acc": [0.0011, 0.0011], "mag": [8.2e-4, 8.1e-4]}[sensor]  # Särkkä et al. section VII-C
    np.testing.assert_allclose(hw_angles, expected, rtol=0.05)


def _study(sensor, runs, seed):
    rng = np.random.default_rng(seed)
    p = cube24()
    S, b = true_parameters(sensor)
    D, M = decompose(S)
    truth = np.r_[S.ravel(), b, 15.0, 10.0, D, M.ravel()]
    est, hws = [], []
    for _ in range(runs):
        m, c, n = simulate_position_means(rng, p, sensor=sensor)
        r = fit_field_sensor(m, c, n, p.attitudes, reference=REF[sensor], sensor=sensor)
        assert r.ok, r.reasons
        u = r.uncertainty()
        est.append(np.r_[r.S.ravel(), r.b, r.alpha_deg, r.beta_deg, r.D, r.misalignment.ravel()])
        hws.append(np.r_[np.ravel(u["S"]), u["b"], u["alpha_deg"], u["beta_deg"], u["D"], np.ravel(u["misalignment"])])
    return truth, np.array(est), np.array(hws)


@pytest.mark.parametrize("sensor,seed", [("acc", 3), ("mag", 4)])
def test_simulation_unbiased_and_intervals_cover_at_95_percent(sensor, seed):
    runs = 150
    truth, est, hws = _study(sensor, runs, seed)
    # Unbiased (Särkkä et al. section VII-C): every mean within 4 standard errors of the truth.
    z = (est.mean(axis=0) - truth) / (est.std(axis=0, ddof=1) / np.sqrt(runs))
    assert np.all(np.abs(z) < 4.0), z
    # α and β recovered (Table VII: 15.0000 and 10.0000).
    assert abs(est[:, 12].mean() - 15.0) < 2e-4 and abs(est[:, 13].mean() - 10.0) < 2e-4
    # The interval width is the spread of the estimates (a wrong 1/n would be off by √5000).
    ratio = hws.mean(axis=0) / (1.96 * est.std(axis=0, ddof=1))
    nonzero = truth != 0
    assert np.all((ratio > 0.75) & (ratio < 1.3)), ratio
    cover = (np.abs(est - truth) <= hws).mean(axis=0)
    lo = stats.binom.ppf(0.0005, runs, 0.95) / runs
    assert np.all(cover >= lo), cover
    pooled = (np.abs(est - truth) <= hws)[:, nonzero].mean()
    assert 0.93 <= pooled <= 0.97, pooled


def test_fit_recovers_exact_parameters_without_noise():
    p = cube24()
    S, b = true_parameters("mag")
    rng = np.random.default_rng(0)
    m, _c, n = simulate_position_means(rng, p, sensor="mag", noise_var=1e-30)
    r = fit_field_sensor(
        m, np.broadcast_to(np.eye(3) * 1e-8, (24, 3, 3)), n, p.attitudes, reference=FIELD_UT, sensor="mag"
    )
    np.testing.assert_allclose(r.S, S, rtol=1e-9)
    np.testing.assert_allclose(r.b, b, rtol=1e-9)
    assert abs(r.alpha_deg - 15) < 1e-7 and abs(r.beta_deg - 10) < 1e-7
    # Calibrated means are the field in the sensor frame, R_pᵀ C_l^c B (Särkkä et al. eq. (7)).
    from app.calibration.cube.accmag import reference_direction

    expected = np.einsum("pkj,k->pj", p.attitudes, reference_direction(np.radians(15), np.radians(10)) * FIELD_UT)
    np.testing.assert_allclose(r.apply(m), expected, atol=1e-6)
    back = FieldSensorCalibration.from_dict(r.to_dict())
    np.testing.assert_allclose(back.S, r.S)
    assert back.uncertainty() == r.uncertainty()


def test_mislabelled_position_fails_the_fit_and_names_it():
    p = cube24()
    rng = np.random.default_rng(5)
    m, c, n = simulate_position_means(rng, p, sensor="acc")
    att = p.attitudes.copy()
    att[[6, 10]] = att[[10, 6]]  # positions 7 and 11 swapped
    r = fit_field_sensor(m, c, n, att, reference=GRAVITY)
    assert not r.ok
    assert "position" in r.reasons[0]


def test_too_few_positions_and_bad_input():
    p = cube24()
    m, c, n = simulate_position_means(np.random.default_rng(1), p, sensor="acc")
    with pytest.raises(InsufficientDataError, match="positions"):
        fit_field_sensor(m[:4], c[:4], n[:4], p.attitudes[:4], reference=GRAVITY)
    with pytest.raises(CalibrationError):
        fit_field_sensor(m, c[:3], n, p.attitudes, reference=GRAVITY)
    with pytest.raises(CalibrationError):
        fit_field_sensor(m, c, n, p.attitudes, reference=-1.0)
    with pytest.raises(InsufficientDataError):
        # Only the four +z positions: the model is not determined.
        fit_field_sensor(
            np.tile(m[:4], (2, 1)),
            np.tile(c[:4], (2, 1, 1)),
            np.tile(n[:4], 2),
            np.tile(p.attitudes[:4], (2, 1, 1)),
            reference=GRAVITY,
        )


def test_eq8_matrix_is_the_product_of_the_two_inclinations_and_dof_is_72_minus_14():
    from app.calibration.cube.accmag import direction_matrix, reference_direction

    a, b = np.radians(15.0), np.radians(10.0)
    Rx = np.array([[1, 0, 0], [0, np.cos(a), np.sin(a)], [0, -np.sin(a), np.cos(a)]])
    Ry = np.array([[np.cos(b), 0, -np.sin(b)], [0, 1, 0], [np.sin(b), 0, np.cos(b)]])
    np.testing.assert_allclose(direction_matrix(a, b), Rx @ Ry, atol=1e-15)  # Särkkä et al. eq. (8)
    np.testing.assert_allclose(reference_direction(a, b), (Rx @ Ry)[:, 2], atol=1e-15)
    np.testing.assert_allclose(direction_matrix(0.0, 0.0), np.eye(3))
    p = cube24()
    m, c, n = simulate_position_means(np.random.default_rng(8), p, sensor="acc")
    r = fit_field_sensor(m, c, n, p.attitudes, reference=GRAVITY)
    assert r.metrics["dof"] == 3 * 24 - 14  # Särkkä et al. section III-C: 72 equations, 14 unknowns
    assert r.metrics["iterations"] < 8  # section VII-A: converged in less than 8 iterations
