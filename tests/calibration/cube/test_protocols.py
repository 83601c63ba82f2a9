"""Protocols: cube24 of docs/methods.md, ferraris, explicit lists."""

import numpy as np
import pytest

from app.calibration import CalibrationError
from app.calibration.cube import quaternion as quat
from app.calibration.cube.protocols import (
    CUBE24_ROTATIONS,
    CUBE24_UPS,
    cube24,
    explicit_protocol,
    ferraris,
    get_protocol,
)


def _rot(axis, deg):
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    i = "xyz".index(axis)
    R = np.eye(3)
    j, k = [a for a in range(3) if a != i]
    R[j, j], R[j, k], R[k, j], R[k, k] = c, -s, s, c
    return R


def test_cube24_rotation_sequence_produces_the_design_up_axes():
    # Independent of the module: rotate about calibration-frame axes, R ← Rot R, read Rᵀ e_z.
    R = np.eye(3)
    ups = []
    for k in range(24):
        v = R.T @ np.array([0.0, 0.0, 1.0])
        i = int(np.argmax(np.abs(v)))
        assert abs(abs(v[i]) - 1) < 1e-12
        ups.append(("+" if v[i] > 0 else "-") + "xyz"[i])
        if k < 23:
            r = CUBE24_ROTATIONS[k]
            R = _rot(r[0], 90.0 if r[1] == "+" else -90.0) @ R
    assert ups == ["+z"] * 4 + ["-x"] * 4 + ["-y"] * 4 + ["-z"] * 4 + ["+x"] * 4 + ["+y"] * 4
    assert tuple(ups) == CUBE24_UPS
    assert len(CUBE24_ROTATIONS) == 23


def test_cube24_protocol_attitudes_and_quaternions():
    p = cube24()
    assert p.n_positions == 24 and p.heading_known
    assert p.ups == CUBE24_UPS
    np.testing.assert_allclose(p.attitudes[0], np.eye(3), atol=1e-15)
    np.testing.assert_allclose(quat.to_matrix(p.quaternions), p.attitudes, atol=1e-12)
    # All 24 attitudes are distinct: the whole rotation group of the cube.
    flat = np.round(p.attitudes.reshape(24, 9), 6)
    assert len({tuple(r) for r in flat}) == 24
    assert p.describe_rotation(3) == "rotation 4 (x+, from position 4 into position 5)"


def test_ferraris_full_turns_are_on_the_negative_branch():
    # imucal's order: the six rests, then each turn about the axis that points up, rest to rest.
    p = ferraris()
    assert p.ups == ("+x", "-x", "+y", "-y", "+z", "-z", "+x", "+x", "+y", "+y", "+z", "+z")
    assert not p.heading_known and p.full_turns and p.reading_positions is None
    assert p.rotations[:6] == (None,) * 6 and p.rotations[7] is None and p.rotations[9] is None
    for axis, k in enumerate((6, 8, 10)):
        assert p.rotations[k].angle_deg == -360.0  # clockwise seen from above, as imucal's x_rot
        np.testing.assert_allclose(p.quaternions[k + 1], -p.quaternions[k], atol=1e-12)
        np.testing.assert_allclose(p.attitudes[k + 1], p.attitudes[k], atol=1e-12)
        # About the sensor axis that points up: the vertical of the calibration frame.
        np.testing.assert_allclose(p.attitudes[k].T @ p.rotations[k].axis, np.eye(3)[axis], atol=1e-12)
        np.testing.assert_allclose(p.rotations[k].axis, [0, 0, 1], atol=1e-12)


def test_explicit_protocols_and_their_errors():
    p = explicit_protocol(["z+", "x+", "y-180"])
    assert p.ups == ("+z", "+z", "+x", "-x")
    assert get_protocol({"rotations": ["z+", "x+"], "ups": ["+z", "+z", "+x"]}).n_positions == 3
    with pytest.raises(CalibrationError, match="protocol says"):
        explicit_protocol(["z+", "x+"], ups=["+z", "+z", "-y"])
    with pytest.raises(CalibrationError, match="unknown rotation"):
        explicit_protocol(["w+"])
    with pytest.raises(CalibrationError, match="free move"):
        explicit_protocol(["z+", "free"])
    with pytest.raises(CalibrationError, match="unknown protocol"):
        get_protocol("cube25")
