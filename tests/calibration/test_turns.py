"""Each cube turn checked as it is made (app/calibration/cube/turns.py, Särkkä et al. section VII-A-1)."""

from __future__ import annotations

import numpy as np
import pytest

from app.calibration.cube import cube24
from app.calibration.cube.turns import MADE_WORDS, check_turn
from tests.cube_phone import phone_cube


def _turn(phone, k):
    """Rates (deg/s) and timestamps of the move from 1-based position k into k + 1, and the rest bias."""
    a = phone.static_segments[k - 1]
    b = phone.static_segments[k]
    bias = phone.gyr[a[0] : a[1]].mean(axis=0)
    return phone.gyr[a[1] : b[0]], phone.t_ms[a[1] : b[0]], bias


def test_every_protocol_turn_passes():
    phone, protocol = phone_cube(5), cube24()
    for k in range(1, 24):
        gyr, t, bias = _turn(phone, k)
        turn = check_turn(gyr, t, protocol, k - 1, bias=bias, gyr_scale=np.pi / 180)
        assert turn.ok, turn.message
        assert turn.made == protocol.rotations[k - 1].label.replace("+", "+90").replace("-", "-90")
        assert turn.max_element_difference < 0.05 and turn.end_error_deg < 5


@pytest.mark.parametrize("made", ["z-", "x+", "x-", "y+", "y-"])
def test_a_wrong_first_turn_is_named_in_words(made):
    gyr, t, bias = _turn(phone_cube(6, wrong_rotations={1: made}), 1)
    turn = check_turn(gyr, t, cube24(), 0, bias=bias, gyr_scale=np.pi / 180)
    assert not turn.ok and turn.made == made[0] + made[1] + "90"
    assert MADE_WORDS[made] in turn.message and turn.message.startswith("wrong turn into position 2")


def test_no_turn_and_a_half_turn():
    phone = phone_cube(7)
    gyr, t, bias = _turn(phone, 1)
    still = check_turn(np.tile(bias, (len(t), 1)), t, cube24(), 0, bias=bias, gyr_scale=np.pi / 180)
    assert not still.ok and "the cube did not turn" in still.message
    half = check_turn(2 * (gyr - bias) + bias, t, cube24(), 0, bias=bias, gyr_scale=np.pi / 180)
    assert not half.ok and half.made == "z180"
    assert f"turned {half.angle_deg:.0f}° about z instead of 90°" in half.message
