"""Georgieva et al. (ESGI'95), Approach 2: least squares (section 3.3), closed form (3.3.1), metrics (3.5)."""

import numpy as np
import pytest

from app.calibration import (
    AffineCalibration,
    CalibrationError,
    InsufficientDataError,
    fit_orientations,
    fit_six_position,
)
from app.calibration.shared.result import CalibrationResult

HUAWEI_X = [[1.00381, -0.00227028, -0.0141925], [-0.00324982, 1.00003, 0.00734762], [-0.019297, 0.0362144, 0.988311]]
HUAWEI_Y = [0.353222, 0.363473, -1.18129]
GT_X = [[0.990908, 0.0193084, -0.0191228], [-0.000163521, 0.981047, -0.00689508], [0.0228047, 0.00124993, 0.998542]]
GT_Y = [0.482181, 0.0587712, 0.0440956]
GT_ORDER = ["+y", "-y", "+x", "-x", "+z", "-z"]  # seeds/README: Table 3's first six rows


def test_huawei_section_3_5_1(table1):
    # Georgieva et al. section 3.5.1: Table 1, first six rows, g = 9.81.
    cal = fit_six_position(table1[:6], gravity=9.81)
    # The paper prints X to 6 significant digits; its y differs from the table's rows by < 1e-5
    # (the paper's own inputs carried more digits than Table 1 prints).
    np.testing.assert_allclose(cal.X, HUAWEI_X, atol=1e-5)
    np.testing.assert_allclose(cal.y, HUAWEI_Y, atol=1e-5)
    assert cal.metrics["fit_error_max"] == pytest.approx(0.010601, abs=1e-6)
    assert cal.metrics["fit_error_max_raw"] == pytest.approx(0.17386, abs=1e-5)
    assert cal.metrics["fit_improvement"] == pytest.approx(16.4, abs=0.05)  # "about 16.4 times"
    # Applied to all rows of Table 1 (the 27 it prints).
    held = cal.evaluate(table1)
    assert held["count"] == 27
    # 0.0315423 from Table 1's printed digits; the paper's 0.0315425 came from its unrounded inputs
    # (its printed X and y give 0.0315424): agreement to 3e-7.
    assert held["norm_error_max"] == pytest.approx(0.0315425, abs=3e-7)
    assert held["norm_error_max_raw"] == pytest.approx(0.122075, abs=1e-6)
    assert held["norm_error_max_raw"] / held["norm_error_max"] == pytest.approx(3.87, abs=0.005)
    assert cal.ok


def test_gt_section_3_5_2(table3):
    cal = fit_six_position(table3[:6], GT_ORDER, gravity=9.81)
    np.testing.assert_allclose(cal.X, GT_X, atol=1e-6)
    np.testing.assert_allclose(cal.y, GT_Y, atol=1e-6)
    assert cal.metrics["fit_error_max"] == pytest.approx(0.0158458, abs=1e-7)
    assert cal.metrics["fit_error_max_raw"] == pytest.approx(0.0725016, abs=1e-7)
    held = cal.evaluate(table3)
    assert held["norm_error_max"] == pytest.approx(0.0138985, abs=1e-7)
    assert held["norm_error_max_raw"] == pytest.approx(0.0582853, abs=1e-7)
    assert cal.metrics["fit_improvement"] == pytest.approx(4.58, abs=0.005)
    assert held["norm_error_max_raw"] / held["norm_error_max"] == pytest.approx(4.19, abs=0.005)


@pytest.mark.parametrize("seed", range(5))
def test_closed_form_equals_least_squares(seed):
    rng = np.random.default_rng(seed)
    labels = list(rng.permutation(["-x", "+x", "-y", "+y", "-z", "+z"]))
    X = np.eye(3) + rng.normal(0, 0.03, (3, 3))
    y = rng.normal(0, 0.3, 3)
    a = np.array([{"x": 0, "y": 1, "z": 2}[lab[1]] for lab in labels])
    up = np.zeros((6, 3))
    up[np.arange(6), a] = [1.0 if lab[0] == "+" else -1.0 for lab in labels]
    means = (up * 9.81) @ X.T + y + rng.normal(0, 0.02, (6, 3))
    closed = fit_six_position(means, labels, gravity=9.81)
    lsq = fit_orientations(means, labels, gravity=9.81)
    np.testing.assert_allclose(closed.X, lsq.X, atol=1e-12)
    np.testing.assert_allclose(closed.y, lsq.y, atol=1e-12)
    np.testing.assert_allclose(closed.covariance, lsq.covariance, atol=1e-12)


