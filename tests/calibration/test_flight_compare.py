"""Which compass is lying (app/calibration/magnetometer/flight_compare.py): ArduPilot's consistency check between
two compasses' fields, the power's pull in degrees, and the one action of each row."""

from __future__ import annotations

import numpy as np
import pytest

from app.calibration.magnetometer.flight_compare import action, consistency, pull


def _turned(field: np.ndarray, degrees: float) -> np.ndarray:
    a = np.radians(degrees)
    Rz = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    return field @ Rz.T


FIELD = np.tile([20.0, 2.0, 45.0], (50, 1))


def test_consistency_takes_arduPilots_three_limits():
    assert consistency(FIELD, FIELD) == {
        "xyz_angle_deg": 0.0,
        "xy_angle_deg": 0.0,
        "xy_length_diff_ut": 0.0,
        "consistent": True,
    }
    # horizontal parts 70° apart (limit 60°), though the whole fields only 24° apart (limit 90°)
    turned = consistency(FIELD, _turned(FIELD, 70.0))
    assert turned["xy_angle_deg"] == pytest.approx(70.0) and turned["xyz_angle_deg"] < 90.0
    assert turned["consistent"] is False
    # 25 µT apart horizontally (limit 200 mG = 20 µT) at a small angle
    shifted = consistency(FIELD, FIELD * [2.2, 2.2, 1.0])
    assert shifted["xy_length_diff_ut"] == pytest.approx(1.2 * np.hypot(20.0, 2.0)) and shifted["consistent"] is False


def test_the_pull_in_degrees_is_its_horizontal_part_against_the_horizontal_field():
    p = pull([0.5, 0.0, 3.0], 20.0, np.array([20.0, 0.0, 45.0]))
    assert p["per_unit"] == pytest.approx(np.hypot(0.5, 3.0))
    assert p["at_top_deg"] == pytest.approx(np.degrees(np.arctan(10.0 / 20.0)))  # the vertical part turns no heading


BASE = {
    "measures": True,
    "ok": False,
    "before_deg": 12.0,
    "orientation_setting": None,
    "pull": None,
    "power_kind": "current",
    "motor_setting": "COMPASS_MOT2_X/Y/Z (COMPASS_MOTCT = 2)",
    "switch": "COMPASS_USE2",
    "consistent": True,
}


@pytest.mark.parametrize(
    "change, said",
    [
        ({"measures": False}, "disable it (COMPASS_USE2 = 0)"),
        ({"orientation_setting": "COMPASS_ORIENT2 = 8"}, "re-orient it (COMPASS_ORIENT2 = 8)"),
        (
            {"pull": {"at_top_deg": 9.6, "determined": True}},
            "set COMPASS_MOT2_X/Y/Z (COMPASS_MOTCT = 2) from this flight (the current pulls it 10°)",
        ),
        (
            {
                "pull": {"at_top_deg": 9.6, "determined": False},
                "reason": "the flight held one heading for most of it (8 of 8 sectors of 45° reached, but 68% of the "
                "flight in one; 80% of the directions): fly turns through every heading (a slow full yaw turn, or "
                "circles), banked as well as level, so that the hard iron can be told from the field and from a turn "
                "of the compass",
            },
            "fly turns through every heading (a slow full yaw turn, or circles), banked as well as level",
        ),
        ({"ok": True}, "apply this calibration"),
        ({"consistent": False}, "calibrate it or stop its use (COMPASS_USE2 = 0)"),
        ({"before_deg": 2.1}, "keep it as it is"),
    ],
)
def test_each_compass_gets_one_action(change, said):
    assert action({**BASE, **change}).startswith(said)
