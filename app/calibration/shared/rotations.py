"""The flight controllers' sensor rotations as 3×3 matrices, and the one nearest a rotation the data show.

Both firmwares name a sensor's mounting by an enum whose entry ``ROTATION_ROLL_r_PITCH_p_YAW_y`` turns a
vector first by ``r`` about x, then by ``p`` about y, then by ``y`` about z (right-handed, degrees): the
matrix applied to the sensor's reading is ``R = Rz(y) Ry(p) Rx(r)``, taking the sensor frame to the
body frame.

- ArduPilot: ``enum Rotation`` in ``libraries/AP_Math/rotations.h`` (ArduPilot/ardupilot; the numbers are
  stored in ``COMPASS_ORIENTn`` and ``AHRS_ORIENTATION`` and never renumbered), applied by
  ``Vector3<T>::rotate`` in ``libraries/AP_Math/vector3.cpp``, a hand-expanded case per entry: e.g.
  ``ROTATION_YAW_90``: ``x' = −y, y' = x``; ``ROTATION_ROLL_90``: ``y' = −z, z' = y``;
  ``ROTATION_PITCH_90``: ``x' = z, z' = −x`` — the columns of ``Rz(90)``, ``Rx(90)``, ``Ry(90)``.
  Entry 38, ``ROTATION_ROLL_90_PITCH_68_YAW_293``, is a measured mounting given there as a literal
  matrix, kept here as printed in ``vector3.cpp`` (to double precision).
- PX4: ``enum Rotation`` and its table ``rot_lookup`` of (roll, pitch, yaw) in degrees in
  ``src/lib/conversion/rotation.h`` (PX4/PX4-Autopilot), turned into a matrix by ``get_rot_matrix``
  (``src/lib/conversion/rotation.cpp``): ``Dcmf(Eulerf(roll, pitch, yaw))``, the same ``Rz Ry Rx``
  (``CAL_MAGn_ROT``, ``SENS_BOARD_ROT``). Entries 0–25 (up to ``ROTATION_PITCH_270``) are the ones every PX4
  release shares (:data:`PX4_EVERY_RELEASE`).

The two enums agree, name for name and number for number, on entries 0–40 (``ROTATION_NONE`` …
``ROTATION_ROLL_90_PITCH_315``), except that PX4 builds entry 38 from its Euler angles (90°, 68°, 293°)
while ArduPilot prints a slightly different literal (0.85° apart). From 41 on they part: ArduPilot has
41 ``PITCH_7``, 42 ``ROLL_45``, 43 ``ROLL_315`` (then ``ROTATION_MAX`` and 100 custom); PX4 has
41 ``ROLL_270_YAW_180``, 42 ``ROLL_270_YAW_270``, 43 ``PITCH_90_YAW_180``, 44 ``PITCH_9_YAW_180``,
45 ``PITCH_45``, 46 ``ROLL_270_YAW_225``, 47 ``ROLL_270_YAW_315``. Some entries are the same rotation
under two names (26 = 14, 27 = 10 in both; PX4's 41 = 31, 42 = 36, 43 = 29): :func:`nearest_rotation`
returns the lowest number.
"""

from __future__ import annotations

import numpy as np

