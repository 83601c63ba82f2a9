"""The still-capture check of the wizard (app/calibration/shared/capture.py)."""

from __future__ import annotations

import numpy as np
import pytest

from app.calibration import CalibrationError
from app.calibration.shared.capture import STILL_MAX_STD_G, check_still_capture


def test_rate_comes_from_event_timestamps_not_a_nominal_interval():
    rng = np.random.default_rng(10)
    n = 500
    t_ms = np.cumsum(rng.uniform(15.0, 18.4, n))  # jittery ~60 Hz events, as a browser delivers them
    acc = np.array([0.0, -1.0, 0.0]) + rng.normal(0, 0.002, (n, 3))  # in g, -y up
    c = check_still_capture(acc, t_ms, gravity=1.0)
    assert c.position == "-y" and c.count == n
    assert c.sampling_rate_hz == pytest.approx(1000.0 / np.median(np.diff(t_ms)))
    assert c.duration_s == pytest.approx((t_ms[-1] - t_ms[0]) / 1000.0)
    np.testing.assert_allclose(c.mean, acc.mean(axis=0))
    np.testing.assert_allclose(c.std, acc.std(axis=0, ddof=1))


@pytest.mark.parametrize("gravity", [9.80665, 1.0])
def test_the_stillness_gate_is_a_fraction_of_gravity_in_either_unit(gravity):
    rng = np.random.default_rng(11)
    base = rng.normal(0, 1.0, (400, 3))
    base /= base.std(axis=0, ddof=1)
    t = np.arange(400.0) * 10
    calm = np.array([0.0, 0.0, gravity]) + 0.9 * STILL_MAX_STD_G * gravity * base
    assert check_still_capture(calm, t, gravity=gravity).position == "+z"
    shaky = np.array([0.0, 0.0, gravity]) + 1.1 * STILL_MAX_STD_G * gravity * base
    with pytest.raises(CalibrationError, match="moved during the capture"):
        check_still_capture(shaky, t, gravity=gravity)


def test_a_new_direction_must_be_ten_degrees_from_the_ones_taken():
    from app.calibration.shared.capture import PoseTooCloseError, check_new_direction

    check_new_direction([0, 0, 9.8], np.zeros((0, 3)), min_angle_deg=10)
    taken = [[9.8, 0, 0], [0, 0, 9.8]]
    tilt = np.radians(12)
    check_new_direction([0, 9.8 * np.sin(tilt), 9.8 * np.cos(tilt)], taken, min_angle_deg=10)
    tilt = np.radians(6)
    with pytest.raises(PoseTooCloseError) as err:
        check_new_direction([0, 9.8 * np.sin(tilt), 9.8 * np.cos(tilt)], taken, min_angle_deg=10)
    assert err.value.code == "pose_too_close"
    assert "only 6° from pose 2" in str(err.value) and "at least 10° further" in str(err.value)
