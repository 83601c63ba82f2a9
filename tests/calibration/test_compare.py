"""Two calibrations compared parameter by parameter (app.calibration.compare): the differences, their intervals
from both results' uncertainty, which are real, and their effect as a tilt or a heading."""

import dataclasses

import numpy as np
import pytest

from app.calibration.compare import compare, correction_half_widths, polar
from app.calibration.magnetometer import fit_magnetometer
from app.calibration.shared.errors import CalibrationError
from app.calibration.still.affine import fit_six_position
from app.calibration.still.triangular import fit_triangular
from simulations.drift import drifted_poses
from simulations.free_poses import free_pose_session
from simulations.magnetometer import EARTH_FIELD_UT, simulate_session, simulate_turn
from tests.real_recordings import mpu9250_sessions


def by_name(sensor):
    return {(d.group, d.axis): d for d in sensor.differences}


def test_a_calibration_compared_with_itself_differs_in_nothing_and_nothing_is_real():
    _, means = free_pose_session(np.random.default_rng(3), 24)
    cal = dataclasses.replace(fit_triangular(means, gravity=1.0), unit="g")
    acc = compare(cal, cal).sensors[0]
    assert all(abs(d.value) < 1e-6 for d in acc.differences)
    assert acc.real() == () and acc.effect < 1e-9 and acc.effect_kind == "tilt"


def test_an_offset_moved_between_two_sessions_is_real_and_told_in_mg_and_degrees():
    rng = np.random.default_rng(7)
    p, means = free_pose_session(rng, 24)
    a = dataclasses.replace(fit_triangular(means, gravity=1.0), unit="g")
    b = dataclasses.replace(fit_triangular(drifted_poses(rng, p, 24, offset_g=(0.0, 0.01, 0.0)), gravity=1.0), unit="g")
    acc = compare(a, b).sensors[0]
    d = by_name(acc)
    assert d["offsets", "y"].real and d["offsets", "y"].value == pytest.approx(10.0, abs=1.5)
    assert d["offsets", "y"].unit == "mg" and d["offsets", "y"].half_width is not None
    assert d["offsets", "y"].input_unit == "g" and d["offsets", "y"].in_input_unit == pytest.approx(0.01, abs=0.0015)
    assert not d["offsets", "x"].real and not d["scales", "x"].real
    # the effect at 1 g: the 10 mg moved and each session's own error, a level off by asin(e / g) at worst
    assert 8.0 < acc.effect < 18.0
    assert acc.effect_deg == pytest.approx(np.degrees(np.arcsin(acc.effect / 1000.0)))


def test_the_intervals_are_read_from_each_model_s_parameters():
    """An affine result's intervals are of X = M⁻¹ and y = o, a triangular's of K = M and o = −o_correction, a
    compass's of M and b: each maps to the correction's."""
    ups, means = mpu9250_sessions()["trial_1"]
    affine = fit_six_position(means, ups, gravity=1.0)
    hw_M, hw_o = correction_half_widths(affine)["acc"]
    u = affine.uncertainty()
    np.testing.assert_allclose(hw_o, u["y"])
    M = affine.correction.M
    np.testing.assert_allclose(hw_M, np.abs(M) @ np.array(u["X"]) @ np.abs(M))
    _, free = free_pose_session(np.random.default_rng(1), 20)
    tri = fit_triangular(free, gravity=1.0)
    hw_M, hw_o = correction_half_widths(tri)["acc"]
    np.testing.assert_allclose(hw_M, tri.uncertainty()["K"]) and np.testing.assert_allclose(
        hw_o, tri.uncertainty()["o"]
    )
    m, _, _ = simulate_session(2, n=300)
    mag = fit_magnetometer(m, field_ut=EARTH_FIELD_UT)
    hw_M, hw_o = correction_half_widths(mag)["mag"]
    np.testing.assert_allclose(hw_o, mag.uncertainty()["b"])


def test_a_hard_iron_shift_is_real_in_ut_and_told_as_a_heading():
    m, M, b = simulate_session(5, n=300)
    a = fit_magnetometer(m, field_ut=EARTH_FIELD_UT)
    rng = np.random.default_rng(9)
    b2 = fit_magnetometer(simulate_turn(rng, M, b + np.array([0.0, 0.0, 4.0]), n=300), field_ut=EARTH_FIELD_UT)
    mag = compare(a, b2, inclination_deg=64.0).sensors[0]
    d = by_name(mag)
    assert d["offsets", "z"].real and d["offsets", "z"].unit == "µT" and d["offsets", "z"].words == "hard iron"
    assert d["offsets", "z"].value == pytest.approx(4.0 * M[2, 2], abs=0.5)
    assert mag.effect_kind == "heading"
    H = EARTH_FIELD_UT * np.cos(np.radians(64.0))
    assert mag.effect_deg == pytest.approx(np.degrees(np.arcsin(mag.effect / H)))


def test_the_real_mpu9250_sessions_compared_say_which_differences_are_real():
    sessions = mpu9250_sessions()
    cals = {n: dataclasses.replace(fit_six_position(m, u, gravity=1.0), unit="g") for n, (u, m) in sessions.items()}
    acc = compare(cals["trial_1"], cals["final_trial"]).sensors[0]
    assert len(acc.differences) == 10 and all(d.half_width is not None for d in acc.differences[:9])
    assert acc.effect < 20.0 and acc.effect_deg < 1.2  # mg and degrees: the same board, months apart


def test_polar_splits_a_rotation_from_the_scales():
    angle = np.radians(10.0)
    R = np.array([[np.cos(angle), -np.sin(angle), 0.0], [np.sin(angle), np.cos(angle), 0.0], [0.0, 0.0, 1.0]])
    S = np.diag([1.01, 0.99, 1.0])
    R2, S2 = polar(R @ S)
    np.testing.assert_allclose(R2, R, atol=1e-12) and np.testing.assert_allclose(S2, S, atol=1e-12)


def test_calibrations_of_different_sensors_are_refused():
    _, means = free_pose_session(np.random.default_rng(3), 24)
    m, _, _ = simulate_session(2, n=300)
    with pytest.raises(CalibrationError, match="no sensor in common"):
        compare(fit_triangular(means, gravity=1.0), fit_magnetometer(m, field_ut=EARTH_FIELD_UT))
