"""The firmwares' rotation numbers (app/calibration/shared/rotations.py) against ArduPilot's ``Vector3<T>::rotate``
(libraries/AP_Math/vector3.cpp), written here case by case, and PX4's ``rot_lookup`` (src/lib/conversion/rotation.h):
the entries, the firmware's own number nearest a rotation, the names, and where the two enums part. The entries
tests/calibration/test_flight_compass.py checks by hand (2, 8, 16, 18, 24, 26, 39, 40) are not repeated here."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from app.calibration.shared.rotations import (
    ARDUPILOT_ROTATIONS,
    FIRMWARE_ROTATIONS,
    PX4_EVERY_RELEASE,
    PX4_ROTATIONS,
    angle_between,
    ardupilot_matrix,
    firmware_matrix,
    nearest_number,
    px4_matrix,
    rotation_name,
)

H = np.sqrt(0.5)
VECTOR3_ROTATE = {  # number: v -> rotated v, as the switch in Vector3<T>::rotate writes it
    1: lambda x, y, z: (H * (x - y), H * (x + y), z),
    3: lambda x, y, z: (-H * (x + y), H * (x - y), z),
    4: lambda x, y, z: (-x, -y, z),
    5: lambda x, y, z: (H * (y - x), -H * (x + y), z),
    6: lambda x, y, z: (y, -x, z),
    7: lambda x, y, z: (H * (x + y), H * (y - x), z),
    9: lambda x, y, z: (H * (x + y), H * (x - y), -z),
    10: lambda x, y, z: (y, x, -z),
    12: lambda x, y, z: (-x, y, -z),
    14: lambda x, y, z: (-y, -x, -z),
    20: lambda x, y, z: (x, z, -y),
    25: lambda x, y, z: (-z, y, x),
    27: lambda x, y, z: (y, x, -z),  # PITCH_180_YAW_270: the same as ROLL_180_YAW_90
    42: lambda x, y, z: (x, H * (y - z), H * (y + z)),  # ROLL_45, ArduPilot's only
    43: lambda x, y, z: (x, H * (y + z), H * (z - y)),  # ROLL_315, ArduPilot's only
}


@pytest.mark.parametrize("number", sorted(VECTOR3_ROTATE))
def test_ardupilot_matrices_are_vector3_rotate(number):
    v = np.random.default_rng(number).normal(size=3)
    assert np.allclose(firmware_matrix("ardupilot", number) @ v, VECTOR3_ROTATE[number](*v))


def test_every_entry_is_a_rotation_and_px4_47_is_its_rot_lookup():
    for firmware, table in FIRMWARE_ROTATIONS.items():
        for number in table:
            R = firmware_matrix(firmware, number)
            assert np.allclose(R @ R.T, np.eye(3)) and np.isclose(np.linalg.det(R), 1.0), (firmware, number)
    R = Rotation.from_euler("ZYX", [315, 0, 270], degrees=True).as_matrix()  # rot_lookup 47: roll 270, yaw 315
    assert np.allclose(px4_matrix(47), R) and rotation_name("px4", 47) == "ROLL_270_YAW_315"


def test_entry_38_is_085_degrees_apart_and_the_numbers_part_from_41():
    # ArduPilot's literal matrix (vector3.cpp) against PX4's whole degrees (90, 68, 293)
    assert angle_between(ardupilot_matrix(38), px4_matrix(38)) == pytest.approx(0.854, abs=1e-3)
    assert nearest_number("ardupilot", ardupilot_matrix(38)) == (38, pytest.approx(0.0, abs=1e-6))
    assert nearest_number("px4", ardupilot_matrix(38)) == (38, pytest.approx(0.854, abs=1e-3))
    for number in (41, 42, 43):  # same number, another rotation
        assert angle_between(ardupilot_matrix(number), px4_matrix(number)) > 100, number
        assert ARDUPILOT_ROTATIONS[number][0] != PX4_ROTATIONS[number][0]
    assert sorted(set(PX4_ROTATIONS) - set(ARDUPILOT_ROTATIONS)) == [44, 45, 46, 47]
    # each firmware answers with its own number: PX4's 41 is ArduPilot's (and its own) 31; ArduPilot's ROLL_45
    # has no PX4 entry, the nearest is 45° away
    assert nearest_number("ardupilot", px4_matrix(41)) == (31, pytest.approx(0.0, abs=1e-6))
    assert nearest_number("px4", px4_matrix(41)) == (31, pytest.approx(0.0, abs=1e-6))
    assert nearest_number("px4", ardupilot_matrix(42)) == (0, pytest.approx(45.0))


def test_nearest_number_names_the_lowest_of_equal_entries_and_unknown_numbers_are_refused():
    assert nearest_number("ardupilot", firmware_matrix("ardupilot", 27)) == (10, pytest.approx(0.0, abs=1e-6))
    number, angle = nearest_number("ardupilot", Rotation.from_euler("z", 93, degrees=True).as_matrix())
    assert (number, round(angle, 6)) == (2, 3.0) and rotation_name("ardupilot", number) == "YAW_90"
    assert rotation_name("px4", 100) == "rotation 100"
    with pytest.raises(ValueError, match="no rotation number 100"):
        firmware_matrix("ardupilot", 100)
    with pytest.raises(ValueError, match="unknown firmware"):
        firmware_matrix("betaflight", 0)
    assert PX4_ROTATIONS[PX4_EVERY_RELEASE][0] == "PITCH_270"


def test_a_firmware_is_offered_only_the_rotations_it_can_apply():
    from app.calibration.shared.rotations import PX4_ROTATIONS, nearest_rotation, px4_matrix

    # ArduPilot's PITCH_7 (41) has no PX4 number: PX4 is offered its own nearest, NONE, 7° away
    pitch_7 = ardupilot_matrix(41)
    assert nearest_rotation(pitch_7)[:3] == (41, None, "PITCH_7")
    ap, px4, name, angle = nearest_rotation(pitch_7, "px4")
    assert (ap, px4, name) == (0, 0, "NONE") and angle == pytest.approx(7.0, abs=1e-9)
    # PX4's own entries past ArduPilot's table are never offered to ArduPilot
    own = max(PX4_ROTATIONS)
    assert nearest_rotation(px4_matrix(own))[:2] == (None, own)
    ap, px4, _, angle = nearest_rotation(px4_matrix(own), "ardupilot")
    assert ap is not None and angle > 1.0