ARDUPILOT_ROTATIONS: dict[int, tuple[str, float, float, float]] = {
    0: ("NONE", 0, 0, 0),
    1: ("YAW_45", 0, 0, 45),
    2: ("YAW_90", 0, 0, 90),
    3: ("YAW_135", 0, 0, 135),
    4: ("YAW_180", 0, 0, 180),
    5: ("YAW_225", 0, 0, 225),
    6: ("YAW_270", 0, 0, 270),
    7: ("YAW_315", 0, 0, 315),
    8: ("ROLL_180", 180, 0, 0),
    9: ("ROLL_180_YAW_45", 180, 0, 45),
    10: ("ROLL_180_YAW_90", 180, 0, 90),
    11: ("ROLL_180_YAW_135", 180, 0, 135),
    12: ("PITCH_180", 0, 180, 0),
    13: ("ROLL_180_YAW_225", 180, 0, 225),
    14: ("ROLL_180_YAW_270", 180, 0, 270),
    15: ("ROLL_180_YAW_315", 180, 0, 315),
    16: ("ROLL_90", 90, 0, 0),
    17: ("ROLL_90_YAW_45", 90, 0, 45),
    18: ("ROLL_90_YAW_90", 90, 0, 90),
    19: ("ROLL_90_YAW_135", 90, 0, 135),
    20: ("ROLL_270", 270, 0, 0),
    21: ("ROLL_270_YAW_45", 270, 0, 45),
    22: ("ROLL_270_YAW_90", 270, 0, 90),
    23: ("ROLL_270_YAW_135", 270, 0, 135),
    24: ("PITCH_90", 0, 90, 0),
    25: ("PITCH_270", 0, 270, 0),
    26: ("PITCH_180_YAW_90", 0, 180, 90),
    27: ("PITCH_180_YAW_270", 0, 180, 270),
    28: ("ROLL_90_PITCH_90", 90, 90, 0),
    29: ("ROLL_180_PITCH_90", 180, 90, 0),
    30: ("ROLL_270_PITCH_90", 270, 90, 0),
    31: ("ROLL_90_PITCH_180", 90, 180, 0),
    32: ("ROLL_270_PITCH_180", 270, 180, 0),
    33: ("ROLL_90_PITCH_270", 90, 270, 0),
    34: ("ROLL_180_PITCH_270", 180, 270, 0),
    35: ("ROLL_270_PITCH_270", 270, 270, 0),
    36: ("ROLL_90_PITCH_180_YAW_90", 90, 180, 90),
    37: ("ROLL_90_YAW_270", 90, 0, 270),
    38: ("ROLL_90_PITCH_68_YAW_293", 90, 68, 293),
    39: ("PITCH_315", 0, 315, 0),
    40: ("ROLL_90_PITCH_315", 90, 315, 0),
    41: ("PITCH_7", 0, 7, 0),
    42: ("ROLL_45", 45, 0, 0),
    43: ("ROLL_315", 315, 0, 0),
}
"""ArduPilot's ``enum Rotation`` (``libraries/AP_Math/rotations.h``): number → (name without
``ROTATION_``, roll, pitch, yaw in degrees). 100 (custom) is a user matrix, not a fixed rotation."""

PX4_ROTATIONS: dict[int, tuple[str, float, float, float]] = {
    **{k: v for k, v in ARDUPILOT_ROTATIONS.items() if k <= 40},
    41: ("ROLL_270_YAW_180", 270, 0, 180),
    42: ("ROLL_270_YAW_270", 270, 0, 270),
    43: ("PITCH_90_YAW_180", 0, 90, 180),
    44: ("PITCH_9_YAW_180", 0, 9, 180),
    45: ("PITCH_45", 0, 45, 0),
    46: ("ROLL_270_YAW_225", 270, 0, 225),
    47: ("ROLL_270_YAW_315", 270, 0, 315),
}
"""PX4's ``enum Rotation`` with ``rot_lookup`` (``src/lib/conversion/rotation.h``): the same names and
numbers as ArduPilot's up to 40, its own from 41."""

FIRMWARE_ROTATIONS = {"ardupilot": ARDUPILOT_ROTATIONS, "px4": PX4_ROTATIONS}
"""Each firmware's table by the name trical gives the firmware (``"ardupilot"``, ``"px4"``)."""

PX4_EVERY_RELEASE = 25
"""PX4's entries 0 to this one (``ROTATION_PITCH_270``) are the entries every PX4 release shares; a log's
later number may mean another rotation in the release that wrote it."""

ARDUPILOT_38 = np.array(
    [
        [0.14303897231223747, 0.36877648650320383, -0.91844638134308709],
        [-0.33213277779664740, -0.85628942146641884, -0.39554550256296522],
        [-0.93232380121551217, 0.36162457008209242, 0.0],
    ]
)
"""``ROTATION_ROLL_90_PITCH_68_YAW_293`` as ``Vector3<T>::rotate`` writes it (``vector3.cpp``)."""


