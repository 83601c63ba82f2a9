"""The one plausibility gate of every result (app/calibration/shared/plausible.py, issue 31 point 6)."""

from __future__ import annotations

import dataclasses

import numpy as np

from app.calibration import CANONICAL_SIX, fit_six_position, up_vector
from app.calibration.magnetometer.fit import fit_magnetometer
from app.calibration.noise.characterise import NoiseResult, characterise_noise
from app.calibration.shared.plausible import PhysicalFigure, implausible, is_plausibility_reason
from app.calibration.shared.result import CalibrationResult

SIX = np.array([up_vector(label) for label in CANONICAL_SIX])


def _noise(samples, fs: float, unit: str) -> NoiseResult:
    part = characterise_noise(samples, fs, unit=unit, sensor="gyr")
    return NoiseResult(
        sensors={"gyr": {k: part[k] for k in ("model", "adev", "uncertainty", "metrics")}},
        sampling_rate_hz=fs,
        duration_s=len(samples) / fs,
        unit=unit,
    )


def test_a_still_gyroscope_in_deg_s_read_as_rad_s_is_not_ok_and_the_unit_is_named():
    # The MPU-6050: a bias of 4.5 °/s read as 4.5 rad/s (260 °/s); noise 0.05 °/s per sample.
    rng = np.random.default_rng(1)
    deg_s = np.array([4.5, -1.2, 0.8]) + rng.normal(scale=0.05, size=(3000, 3))
    wrong = _noise(deg_s, 100.0, "rad/s")
    assert not wrong.ok
    assert any("gyroscope's bias is 258 °/s" in r and "give gyr_unit deg/s" in r for r in wrong.reasons)
    assert all("give gyr_unit deg/s" in r for r in wrong.reasons)  # its noise density too: 0.287 °/s/√Hz
    right = _noise(np.deg2rad(deg_s), 100.0, "rad/s")
    assert right.ok, right.reasons


def test_readings_that_are_not_counts_have_a_noise_below_one_count_s_rounding():
    rng = np.random.default_rng(2)
    wrong = _noise(rng.normal(scale=0.001, size=(3000, 3)), 100.0, "raw")
    assert not wrong.ok and "not counts" in wrong.reasons[0]
    counts = _noise(np.round(rng.normal(scale=3.0, size=(3000, 3))), 100.0, "raw")
    assert counts.ok, counts.reasons


def test_an_accelerometer_in_m_s2_fitted_as_g_has_an_implausible_scale():
    means = SIX * 9.80665 + 0.05
    wrong = fit_six_position(means, gravity=1.0, plausible_scale=None)
    assert not wrong.ok and any("accelerometer's scale is 0.102" in r for r in wrong.reasons)
    assert fit_six_position(means, gravity=9.80665).ok


def test_a_compass_in_gauss_read_as_microtesla_names_gauss():
    rng = np.random.default_rng(3)
    d = rng.normal(size=(400, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    gauss = 0.48 * d + np.array([0.05, -0.02, 0.1]) + rng.normal(scale=0.002, size=(400, 3))
    wrong = fit_magnetometer(gauss)  # readings taken as µT: a field of 0.48 µT
    assert not wrong.ok and "give mag_unit gauss" in wrong.reasons[0]
    assert fit_magnetometer(100 * gauss).ok


def test_the_gate_is_judged_again_when_a_result_is_made_again():
    rng = np.random.default_rng(4)
    d = rng.normal(size=(400, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    counts = (
        1000 * d * np.array([1.1, 0.9, 1.0]) + np.array([300.0, -120.0, 40.0]) + rng.normal(scale=2.0, size=(400, 3))
    )
    as_ut = fit_magnetometer(counts)  # made in µT (the fit's default): 1000 µT is no Earth's field
    assert not as_ut.ok
    in_counts = dataclasses.replace(as_ut, unit="raw")  # the workflow says they are counts
    assert in_counts.ok, in_counts.reasons
    stored = as_ut.to_dict()
    again = CalibrationResult.from_dict(stored)
    assert again.reasons == as_ut.reasons  # read back: the same reason once, not twice


def test_a_stored_body_is_read_back_as_it_was_stored_not_judged_again():
    # A body stored under other limits (here: its plausibility reason taken away, as if an older trical had
    # stored it) reads back with the reasons it holds: reading does not rewrite it (issue 46, deliverable 2).
    rng = np.random.default_rng(4)
    d = rng.normal(size=(400, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    as_ut = fit_magnetometer(1000 * d + rng.normal(scale=2.0, size=(400, 3)))
    assert not as_ut.ok
    stored = {**as_ut.to_dict(), "ok": True, "reasons": [], "warnings": []}
    again = CalibrationResult.from_dict(stored)
    assert again.reasons == () and again.warnings == ()
    assert again.to_dict() == stored
    made_again = dataclasses.replace(again, unit="uT")  # made anew from it: its figures judged again
    assert made_again.reasons == tuple(r for r in as_ut.reasons if is_plausibility_reason(r)) != ()


def test_offsets_and_biases_have_limits_scales_and_densities_a_range():
    assert implausible([PhysicalFigure("acc", "offset", (0.5, 0.2, 1.2), "g")])[0].startswith(
        "the accelerometer's offset is 1.2e+03 mg"
    )
    assert implausible([PhysicalFigure("gyr", "bias", (0.1, 0.2, 0.3), "rad/s")]) == []
    assert implausible([PhysicalFigure("mag", "field", (50.0,), "uT")]) == []
    assert "give mag_unit nT" in implausible([PhysicalFigure("mag", "field", (48000.0,), "uT")])[0]
    assert implausible([PhysicalFigure("acc", "noise_density", (3.3e-3,), "m/s^2")]) == []
