"""One turn of a guided cube sequence, checked as it happens (Särkkä et al. (IEEE Sensors J. 2017), VII-A-1).

The wizard checks each rotation right after it is made, so that a wrong turn is named at once
instead of spoiling the rest of the sequence: the gyroscope's rates over the move are integrated
by Särkkä et al. eq. (2) from the protocol's attitude of the position left, and the end quaternion must
match the protocol's next attitude within 0.1 per element (the paper's test).  When it does not,
the rotation actually made is named in words, from the integrated net rotation.

Browser events arrive at uneven times, so the rates are first put on a uniform grid at the
median event interval.  Phones report the gyroscope in deg/s (W3C) but some browsers have sent
rad/s: a turn that fails in the declared unit and passes in the other one tells which it was.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..shared.capture import on_uniform_grid
from ..shared.errors import CalibrationError
from . import quaternion as quat
from .protocols import Protocol
from .sequence import element_tolerance

DEG = np.pi / 180.0

TURN_WORDS = {
    "z+": "turn the cube a quarter counter-clockwise (seen from above) on the plane",
    "z-": "a quarter clockwise turn (seen from above) on the plane",
    "x+": "tip the cube 90° over the jig edge (about x, its top moving towards −y)",
    "x-": "tip the cube 90° over the jig edge (about x, its top moving towards +y)",
    "y+": "tip the cube 90° about y (its top moving towards +x)",
    "y-": "tip the cube 90° about y (its top moving towards −x)",
}
"""What each body rotation (calibration frame, right-hand rule, docs/methods.md) means to a person."""

MADE_WORDS = {
    "z+": "a quarter turn counter-clockwise (seen from above)",
    "z-": "a quarter turn clockwise (seen from above)",
    "x+": "a tip about x with its top moving towards −y",
    "x-": "a tip about x with its top moving towards +y",
    "y+": "a tip about y with its top moving towards +x",
    "y-": "a tip about y with its top moving towards −x",
}
"""The same rotations, as something that was done."""


@dataclass(frozen=True)
class TurnCheck:
    """The check of one transition.

    Attributes
    ----------
    ok : bool
        The end attitude matches the protocol's within Särkkä et al.'s tolerance.
    expected : str
        The protocol's rotation label (``z+``, ``x-`` …).
    made : str
        The net rotation made: the nearest axis and sign with 90 (``z-90``), ``z180`` for a half
        turn, or ``none`` below 20°.
    angle_deg : float
        Angle of the net rotation made.
    end_error_deg : float
        Angle between the integrated and the protocol's end attitudes.
    max_element_difference : float
        Largest difference of a quaternion element (Särkkä et al. section VII-A-1).
    gyr_scale : float
        Factor that brought the rates to rad/s (π/180 for deg/s); the other unit's when it fitted.
    message : str
        For a person: what was done and what to do.
    """

    ok: bool
    expected: str
    made: str
    angle_deg: float
    end_error_deg: float
    max_element_difference: float
    gyr_scale: float
    message: str

    def to_dict(self) -> dict:
        return {
            k: getattr(self, k)
            for k in (
                "ok",
                "expected",
                "made",
                "angle_deg",
                "end_error_deg",
                "max_element_difference",
                "gyr_scale",
                "message",
            )
        }


def uniform_rates(gyr, t_ms) -> tuple[np.ndarray, float]:
    """Rates on a uniform grid at the median event interval, and that interval in seconds."""
    w = np.asarray(gyr, dtype=float)
    t = np.asarray(t_ms, dtype=float)
    if w.ndim != 2 or w.shape[1] != 3 or len(w) != len(t) or len(w) < 2:
        raise CalibrationError("a turn needs gyr (N×3) and t_ms (N), N ≥ 2, one timestamp per sample")
    if np.any(np.diff(t) < 0) or not np.all(np.isfinite(w)) or not np.all(np.isfinite(t)):
        raise CalibrationError("the turn's timestamps must increase and its rates be finite numbers")
    (rates,), h_ms = on_uniform_grid(t, w)
    return rates, h_ms / 1000.0


def _net_rotation(q_from: np.ndarray, q_to: np.ndarray) -> tuple[str, float]:
    """The rotation from one attitude to another in the calibration frame: ``z-90`` and its angle."""
    dq = quat.multiply(q_to, quat.conjugate(q_from))
    if dq[0] < 0:
        dq = -dq
    angle = float(np.degrees(2 * np.arctan2(np.linalg.norm(dq[1:]), dq[0])))
    if angle < 20.0:
        return "none", angle
    axis = dq[1:] / np.linalg.norm(dq[1:])
    k = int(np.argmax(np.abs(axis)))
    if angle >= 135.0:  # a half turn: its sense cannot be told from the end attitude
        return f"{'xyz'[k]}180", angle
    return f"{'xyz'[k]}{'+' if axis[k] > 0 else '-'}90", angle


def _describe(made: str, angle_deg: float) -> str:
    """What the person did, in words: ``the cube made a quarter turn clockwise (seen from above)``."""
    if made == "none":
        return "the cube did not turn"
    if made.endswith("180") or abs(angle_deg - 90.0) > 25.0:
        return f"the cube turned {angle_deg:.0f}° about {made[0]} instead of 90°"
    return f"the cube made {MADE_WORDS[made[:2]]}"


def check_turn(gyr, t_ms, protocol: Protocol, k: int, *, bias, gyr_scale: float) -> TurnCheck:
    """Check transition ``k`` (0-based: from position k + 1 into position k + 2) of a protocol.

    Parameters
    ----------
    gyr : array_like, shape (N, 3)
        Rates over the move, in the unit that ``gyr_scale`` converts to rad/s.
    t_ms : array_like, shape (N,)
        Event timestamps in milliseconds.
    protocol : Protocol
    k : int
        0-based transition number.
    bias : array_like, shape (3,)
        The rates at rest (the mean of the position left), in the unit of ``gyr``.
    gyr_scale : float
        π/180 for deg/s, 1 for rad/s: the declared unit.

    Returns
    -------
    TurnCheck
        ``ok`` false with a message naming the turn made and the one to make; when the turn fits
        only with the other unit, ``ok`` is true and ``gyr_scale`` is that unit's.
    """
    rot = protocol.rotations[k]
    if rot is None:  # pragma: no cover - cube24 has no free moves
        raise CalibrationError(f"transition {k + 1} of {protocol.name} is a free move: nothing to check")
    rates, h = uniform_rates(gyr, t_ms)
    rates = rates - np.asarray(bias, dtype=float)
    q0, q_exp = protocol.quaternions[k], protocol.quaternions[k + 1]
    tolerance = element_tolerance(rot.angle_deg)
    other = 1.0 if gyr_scale != 1.0 else DEG

    def attempt(scale):
        q_end = quat.integrate(rates * scale, h, q0)[-1]  # Särkkä et al. eq. (2)
        diff = float(np.max(np.abs(q_end - q_exp)))
        return q_end, diff

    q_end, diff = attempt(gyr_scale)
    scale = gyr_scale
    if diff > tolerance:
        q_alt, diff_alt = attempt(other)
        if diff_alt <= tolerance:
            q_end, diff, scale = q_alt, diff_alt, other
    made, angle = _net_rotation(q0, q_end)
    end_error = float(np.degrees(2 * np.arccos(min(1.0, abs(float(q_end @ q_exp))))))
    ok = diff <= tolerance
    expected = rot.label
    if ok:
        message = f"position {k + 1} → {k + 2}: {expected} ok"
    else:
        message = (
            f"wrong turn into position {k + 2}: {_describe(made, angle)}. Put it back in position "
            f"{k + 1}, then {TURN_WORDS.get(expected, expected)}"
        )
    return TurnCheck(
        ok=ok,
        expected=expected,
        made=made,
        angle_deg=angle,
        end_error_deg=end_error,
        max_element_difference=diff,
        gyr_scale=scale,
        message=message,
    )
