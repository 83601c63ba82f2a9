"""The firmwares' rotation numbers as matrices (app.calibration.firmware_rotations) against ArduPilot's
``Vector3::rotate`` (libraries/AP_Math/vector3.cpp), written here case by case, and PX4's Euler lookup."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from app.calibration.firmware_rotations import (ROTATIONS, angle_between_deg, nearest_firmware_rotation,
                                                rotation_matrix, rotation_name)

H = np.sqrt(0.5)
VECTOR3_ROTATE = {  # number: v -> rotated v, as the switch in Vector3::rotate writes it
    1: lambda x, y, z: (H * (x - y), H * (x + y), z),
    2: lambda x, y, z: (-y, x, z),
    3: lambda x, y, z: (-H * (x + y), H * (x - y), z),
    4: lambda x, y, z: (-x, -y, z),
    5: lambda x, y, z: (H * (y - x), -H * (x + y), z),
    6: lambda x, y, z: (y, -x, z),
    7: lambda x, y, z: (H * (x + y), H * (y - x), z),
    8: lambda x, y, z: (x, -y, -z),
    9: lambda x, y, z: (H * (x + y), H * (x - y), -z),
    10: lambda x, y, z: (y, x, -z),
    12: lambda x, y, z: (-x, y, -z),
    14: lambda x, y, z: (-y, -x, -z),
    16: lambda x, y, z: (x, -z, y),
    18: lambda x, y, z: (z, x, y),  # ROLL_90 then YAW_90
    20: lambda x, y, z: (x, z, -y),
    24: lambda x, y, z: (z, y, -x),
    25: lambda x, y, z: (-z, y, x),
    27: lambda x, y, z: (y, x, -z),  # same as ROLL_180_YAW_90
    39: lambda x, y, z: (H * (x - z), y, H * (x + z)),
    42: lambda x, y, z: (x, H * (y - z), H * (y + z)),
    43: lambda x, y, z: (x, H * (y + z), H * (z - y)),
}


@pytest.mark.parametrize("number", sorted(VECTOR3_ROTATE))
def test_ardupilot_matrices_are_vector3_rotate(number):
    v = np.random.default_rng(number).normal(size=3)
    assert np.allclose(rotation_matrix("ardupilot", number) @ v, VECTOR3_ROTATE[number](*v))


def test_every_entry_is_a_rotation_and_px4_shares_ardupilots_numbers_to_40():
    for firmware, table in ROTATIONS.items():
        for number, (_, R) in table.items():
            assert np.allclose(R @ R.T, np.eye(3)) and np.isclose(np.linalg.det(R), 1.0), (firmware, number)
    for number in range(41):
        angle = angle_between_deg(rotation_matrix("px4", number), rotation_matrix("ardupilot", number))
        assert angle < (1.0 if number == 38 else 1e-6), number  # PX4's 38 is in whole degrees
    R = Rotation.from_euler("ZYX", [315, 0, 270], degrees=True).as_matrix()  # PX4 rot_lookup 47: roll 270, yaw 315
    assert np.allclose(rotation_matrix("px4", 47), R)


def test_nearest_rotation_names_the_lowest_of_equal_entries():
    assert nearest_firmware_rotation("ardupilot", rotation_matrix("ardupilot", 27)) == (10, pytest.approx(0.0, abs=1e-6))
    number, angle = nearest_firmware_rotation("ardupilot", Rotation.from_euler("z", 93, degrees=True).as_matrix())
    assert (number, round(angle, 6)) == (2, 3.0) and rotation_name("ardupilot", number) == "Yaw90"
    with pytest.raises(ValueError, match="no rotation number 100"):
        rotation_matrix("ardupilot", 100)
