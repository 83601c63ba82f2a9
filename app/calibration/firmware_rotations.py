"""The sensor rotations ArduPilot and PX4 store as numbers (``COMPASS_ORIENTn``, ``AHRS_ORIENTATION``;
``CAL_MAGn_ROT``, ``SENS_BOARD_ROT``), as 3×3 matrices that take a vector from the sensor's frame to the
vehicle's: ``v_body = R v_sensor``.

* ArduPilot, ``libraries/AP_Math/rotations.h`` (``enum Rotation``) and ``Vector3::rotate`` in
  ``libraries/AP_Math/vector3.cpp``: each entry is named by the rotations applied in turn, roll (about x) first,
  then pitch (about y), then yaw (about z), so ``R = Rz(yaw) Ry(pitch) Rx(roll)`` — e.g. ``ROTATION_YAW_90``
  is ``x' = −y, y' = x``. Entry 38 is written out as a matrix in ``Vector3::rotate`` and taken from there.
  Entries 26 and 27 repeat 14 and 10; 41 is ``PITCH_7``, 42 ``ROLL_45``, 43 ``ROLL_315``.
* PX4, ``src/lib/conversion/rotation.h`` (``enum Rotation`` and ``rot_lookup`` of roll, pitch, yaw in
  degrees) and ``get_rot_matrix`` in ``rotation.cpp``: ``Dcmf(Eulerf(roll, pitch, yaw))``, the same
  ``Rz Ry Rx``. The numbers 0–40 are ArduPilot's (MAVLink's ``MAV_SENSOR_ORIENTATION``) except that 38 has
  whole degrees (90, 68, 293); 41–47 are PX4's own and differ from ArduPilot's 41–43.
"""

from __future__ import annotations

import numpy as np

# number: (name, roll, pitch, yaw) in degrees, libraries/AP_Math/rotations.h
_ARDUPILOT = {
    0: ("None", 0, 0, 0), 1: ("Yaw45", 0, 0, 45), 2: ("Yaw90", 0, 0, 90), 3: ("Yaw135", 0, 0, 135),
    4: ("Yaw180", 0, 0, 180), 5: ("Yaw225", 0, 0, 225), 6: ("Yaw270", 0, 0, 270), 7: ("Yaw315", 0, 0, 315),
    8: ("Roll180", 180, 0, 0), 9: ("Roll180Yaw45", 180, 0, 45), 10: ("Roll180Yaw90", 180, 0, 90),
    11: ("Roll180Yaw135", 180, 0, 135), 12: ("Pitch180", 0, 180, 0), 13: ("Roll180Yaw225", 180, 0, 225),
    14: ("Roll180Yaw270", 180, 0, 270), 15: ("Roll180Yaw315", 180, 0, 315), 16: ("Roll90", 90, 0, 0),
    17: ("Roll90Yaw45", 90, 0, 45), 18: ("Roll90Yaw90", 90, 0, 90), 19: ("Roll90Yaw135", 90, 0, 135),
    20: ("Roll270", 270, 0, 0), 21: ("Roll270Yaw45", 270, 0, 45), 22: ("Roll270Yaw90", 270, 0, 90),
    23: ("Roll270Yaw135", 270, 0, 135), 24: ("Pitch90", 0, 90, 0), 25: ("Pitch270", 0, 270, 0),
    26: ("Pitch180Yaw90", 0, 180, 90), 27: ("Pitch180Yaw270", 0, 180, 270), 28: ("Roll90Pitch90", 90, 90, 0),
    29: ("Roll180Pitch90", 180, 90, 0), 30: ("Roll270Pitch90", 270, 90, 0), 31: ("Roll90Pitch180", 90, 180, 0),
    32: ("Roll270Pitch180", 270, 180, 0), 33: ("Roll90Pitch270", 90, 270, 0), 34: ("Roll180Pitch270", 180, 270, 0),
    35: ("Roll270Pitch270", 270, 270, 0), 36: ("Roll90Pitch180Yaw90", 90, 180, 90), 37: ("Roll90Yaw270", 90, 0, 270),
    38: ("Roll90Pitch68Yaw293", None, None, None), 39: ("Pitch315", 0, 315, 0), 40: ("Roll90Pitch315", 90, 315, 0),
    41: ("Pitch7", 0, 7, 0), 42: ("Roll45", 45, 0, 0), 43: ("Roll315", 315, 0, 0),
}
# ROTATION_ROLL_90_PITCH_68_YAW_293 as Vector3::rotate writes it (libraries/AP_Math/vector3.cpp)
_ARDUPILOT_38 = np.array([
    [0.14303897231223747, 0.36877648650320383, -0.91844638134308709],
    [-0.33213277779664740, -0.85628942146641884, -0.39554550256296522],
    [-0.93232380121551217, 0.36162457008209242, 0.0],
])
# number: (roll, pitch, yaw) in degrees, src/lib/conversion/rotation.h rot_lookup
_PX4 = {
    0: (0, 0, 0), 1: (0, 0, 45), 2: (0, 0, 90), 3: (0, 0, 135), 4: (0, 0, 180), 5: (0, 0, 225), 6: (0, 0, 270),
    7: (0, 0, 315), 8: (180, 0, 0), 9: (180, 0, 45), 10: (180, 0, 90), 11: (180, 0, 135), 12: (0, 180, 0),
    13: (180, 0, 225), 14: (180, 0, 270), 15: (180, 0, 315), 16: (90, 0, 0), 17: (90, 0, 45), 18: (90, 0, 90),
    19: (90, 0, 135), 20: (270, 0, 0), 21: (270, 0, 45), 22: (270, 0, 90), 23: (270, 0, 135), 24: (0, 90, 0),
    25: (0, 270, 0), 26: (0, 180, 90), 27: (0, 180, 270), 28: (90, 90, 0), 29: (180, 90, 0), 30: (270, 90, 0),
    31: (90, 180, 0), 32: (270, 180, 0), 33: (90, 270, 0), 34: (180, 270, 0), 35: (270, 270, 0),
    36: (90, 180, 90), 37: (90, 0, 270), 38: (90, 68, 293), 39: (0, 315, 0), 40: (90, 315, 0), 41: (270, 0, 180),
    42: (270, 0, 270), 43: (0, 90, 180), 44: (0, 9, 180), 45: (0, 45, 0), 46: (270, 0, 225), 47: (270, 0, 315),
}