def euler_matrix(roll_deg: float, pitch_deg: float, yaw_deg: float) -> np.ndarray:
    """``Rz(yaw) Ry(pitch) Rx(roll)``: roll first, then pitch, then yaw (PX4 ``Dcmf(Eulerf(…))``,
    ArduPilot's ``Matrix3::from_euler``), angles in degrees; right-angle entries are made exact."""
    r, p, y = np.radians([roll_deg, pitch_deg, yaw_deg])
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    Rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    Ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    Rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    R = Rz @ Ry @ Rx
    R[np.abs(R) < 1e-12] = 0.0
    return R


def ardupilot_matrix(number: int) -> np.ndarray:
    """The matrix ArduPilot applies for ``COMPASS_ORIENTn = number`` (sensor → body).

    Raises
    ------
    KeyError
        For a number not in :data:`ARDUPILOT_ROTATIONS` (100, custom, has no fixed matrix).
    """
    if number == 38:
        return ARDUPILOT_38.copy()
    _, r, p, y = ARDUPILOT_ROTATIONS[number]
    return euler_matrix(r, p, y)


def px4_matrix(number: int) -> np.ndarray:
    """The matrix PX4 applies for ``CAL_MAGn_ROT = number`` (``get_rot_matrix``, sensor → body)."""
    _, r, p, y = PX4_ROTATIONS[number]
    return euler_matrix(r, p, y)


def firmware_matrix(firmware: str, number: int) -> np.ndarray:
    """The matrix a firmware applies for its rotation ``number`` (sensor → body).

    Parameters
    ----------
    firmware : {"ardupilot", "px4"}
    number : int
        ``COMPASS_ORIENTn`` / ``AHRS_ORIENTATION``, or ``CAL_MAGn_ROT`` / ``SENS_BOARD_ROT``.

    Raises
    ------
    ValueError
        An unknown firmware, or a number outside its table (custom rotations among them).
    """
    table = _table(firmware)
    if number not in table:
        raise ValueError(f"{firmware} has no rotation number {number} (known 0–{max(table)})")
    return ardupilot_matrix(number) if firmware == "ardupilot" else px4_matrix(number)


def rotation_name(firmware: str, number: int) -> str:
    """The enum's name of a firmware's rotation number, without ``ROTATION_`` (``ROLL_180_YAW_90``), or
    ``rotation <number>`` for a number not in its table."""
    table = _table(firmware)
    return table[number][0] if number in table else f"rotation {number}"


def _table(firmware: str) -> dict[int, tuple[str, float, float, float]]:
    try:
        return FIRMWARE_ROTATIONS[firmware]
    except KeyError:
        raise ValueError(f"unknown firmware {firmware!r}; known: {', '.join(FIRMWARE_ROTATIONS)}") from None


def angle_between(A: np.ndarray, B: np.ndarray) -> float:
    """The angle in degrees of the rotation ``A Bᵀ`` (how far apart two rotations are):
    ``arccos((trace − 1) / 2)``."""
    c = (np.trace(np.asarray(A) @ np.asarray(B).T) - 1.0) / 2.0
    return float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))


def _same(A: np.ndarray, B: np.ndarray) -> bool:
    return angle_between(A, B) < 0.01


def px4_number(R: np.ndarray) -> int | None:
    """The lowest PX4 number whose matrix is ``R`` (within 0.01°), or None."""
    for number in sorted(PX4_ROTATIONS):
        if _same(px4_matrix(number), R):
            return number
    return None


def ardupilot_number(R: np.ndarray) -> int | None:
    """The lowest ArduPilot number whose matrix is ``R`` (within 0.01°), or None."""
    for number in sorted(ARDUPILOT_ROTATIONS):
        if _same(ardupilot_matrix(number), R):
            return number
    return None


