"""Temperature calibration (app.calibration.temperature) on seeded warm-ups with a known cubic offset,
the noise of a real still MPU-6050 and a flight controller's jittered sample times."""

from __future__ import annotations

import numpy as np
import pytest

from app.calibration.shared.errors import CalibrationError
from app.calibration.shared.result import CalibrationResult
from app.calibration.temperature import TemperatureResult, calibrate_temperature, offset_at, shift_polynomial
from simulations.temperature import ACC_TRUTH, GYR_TRUTH, T_POLY_REF_C, simulate_warm_up
from tests.temperature_logs import real_still_noise, warm_up


def truth_about(model: dict, sensor: str) -> np.ndarray:
    c = shift_polynomial(ACC_TRUTH if sensor == "acc" else GYR_TRUTH, T_POLY_REF_C, model["t_ref_c"])
    if model["relative"]:
        c[:, 0] = 0.0
    return c


def test_a_known_cubic_is_recovered_within_its_intervals_and_the_drift_falls():
    w = warm_up(7, duration_s=1800, sampling_rate_hz=50)
    r = calibrate_temperature(w.temperature_c, acc=w.acc, gyr=w.gyr, sampling_rate_hz=50, time_s=w.time_s, order=3)
    assert r.ok, r.reasons
    for sensor in ("acc", "gyr"):
        model, unc = r.sensors[sensor]["model"], r.sensors[sensor]["uncertainty"]
        err = np.abs(np.asarray(model["coefficients"]) - truth_about(model, sensor))
        half = np.asarray(unc["coefficients"])
        fitted = half > 0
        assert np.all(err[fitted] < 1.5 * half[fitted]), (sensor, err / np.where(fitted, half, 1))
        m = r.sensors[sensor]["metrics"]
        assert m["n_samples"] == len(w.time_s)
        assert 0.999 * m["n_samples"] <= sum(m["samples_per_band"]) <= m["n_samples"]  # bins of < 5 left out
        assert max(m["drift_cv"]) < 0.2 * max(m["drift_raw"])
    # The accelerometer's drift over 15–55 °C is 14 mg on z; after, about the bins' noise.
    acc = r.sensors["acc"]["metrics"]
    assert acc["unit"] == "mg" and 13 < acc["drift_raw"][2] < 16 and acc["drift_cv_max"] < 1.5
    assert r.sensors["acc"]["model"]["coefficients"][0][0] == 0.0  # relative to T_ref
    gyr = r.sensors["gyr"]["model"]
    assert gyr["t_ref_c"] == pytest.approx(0.5 * (gyr["t_min_c"] + gyr["t_max_c"]))


def test_the_order_is_chosen_on_bands_left_out():
    truth = np.zeros((3, 4))
    truth[:, 1] = [2e-3, -1e-3, 3e-3]  # straight lines
    w = simulate_warm_up(np.random.default_rng(3), noise=real_still_noise(), acc_truth=truth, duration_s=1800)
    r = calibrate_temperature(w.temperature_c, acc=w.acc, sampling_rate_hz=50)
    assert r.ok
    assert r.sensors["acc"]["model"]["order"] == [1, 1, 1]
    w = warm_up(3, duration_s=1800)
    r = calibrate_temperature(w.temperature_c, acc=w.acc, gyr=w.gyr, sampling_rate_hz=50, time_s=w.time_s)
    for sensor in ("acc",):  # curved by 1.2–2.4 mg on every axis: a straight line loses on the bands left out
        m = r.sensors[sensor]
        assert all(order >= 2 for order in m["model"]["order"]), m["model"]["order"]
        by_order = np.asarray(m["metrics"]["cv_error_by_order"])
        assert np.all(by_order[:, 0] > np.asarray(m["metrics"]["cv_error"]))


def test_intervals_cover_the_truth_in_a_small_seeded_run():
    """bench/temperature.py measures the coverage over 400 warm-ups; here 12, loosely."""
    hits = total = 0
    for seed in range(12):
        w = warm_up(100 + seed, duration_s=900, sampling_rate_hz=20)
        r = calibrate_temperature(w.temperature_c, acc=w.acc, gyr=w.gyr, sampling_rate_hz=20, time_s=w.time_s, order=3)
        for sensor in ("acc", "gyr"):
            model, half = r.sensors[sensor]["model"], np.asarray(r.sensors[sensor]["uncertainty"]["coefficients"])
            err = np.abs(np.asarray(model["coefficients"]) - truth_about(model, sensor))
            fitted = half > 0
            hits += int(np.sum(err[fitted] <= half[fitted]))
            total += int(fitted.sum())
    assert 0.88 <= hits / total <= 0.995, hits / total


