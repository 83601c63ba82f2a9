"""The gyroscope bias of still captures and its 95 % interval (app.calibration.still.gyro_bias)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from app.calibration import CalibrationError
from app.calibration.still.gyro_bias import gyroscope_bias
from simulations.gyro_captures import capture_statistics, simulate_captures

BIAS = np.array([0.004, -0.0025, 0.0012])  # rad/s: 0.23, −0.14, 0.07 °/s, a phone gyroscope's order
NOISE = np.radians(0.3)  # white noise per sample at 60 Hz
WANDER = np.radians(0.02)  # the bias's wander between captures
SESSIONS = 400


def _coverage(rng, *, n_captures, wander):
    inside, naive = np.zeros(3), np.zeros(3)
    for _ in range(SESSIONS):
        captures = simulate_captures(rng, bias=BIAS, n_captures=n_captures, n_samples=300, noise=NOISE, wander=wander)
        b = gyroscope_bias(*capture_statistics(captures))
        inside += np.abs(np.array(b["rad_s"]) - BIAS) <= np.array(b["half_width_rad_s"])
        pooled = np.vstack(captures)  # the samples' standard error: white noise only
        half = stats.t.ppf(0.975, len(pooled) - 1) * pooled.std(axis=0, ddof=1) / np.sqrt(len(pooled))
        naive += np.abs(pooled.mean(axis=0) - BIAS) <= half
    return inside / SESSIONS, naive / SESSIONS


def test_the_interval_over_captures_covers_the_bias_at_95_percent_despite_its_wander():
    covered, naive = _coverage(np.random.default_rng(2026), n_captures=6, wander=WANDER)
    assert np.all((covered >= 0.93) & (covered <= 0.97)), covered
    # The samples' standard error ignores the wander between captures: its interval is too narrow.
    assert np.all(naive < 0.88), naive


def test_the_bias_is_the_mean_of_the_capture_means_with_a_t_interval_on_their_spread():
    rng = np.random.default_rng(5)
    means, stds, counts = capture_statistics(
        simulate_captures(rng, bias=BIAS, n_captures=6, n_samples=300, noise=NOISE, wander=WANDER)
    )
    b = gyroscope_bias(means, stds, counts)
    np.testing.assert_allclose(b["rad_s"], means.mean(axis=0), rtol=0, atol=1e-15)
    expected = stats.t.ppf(0.975, 5) * means.std(axis=0, ddof=1) / np.sqrt(6)
    np.testing.assert_allclose(b["half_width_rad_s"], expected, rtol=1e-12)
    np.testing.assert_allclose(b["deg_s"], np.degrees(means.mean(axis=0)), rtol=1e-14)
    np.testing.assert_allclose(b["half_width_deg_s"], np.degrees(expected), rtol=1e-12)
    assert (b["count"], b["confidence"], b["interval_from"]) == (6, 0.95, "captures")
    assert "t(0.975, K-1)" in b["formula"]
    np.testing.assert_allclose(b["rad_s"], BIAS, atol=4 * WANDER / np.sqrt(6))


def test_a_single_capture_takes_its_interval_from_the_samples_and_says_so():
    rng = np.random.default_rng(9)
    (samples,) = simulate_captures(rng, bias=BIAS, n_captures=1, n_samples=300, noise=NOISE, wander=0.0)
    b = gyroscope_bias(*capture_statistics([samples]))
    assert (b["count"], b["interval_from"]) == (1, "samples") and "t(0.975, n-1)" in b["formula"]
    np.testing.assert_allclose(b["rad_s"], samples.mean(axis=0), rtol=0, atol=1e-15)
    expected = stats.t.ppf(0.975, 299) * samples.std(axis=0, ddof=1) / np.sqrt(300)
    np.testing.assert_allclose(b["half_width_rad_s"], expected, rtol=1e-12)
    # Without wander, the within-capture interval covers at its level too.
    covered, _ = _coverage(np.random.default_rng(11), n_captures=1, wander=0.0)
    assert np.all((covered >= 0.93) & (covered <= 0.97)), covered


@pytest.mark.parametrize(
    "means, stds, counts, message",
    [
        (np.zeros((0, 3)), np.zeros((0, 3)), [], "shape (K, 3)"),
        (np.zeros((2, 2)), np.zeros((2, 2)), [10, 10], "shape (K, 3)"),
        (np.zeros((2, 3)), np.zeros((1, 3)), [10, 10], "one std row"),
        (np.full((2, 3), np.nan), np.zeros((2, 3)), [10, 10], "not a finite number"),
        (np.zeros((2, 3)), np.zeros((2, 3)), [10, 0], "at least 1"),
        (np.zeros((1, 3)), np.zeros((1, 3)), [1], "at least two samples"),
    ],
)
def test_bad_input_is_refused_naming_the_problem(means, stds, counts, message):
    with pytest.raises(CalibrationError, match=message.replace("(", r"\(").replace(")", r"\)")):
        gyroscope_bias(means, stds, counts)