def nearest_number(firmware: str, R) -> tuple[int, float]:
    """The number of the firmware's rotation nearest ``R`` (of equal entries the lowest) and the angle left.

    Parameters
    ----------
    firmware : {"ardupilot", "px4"}
    R : array_like, shape (3, 3)
        A rotation (sensor → body).

    Returns
    -------
    number : int
        ``COMPASS_ORIENTn`` or ``CAL_MAGn_ROT``: this firmware's own number, from its own table (entry 38
        included as that firmware writes it).
    angle_deg : float
        :func:`angle_between` ``R`` and that entry; the caller decides how far is still the same rotation.
    """
    R = np.asarray(R, dtype=float)
    angles = {n: angle_between(R, firmware_matrix(firmware, n)) for n in _table(firmware)}
    best = min(angles, key=lambda n: (round(angles[n], 9), n))
    return best, angles[best]


def _candidates() -> list[tuple[int | None, int | None, str, np.ndarray]]:
    """Every distinct rotation of either firmware: ArduPilot's in its order (with PX4's number for the
    same matrix), then PX4's own. Entry 38 is taken as ArduPilot writes it and, for PX4, as PX4's."""
    out: list[tuple[int | None, int | None, str, np.ndarray]] = []
    for number in sorted(ARDUPILOT_ROTATIONS):
        R = ardupilot_matrix(number)
        if any(_same(R, c[3]) for c in out):
            continue
        px4 = 38 if number == 38 else px4_number(R)
        out.append((number, px4, ARDUPILOT_ROTATIONS[number][0], R))
    for number in sorted(PX4_ROTATIONS):
        R = px4_matrix(number)
        if number == 38 or any(_same(R, c[3]) for c in out):
            continue
        out.append((None, number, PX4_ROTATIONS[number][0], R))
    return out


CANDIDATES = _candidates()
"""(ArduPilot number or None, PX4 number or None, name, matrix) of every distinct firmware rotation."""


def nearest_rotation(Q, firmware: str | None = None) -> tuple[int | None, int | None, str, float]:
    """The firmware rotation nearest a rotation matrix.

    Parameters
    ----------
    Q : array_like, shape (3, 3)
        A rotation (sensor → body), e.g. the one a flight's data show. Where the readings were already
        turned by a firmware rotation T (ArduPilot logs them in the body frame under ``COMPASS_ORIENTn``),
        the setting to store is the nearest to ``Q @ T``.
    firmware : {"ardupilot", "px4"}, optional
        Only the rotations this firmware can apply (PX4 has no ``PITCH_7``, ArduPilot none of PX4's 44–47);
        by default either firmware's.

    Returns
    -------
    ardupilot : int or None
        ``COMPASS_ORIENTn`` of the nearest rotation; None only when the nearest is one of PX4's own
        (41–47) that ArduPilot lacks.
    px4 : int or None
        ``CAL_MAGn_ROT`` of the same rotation, None when PX4 has none (ArduPilot's 41–43).
    name : str
        The enum's name without ``ROTATION_`` (``NONE``, ``YAW_90``, ``ROLL_180``…).
    angle_deg : float
        The angle of the rotation left between ``Q`` and the nearest (:func:`angle_between`).
    """
    Q = np.asarray(Q, dtype=float)
    which = {None: None, "ardupilot": 0, "px4": 1}[firmware]
    candidates = [c for c in CANDIDATES if which is None or c[which] is not None]
    angles = [angle_between(Q, c[3]) for c in candidates]
    best = int(np.argmin(angles))
    ap, px4, name, _ = candidates[best]
    return ap, px4, name, angles[best]


def rotation_matrix(ardupilot: int | None, px4: int | None) -> np.ndarray:
    """The matrix of a firmware rotation given by either number (ArduPilot's first)."""
    if ardupilot is not None:
        return ardupilot_matrix(ardupilot)
    assert px4 is not None, "every rotation has either firmware's number"
    return px4_matrix(px4)