def test_intervals_cover_truth_at_nominal_rate():
    # Residual-variance intervals with 2 dof per axis (six readings): t quantile 4.30.
    rng = np.random.default_rng(2024)
    X = np.array([[1.01, 0.01, -0.02], [0.005, 0.99, 0.01], [-0.01, 0.02, 1.02]])
    y = np.array([0.2, -0.1, 0.4])
    up = np.vstack([-np.eye(3)[0], np.eye(3)[0], -np.eye(3)[1], np.eye(3)[1], -np.eye(3)[2], np.eye(3)[2]])
    up = np.vstack([up, np.array([[1, 1, 1], [-1, 1, -1], [1, -1, -1]]) / np.sqrt(3)])  # 9 readings, 5 dof
    labels = [None] * len(up)
    truth = np.concatenate([X.ravel(), y])
    hits = np.zeros(12)
    runs = 2000
    for _ in range(runs):
        means = (up * 9.81) @ X.T + y + rng.normal(0, 0.01, (len(up), 3))
        cal = fit_orientations(means, labels, expected=list(up * 9.81), gravity=9.81)
        unc = cal.uncertainty()
        hw = np.concatenate([np.ravel(unc["X"]), unc["y"]])
        est = np.concatenate([cal.X.ravel(), cal.y])
        hits += np.abs(est - truth) <= hw
    coverage = hits / runs
    # Binomial 99.9 % band around 0.95 for 2000 runs: ±0.016.
    assert np.all(np.abs(coverage - 0.95) < 0.016), coverage


def test_no_degrees_of_freedom_is_honest():
    means = np.array([[9.8, 0, 0], [0, 9.8, 0], [0, 0, 9.8], [-9.8, 0, 0]]) + 0.01
    cal = fit_orientations(means, ["+x", "+y", "+z", "-x"], gravity=9.8)
    unc = cal.uncertainty()
    assert unc["X"] is None and unc["y"] is None and "0 residual degrees of freedom" in unc["note"]
    assert cal.dof == 0 and cal.covariance is None
    assert any("no residual degrees of freedom" in w for w in cal.warnings)
    d = cal.to_dict()
    assert "NaN" not in repr(d) and "nan" not in repr(d)


def test_condition_22_names_the_missing_axis():
    means = np.array([[9.8, 0, 0], [-9.8, 0, 0], [0, 9.8, 0], [0, -9.8, 0], [7, 7, 0]])
    with pytest.raises(InsufficientDataError, match=r"condition \(22\).*rank 3.*z axis"):
        fit_orientations(means, ["+x", "-x", "+y", "-y", None], expected=[None] * 4 + [[6.93, 6.93, 0]], gravity=9.8)


def test_fewer_than_four_readings():
    with pytest.raises(InsufficientDataError, match="at least 4"):
        fit_orientations([[9.8, 0, 0], [0, 9.8, 0], [0, 0, 9.8]], ["+x", "+y", "+z"], gravity=9.8)


@pytest.mark.parametrize(
    "labels, message",
    [
        (["-x", "+x", "-y", "+y", "-z", "-z"], r"-z is given more than once and \+z is missing"),
        (["-x", "+x", "-y", "+y", "-z", "up"], "unknown orientation 'up'"),
    ],
)
def test_six_position_labels(table1, labels, message):
    with pytest.raises(CalibrationError, match=message):
        fit_six_position(table1[:6], labels, gravity=9.81)


@pytest.mark.parametrize(
    "means, message",
    [
        (np.zeros((6, 2)), r"shape N×3"),
        (np.array([[1, 2, np.nan]] * 6), "NaN or infinite"),
        (np.array([[1, 2, np.inf]] * 6), "NaN or infinite"),
        (np.zeros((5, 3)), "exactly 6 readings"),
    ],
)
def test_bad_shapes(means, message):
    with pytest.raises(CalibrationError, match=message):
        fit_six_position(means, gravity=9.81)


def test_mislabelled_reading_fails_the_gates(table1):
    labels = ["+x", "-x", "-y", "+y", "-z", "+z"]  # x readings swapped
    cal = fit_six_position(table1[:6], labels, gravity=9.81)
    assert not cal.ok
    assert any("scale of the x axis" in r for r in cal.reasons)


def test_near_duplicates_are_named(table1):
    means = np.vstack([table1[:6], table1[0] + 0.01])
    cal = fit_orientations(means, ["-x", "+x", "-y", "+y", "-z", "+z", "-x"], gravity=9.81)
    assert any("readings 0 and 6" in w for w in cal.warnings)


def test_round_trip_and_apply(table1):
    cal = fit_six_position(table1[:6], gravity=9.81)
    again = CalibrationResult.from_dict(cal.to_dict())
    assert isinstance(again, AffineCalibration)
    np.testing.assert_array_equal(again.X, cal.X)
    np.testing.assert_array_equal(again.apply(table1), cal.apply(table1))
    np.testing.assert_allclose(cal.apply(table1[0]), np.linalg.solve(cal.X, table1[0] - cal.y))
    # a = X⁻¹ (m − y) inverts m = X a + y (Georgieva et al. eqs. (20)).
    a = np.array([[1.0, -2.0, 9.0]])
    np.testing.assert_allclose(cal.apply(a @ cal.X.T + cal.y), a, atol=1e-12)
    assert cal.to_dict()["readings"][0]["up"] == "-x"
