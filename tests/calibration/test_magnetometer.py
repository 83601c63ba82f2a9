"""The compass calibration (app.calibration.magnetometer) on seeded simulated turns with a known truth."""

import numpy as np
import pytest

from app.calibration.magnetometer import MagnetometerResult, fit_magnetometer
from app.calibration.magnetometer.ellipsoid import fit_ellipsoid, fit_sphere
from app.calibration.magnetometer.refine import correlation_inflation, pack
from app.calibration.shared.errors import CalibrationError, InsufficientDataError
from app.calibration.shared.result import CalibrationResult
from simulations.magnetometer import EARTH_FIELD_UT, random_soft_iron, simulate_rests, simulate_session, simulate_turn

F = EARTH_FIELD_UT


def test_closed_forms_are_exact_without_noise():
    m, M, b = simulate_session(3, noise_ut=0.0, n=200)
    M_e, b_e = fit_ellipsoid(m, F)
    np.testing.assert_allclose(M_e, M, atol=1e-9)
    np.testing.assert_allclose(b_e, b, atol=1e-7)
    sphere = simulate_turn(np.random.default_rng(4), np.eye(3) * 1.1, [300.0, -20.0, 5.0], noise_ut=0.0, n=100)
    M_s, b_s = fit_sphere(sphere, F)
    np.testing.assert_allclose(b_s, [300.0, -20.0, 5.0], atol=1e-8)
    np.testing.assert_allclose(M_s, 1.1 * np.eye(3), atol=1e-10)


def test_the_fit_recovers_a_phone_s_hard_and_soft_iron():
    m, M, b = simulate_session(1, n=400, noise_ut=0.3, hard_iron_ut=300.0)
    r = fit_magnetometer(m, field_ut=F, field_source="model")
    assert r.ok, r.reasons
    np.testing.assert_allclose(r.b, b, atol=0.15)
    np.testing.assert_allclose(r.M, M, atol=0.006)
    np.testing.assert_allclose(r.M, r.M.T)
    assert r.metrics["field_source"] == "model" and r.metrics["coverage"] == 1.0
    assert r.metrics["noise_ut"] == pytest.approx(0.3, rel=0.1)
    # on directions left out the error is the noise, a little above the in-sample figure
    assert r.metrics["fit_error_ut"] < r.metrics["cv_error_ut"] < 0.36
    assert r.metrics["raw_error_ut"] > 100.0 and r.metrics["norm_spread_ut"] < 1.2


def test_the_95_percent_intervals_hold_the_truth_95_percent_of_the_time():
    hits = []
    for seed in range(500):
        m, M, b = simulate_session(1000 + seed, n=200)
        r = fit_magnetometer(m, field_ut=F, field_source="model")
        u = r.uncertainty()
        half = pack(np.array(u["M"]), np.array(u["b"]))
        hits.append(np.abs(pack(r.M, r.b) - pack(M, b)) <= half)
    hits = np.array(hits)
    assert 0.94 <= hits.mean() <= 0.965, hits.mean()
    assert np.all((hits.mean(axis=0) >= 0.92) & (hits.mean(axis=0) <= 0.98)), hits.mean(axis=0)


def test_a_turn_that_misses_directions_is_refused_with_them_named():
    m, _, _ = simulate_session(8, n=400, max_polar_deg=90.0)  # screen up only: a hemisphere
    r = fit_magnetometer(m, field_ut=F)
    assert not r.ok
    assert r.metrics["coverage"] < 0.75 and len(r.metrics["missing_directions"]) >= 5
    reason = r.reasons[0]
    assert "covered" in reason and all(face in reason for face in r.metrics["missing_directions"])
    full = fit_magnetometer(simulate_session(8, n=400)[0], field_ut=F)
    assert full.ok and full.metrics["missing_directions"] == []


def test_a_field_that_changes_during_the_turn_is_named():
    rng = np.random.default_rng(9)
    M, b = random_soft_iron(rng), np.array([20.0, -35.0, 10.0])
    first = simulate_turn(rng, M, b, field_ut=F, n=300)
    near_steel = simulate_turn(rng, M, b, field_ut=1.3 * F, n=300)  # the second half beside a steel desk
    r = fit_magnetometer(np.vstack([first, near_steel]), field_ut=F)
    assert not r.ok and any("field changed" in x for x in r.reasons)


