"""ArduPilot and PX4 parameter exports on hand-made calibrations: ranges, signs, the residual bound."""

from __future__ import annotations

import numpy as np
import pytest

from app.io.errors import ExportError
from app.io.export_params import offset_scale, to_ardupilot, to_px4


def body(X, y, unit="m/s^2", gravity=9.80665):
    return {"id": "cal_test", "method": "six_position", "created_at": "2026-11-23T00:00:00Z", "unit": unit,
            "output_unit": unit, "gravity": gravity,
            "model": {"type": "affine", "X": np.asarray(X, float).tolist(), "y": list(map(float, y))}}


def test_scale_outside_ardupilot_range_is_refused():
    with pytest.raises(ExportError, match=r"INS_ACCSCAL_X = 0.7692 is outside 0.8…1.2"):
        to_ardupilot(body(np.diag([1.3, 1.0, 1.0]), [0, 0, 0]))


def test_diagonal_calibration_has_no_residual_and_the_sign_of_the_offset():
    # m = X a + y, so a = X^-1 (m - y): ArduPilot subtracts INS_ACCOFFS = y, then scales by 1/X_ii.
    text = to_ardupilot(body(np.diag([1.02, 0.99, 1.01]), [0.3, -0.2, 0.1])).content
    assert "INS_ACCOFFS_X 0.3\n" in text and "INS_ACCOFFS_Y -0.2\n" in text
    assert "INS_ACCSCAL_X 0.980392157\n" in text
    assert "# dropped_terms_residual_max: 0 m/s^2" in text


def test_g_calibration_offsets_are_exported_in_m_s2():
    p = offset_scale(body(np.eye(3), [0.01, 0.0, -0.02], unit="g", gravity=1.0), "PX4")
    np.testing.assert_allclose(p["offset_mps2"], [0.0980665, 0.0, -0.196133])
    text = to_px4(body(np.eye(3), [0.01, 0.0, -0.02], unit="g", gravity=1.0)).content
    assert "param set CAL_ACC0_ZOFF -0.196133\n" in text and "param set CAL_ACC0_XSCALE 1\n" in text


def test_residual_is_the_worst_case_over_the_sphere():
    X = np.array([[1.0, 0.02, 0.0], [0.0, 1.0, -0.01], [0.03, 0.0, 1.0]])
    p = offset_scale(body(X, [0, 0, 0]), "ArduPilot")
    M = np.linalg.inv(X)
    D = np.diag(np.diag(M))
    a = np.random.default_rng(0).normal(size=(20000, 3))
    a *= 9.80665 / np.linalg.norm(a, axis=1, keepdims=True)
    m = a @ X.T
    diff = m @ M.T - m @ D.T
    assert np.linalg.norm(diff, axis=1).max() == pytest.approx(p["residual_max"], rel=2e-3)


def test_inverted_axis_is_refused_by_px4():
    with pytest.raises(ExportError, match=r"CAL_ACC0_XSCALE = -1 outside its parameter range 0.1…3.*inverted"):
        to_px4(body(np.diag([-1.0, 1.0, 1.0]), [0, 0, 0]))