def test_a_bias_wandering_in_time_widens_the_gyroscope_s_intervals():
    w = warm_up(15, duration_s=1800, sampling_rate_hz=20)
    rng = np.random.default_rng(15)
    walk = np.cumsum(rng.normal(0.0, 2e-5 / np.sqrt(20), w.gyr.shape), axis=0)  # K = 2e-5 rad/s²/√Hz
    still = calibrate_temperature(w.temperature_c, gyr=w.gyr, sampling_rate_hz=20, time_s=w.time_s, order=3)
    wander = calibrate_temperature(w.temperature_c, gyr=w.gyr + walk, sampling_rate_hz=20, time_s=w.time_s, order=3)
    k = np.asarray(wander.sensors["gyr"]["uncertainty"]["random_walk"])
    assert np.all((k > 0.3 * 2e-5) & (k < 3 * 2e-5)), k
    widths = [np.asarray(r.sensors["gyr"]["uncertainty"]["coefficients"])[:, 1] for r in (still, wander)]
    assert np.all(widths[1] > 3 * widths[0])


def test_correct_subtracts_the_offset_clamped_to_the_range():
    w = warm_up(9, duration_s=900, sampling_rate_hz=20)
    r = calibrate_temperature(w.temperature_c, acc=w.acc, gyr=w.gyr, sampling_rate_hz=20)
    model = r.sensors["gyr"]["model"]
    t = np.array([model["t_min_c"] - 20, model["t_min_c"], model["t_ref_c"], model["t_max_c"] + 5])
    o = offset_at(model, t)
    np.testing.assert_array_equal(o[0], o[1])  # clamped below the range
    np.testing.assert_allclose(o[2], np.asarray(model["coefficients"])[:, 0], rtol=1e-12)
    m = np.ones((4, 3))
    np.testing.assert_allclose(r.correct("gyr", m, t), m - o, rtol=1e-12)
    again = CalibrationResult.from_dict(r.to_dict())
    assert isinstance(again, TemperatureResult)
    np.testing.assert_allclose(again.correct("gyr", m, t), m - o, rtol=1e-12)
    with pytest.raises(CalibrationError, match="temperature"):
        r.apply(m)


def test_shift_polynomial_writes_the_same_curve_about_another_temperature():
    c = np.array([[0.3, -0.2, 0.01, 4e-4]])
    shifted = shift_polynomial(c, 35.0, 22.5)
    t = np.linspace(-10, 70, 9)
    np.testing.assert_allclose(np.polyval(shifted[0][::-1], t - 22.5), np.polyval(c[0][::-1], t - 35.0), rtol=1e-12)


def test_a_span_under_ten_degrees_fails():
    w = warm_up(11, duration_s=900, sampling_rate_hz=20, t_start_c=30.0, t_end_c=37.0)
    r = calibrate_temperature(w.temperature_c, acc=w.acc, gyr=w.gyr, sampling_rate_hz=20)
    assert not r.ok
    assert any("under the 10 °C" in reason for reason in r.reasons)


def test_too_few_samples_in_a_band_fails_naming_the_band():
    # A warm-up so quick that the cold bands pass in seconds.
    w = warm_up(12, duration_s=600, sampling_rate_hz=10, tau_s=20.0)
    r = calibrate_temperature(w.temperature_c, acc=w.acc, sampling_rate_hz=10)
    assert not r.ok
    assert any("too few accelerometer samples in 15.0–" in reason for reason in r.reasons), r.reasons


def test_a_sensor_that_does_not_drift_fails_worse_than_raw():
    w = simulate_warm_up(
        np.random.default_rng(13),
        noise=real_still_noise(),
        acc_truth=np.zeros((3, 4)),
        duration_s=900,
        sampling_rate_hz=20,
    )
    r = calibrate_temperature(w.temperature_c, acc=w.acc, sampling_rate_hz=20)
    assert not r.ok
    assert any("no better than no correction" in reason for reason in r.reasons), r.reasons


def test_a_device_that_moved_fails_the_accelerometer_and_fits_the_gyroscope_on_its_rests():
    w = warm_up(14, duration_s=900, sampling_rate_hz=20)
    acc, gyr = w.acc.copy(), w.gyr.copy()
    half = len(acc) // 2
    acc[half:] = acc[half:][:, [0, 2, 1]] * [1, 1, -1]  # turned onto its side halfway
    gyr[half - 20 : half] += [0.0, 1.5, 0.0]  # the turn, 1 s at 1.5 rad/s
    r = calibrate_temperature(w.temperature_c, acc=acc, gyr=gyr, sampling_rate_hz=20)
    assert not r.ok
    assert any("the device moved" in reason and "accelerometer" in reason for reason in r.reasons)
    assert any("gyroscope was fitted on its" in warning for warning in r.warnings)
    assert r.sensors["gyr"]["metrics"]["n_samples"] < len(gyr)


def test_input_that_cannot_be_calibrated_is_refused():
    with pytest.raises(CalibrationError, match="accelerometer or gyroscope"):
        calibrate_temperature(np.zeros(10))
    with pytest.raises(CalibrationError, match="line up"):
        calibrate_temperature(np.zeros(10), acc=np.zeros((9, 3)))