def test_an_already_calibrated_sensor_is_not_made_worse():
    m = simulate_turn(np.random.default_rng(10), np.eye(3), np.zeros(3), field_ut=F, n=400, noise_ut=0.3)
    r = fit_magnetometer(m, field_ut=F)
    assert r.metrics["cv_error_ut"] >= r.metrics["raw_error_ut"]
    assert not r.ok and any("would not help" in x for x in r.reasons)


def test_without_a_field_the_magnitude_is_estimated_and_said():
    m, M, b = simulate_session(11, n=400, noise_ut=0.1)
    r = fit_magnetometer(m)
    scale = np.linalg.det(M) ** (-1.0 / 3.0)  # M's scale is fixed by det M = 1
    assert np.linalg.det(r.M) == pytest.approx(1.0, abs=1e-6)
    np.testing.assert_allclose(r.M, scale * M, atol=0.003)
    np.testing.assert_allclose(r.b, b, atol=0.08)
    assert r.metrics["field_ut"] == pytest.approx(scale * F, rel=1e-3)
    assert r.metrics["field_source"] == "estimated" and any("estimated" in w for w in r.warnings)


def test_the_dip_against_gravity_checks_the_model_s_inclination():
    rng = np.random.default_rng(12)
    m, M, b = simulate_session(12, n=400)
    rests = simulate_rests(rng, M, b, inclination_deg=64.0, n=6)
    r = fit_magnetometer(m, field_ut=F, field_source="model", inclination_deg=64.0, rests=rests)
    assert r.ok, r.reasons
    assert r.metrics["measured_inclination_deg"] == pytest.approx(64.0, abs=0.5) and r.metrics["rests"] == 6
    disturbed = fit_magnetometer(m, field_ut=F, inclination_deg=52.0, rests=rests)  # a field 12° off the model's
    assert not disturbed.ok and any("disturbed field" in x for x in disturbed.reasons)


def test_too_little_or_bad_input_says_what_to_do():
    m, _, _ = simulate_session(13, n=49)
    with pytest.raises(InsufficientDataError, match="at least 50"):
        fit_magnetometer(m, field_ut=F)
    with pytest.raises(InsufficientDataError, match="do not change"):
        fit_magnetometer(np.ones((60, 3)), field_ut=F)
    bad = simulate_session(13, n=60)[0]
    bad[5, 1] = np.nan
    with pytest.raises(CalibrationError, match="NaN"):
        fit_magnetometer(bad, field_ut=F)
    with pytest.raises(CalibrationError, match="N×3"):
        fit_magnetometer(np.zeros((60, 2)), field_ut=F)


def test_correlated_residuals_widen_the_intervals():
    assert correlation_inflation(np.random.default_rng(1).normal(size=5000)) == pytest.approx(1.0, abs=0.06)
    walk = np.convolve(np.random.default_rng(2).normal(size=5000), np.ones(20), mode="same")
    assert correlation_inflation(walk) > 20.0


def test_the_result_round_trips_and_applies():
    m, _M, _b = simulate_session(14, n=300)
    r = fit_magnetometer(m, field_ut=F)
    again = CalibrationResult.from_dict(r.to_dict())
    assert isinstance(again, MagnetometerResult)
    np.testing.assert_array_equal(again.M, r.M)
    np.testing.assert_array_equal(again.b, r.b)
    assert again.uncertainty() == r.uncertainty() and again.to_dict() == r.to_dict()
    h = r.corrections()["mag"].apply(m)
    np.testing.assert_allclose(np.linalg.norm(h, axis=1).mean(), F, rtol=2e-3)
    np.testing.assert_allclose(r.apply(m[0]), r.M @ (m[0] - r.b))
    assert r.to_dict()["model"]["type"] == "magnetometer" and len(r.to_dict()["samples"]["raw_ut"]) == 300