FIRMWARES = ("ardupilot", "px4")


def euler_matrix(roll_deg: float, pitch_deg: float, yaw_deg: float) -> np.ndarray:
    """``Rz(yaw) Ry(pitch) Rx(roll)``: roll applied first (PX4's ``Dcm(Euler)``, ArduPilot's ``from_euler``)."""
    r, p, y = np.radians([roll_deg, pitch_deg, yaw_deg])
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def _name(roll: int, pitch: int, yaw: int) -> str:
    parts = [f"{n}{v}" for n, v in (("Roll", roll), ("Pitch", pitch), ("Yaw", yaw)) if v]
    return "".join(parts) or "None"


def _tables() -> dict[str, dict[int, tuple[str, np.ndarray]]]:
    ardupilot = {n: (name, _ARDUPILOT_38.copy() if n == 38 else euler_matrix(r, p, y))
                 for n, (name, r, p, y) in _ARDUPILOT.items()}
    px4 = {n: (_name(*rpy), euler_matrix(*rpy)) for n, rpy in _PX4.items()}
    return {"ardupilot": ardupilot, "px4": px4}


ROTATIONS = _tables()
"""``ROTATIONS[firmware][number] = (name, R)``, R taking sensor-frame vectors to the body frame."""


def _table(firmware: str) -> dict[int, tuple[str, np.ndarray]]:
    try:
        return ROTATIONS[firmware]
    except KeyError:
        raise ValueError(f"unknown firmware {firmware!r}; known: {', '.join(FIRMWARES)}") from None


def rotation_matrix(firmware: str, number: int) -> np.ndarray:
    """The matrix of a firmware's rotation number.

    Raises
    ------
    ValueError
        An unknown firmware, or a number outside its table (custom rotations among them).
    """
    table = _table(firmware)
    if number not in table:
        raise ValueError(f"{firmware} has no rotation number {number} (known 0–{max(table)})")
    return table[number][1].copy()


def rotation_name(firmware: str, number: int) -> str:
    """The name of a firmware's rotation number (``Roll180Yaw90``)."""
    table = _table(firmware)
    return table[number][0] if number in table else f"rotation {number}"


def angle_between_deg(a: np.ndarray, b: np.ndarray) -> float:
    """The angle of the rotation ``a bᵀ`` (degrees): 0 when the two rotations are equal."""
    c = (np.trace(np.asarray(a, float) @ np.asarray(b, float).T) - 1.0) / 2.0
    return float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))


def nearest_firmware_rotation(firmware: str, R: np.ndarray) -> tuple[int, float]:
    """The firmware's rotation number nearest to ``R`` and the angle left (degrees); of equal entries, the
    lowest number."""
    best = min(_table(firmware).items(), key=lambda item: (round(angle_between_deg(R, item[1][1]), 9), item[0]))
    return best[0], angle_between_deg(R, best[1][1])
