"""ArduPilot and PX4 parameter exports on hand-made calibrations: ranges, signs, and what a rotation and the axes'
non-orthogonality leave to the firmware's offsets and scales."""

from __future__ import annotations

import numpy as np
import pytest

from app.io.errors import ExportError
from app.io.exports.params import firmware_summary, offset_scale, to_ardupilot, to_px4


def body(X, y, unit="m/s^2", gravity=9.80665):
    return {
        "id": "cal_test",
        "method": "six_position",
        "created_at": "2026-11-23T00:00:00Z",
        "unit": unit,
        "output_unit": unit,
        "gravity": gravity,
        "model": {"type": "affine", "X": np.asarray(X, float).tolist(), "y": list(map(float, y))},
    }


def test_scale_outside_ardupilot_range_is_refused():
    with pytest.raises(ExportError, match=r"INS_ACCSCAL_X = 0.7692 is outside 0.8…1.2"):
        to_ardupilot(body(np.diag([1.3, 1.0, 1.0]), [0, 0, 0]))


def test_diagonal_calibration_has_no_residual_and_the_sign_of_the_offset():
    # m = X a + y, so a = X^-1 (m - y): ArduPilot subtracts INS_ACCOFFS = y, then scales by 1/X_ii.
    text = to_ardupilot(body(np.diag([1.02, 0.99, 1.01]), [0.3, -0.2, 0.1])).content
    assert "INS_ACCOFFS_X 0.3\n" in text and "INS_ACCOFFS_Y -0.2\n" in text
    assert "INS_ACCSCAL_X 0.980392157\n" in text
    for line in ("firmware_norm_error_any_direction_mg: 0.000", "rotation_deg: 0.000", "nonorthogonality_mg: 0.000"):
        assert f"# {line} " in text


def test_g_calibration_offsets_are_exported_in_m_s2():
    p = offset_scale(body(np.eye(3), [0.01, 0.0, -0.02], unit="g", gravity=1.0), "PX4")
    np.testing.assert_allclose(p["offset_mps2"], [0.0980665, 0.0, -0.196133])
    text = to_px4(body(np.eye(3), [0.01, 0.0, -0.02], unit="g", gravity=1.0)).content
    assert "param set CAL_ACC0_ZOFF -0.196133\n" in text and "param set CAL_ACC0_XSCALE 1\n" in text


def rotation(axis, deg):
    """Rodrigues' formula: the rotation by ``deg`` about the unit vector ``axis``."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    t = np.radians(deg)
    return np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * K @ K


def test_a_rotation_is_no_error_of_the_firmware_s_offsets_and_scales():
    # The sensor turned 3° about (1, 2, 0.5) against the poses' frame, with scales and offsets: M = R S. The old
    # export (o and diag M) was tens of mg off; the fitted offsets and scales are the sensor's own, exactly.
    R = rotation([1, 2, 0.5], 3.0)
    S = np.diag([1.02, 0.99, 1.01])
    o = np.array([0.3, -0.2, 0.1])
    p = offset_scale(body(np.linalg.inv(R @ S), o), "ArduPilot")
    np.testing.assert_allclose(p["offset_mps2"], o, atol=1e-9)
    np.testing.assert_allclose(p["scale"], np.diag(S), atol=1e-9)
    fit = p["fit"]
    assert fit.rotation_deg == pytest.approx(3.0, abs=1e-9) and fit.nonorthogonality == pytest.approx(0, abs=1e-12)
    np.testing.assert_allclose(fit.rotation_axes_deg, 3.0 * np.array([1, 2, 0.5]) / np.linalg.norm([1, 2, 0.5]))
    assert not fit.from_readings and fit.count == 14 and fit.norm_error_any_direction < 1e-9
    text = to_ardupilot(body(np.linalg.inv(R @ S), o)).content
    assert "# rotation_deg: 3.000  (about x 1.309, y 2.619, z 0.655 deg)" in text
    assert (
        "ArduPilot's level calibration (Mission Planner: Calibrate Level) takes its tilt (2.93 deg about x and y) "
        "into AHRS_TRIM_X and AHRS_TRIM_Y (roll and pitch, in rad, within +-0.1745 = +-10 deg"
    ) in text


def test_the_axes_non_orthogonality_is_what_the_firmware_cannot_hold():
    # Axes x and y 1° from orthogonal (a symmetric shear): no rotation, and a norm error no diagonal removes.
    P = np.array([[1.0, np.sin(np.radians(0.5)), 0], [np.sin(np.radians(0.5)), 1.0, 0], [0, 0, 1.0]])
    p = offset_scale(body(np.linalg.inv(P), [0, 0, 0]), "PX4")
    fit = p["fit"]
    assert fit.rotation_deg == pytest.approx(0, abs=1e-9)
    assert abs(fit.axis_angles_deg[0]) == pytest.approx(1.0, abs=1e-3) and abs(fit.axis_angles_deg[1:]).max() < 1e-9
    # g |I − D P⁻¹|₂ with D = I and off-diagonal e: the eigenvalues of I − P⁻¹ are (±e − e²)/(1 − e²), so e/(1 − e).
    e = np.sin(np.radians(0.5))
    assert fit.nonorthogonality == pytest.approx(e / (1 - e), rel=1e-9)
    # Along (1, 1, 0)/√2 |P a| = g (1 + 0.0087): the firmware's best diagonal is left with mg, not zero.
    assert 2 < 1000 * fit.norm_error_any_direction < 9


def test_a_tilt_beyond_ardupilot_s_level_range_is_said():
    text = to_ardupilot(body(np.linalg.inv(rotation([1, 0, 0], 12.0)), [0, 0, 0])).content
    assert (
        "takes its tilt (12.00 deg about x and y)" in text and "beyond 10 deg it cannot: mount the board level" in text
    )


def test_inverted_axis_is_refused_by_px4():
    with pytest.raises(ExportError, match=r"CAL_ACC0_XSCALE = -1 outside its parameter range 0.1…3.*inverted"):
        to_px4(body(np.diag([-1.0, 1.0, 1.0]), [0, 0, 0]))


def test_a_sensor_whose_only_error_is_its_axes_angles_gets_no_firmware_file():
    # Every pair of axes 2° from orthogonal (shear e = sin 1°), no offset, no scale error: the best offsets and
    # scales leave the worst reading 34.7 mg off, raw 33.7 mg: no better, and said so.
    e = np.sin(np.radians(1.0))
    P = np.array([[1, e, e], [e, 1, e], [e, e, 1.0]])
    out = firmware_summary(body(np.linalg.inv(P), [0, 0, 0]), "ArduPilot")
    assert not out["improves"] and not out["from_readings"] and out["count"] == 14
    assert out["firmware_max_mg"] == pytest.approx(34.699, abs=1e-3) and out["raw_max_mg"] == pytest.approx(
        33.728, abs=1e-3
    )
    assert out["words"] == (
        "ArduPilot's offsets and scales would leave 34.7 mg on readings in 14 directions, no better "
        "than raw (33.7 mg): use the full correction (M and o) instead"
    )
    assert firmware_summary(body(np.linalg.inv(P) * 0.98, [0.2, 0, 0]), "PX4")["improves"]  # with a scale and offset
