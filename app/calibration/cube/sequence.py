"""Sequence checks (Särkkä et al., IEEE Sensors Journal 17(11) 2017, section VII-A-1).

The end attitude of every rotation is known from the protocol; the forward solution of eq. (2)
with the pre-adjusted rates approximates it.  If any element of the integrated end quaternion
differs from the protocol's by more than 0.1, the rotation was not the one the protocol expects
(in the paper's calibrations the differences stayed below 0.05).  The accelerometer gives a
second, independent check: in each position the axis it sees pointing up must be the expected
face.  The rotations before the first mistake can still be used for the calibration.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..shared.orientations import nearest_orientation
from . import quaternion as quat
from .protocols import Protocol

MAX_ELEMENT_DIFFERENCE = 0.1
"""Särkkä et al., IEEE Sensors Journal 17(11) 2017, section VII-A-1: a larger difference in any
quaternion element flags a wrong rotation.

The paper's rotations are 90°; a scale error of the pre-adjusted gyroscope grows with the angle,
so for larger rotations the tolerance grows in proportion (0.1 per 90°, e.g. 0.4 for a 360° turn
of the ferraris protocol — still far below the difference 2 between a full turn and none)."""


def element_tolerance(angle_deg: float) -> float:
    """Largest quaternion element difference accepted for a rotation of this angle."""
    return MAX_ELEMENT_DIFFERENCE * max(1.0, abs(angle_deg) / 90.0)


FACE_MAX_ANGLE_DEG = 45.0
"""The up axis seen by the accelerometer is the nearest axis within this angle."""


@dataclass(frozen=True)
class SequenceCheck:
    """The check of every transition and the first mistake.

    Attributes
    ----------
    rotations : tuple of dict
        One entry per transition: ``rotation`` (1-based), ``label``, ``from_position``,
        ``to_position``, ``expected_up``, ``observed_up``, ``max_element_difference`` (None for
        free moves), ``end_error_deg``, ``saturated``, ``ok`` and ``message``.
    first_wrong : int or None
        1-based number of the first wrong rotation.
    """

    rotations: tuple
    first_wrong: int | None

    @property
    def ok(self) -> bool:
        return self.first_wrong is None

    @property
    def valid_positions(self) -> int:
        """How many leading positions are trustworthy (all before the mistake)."""
        return len(self.rotations) + 1 if self.first_wrong is None else self.first_wrong

    def reason(self) -> str | None:
        """The message naming the first wrong rotation, or None."""
        if self.first_wrong is None:
            return None
        return self.rotations[self.first_wrong - 1]["message"]


def normalised_directions(means: np.ndarray, gravity: float) -> np.ndarray:
    """Directions of the accelerometer means in a roughly calibrated frame.

    Physical units (norms within 30 % of ``gravity``) are used as they are; raw units are
    centred and scaled per axis by the mid-range of the position means.
    """
    norms = np.linalg.norm(means, axis=1)
    if np.all(np.abs(norms - gravity) < 0.3 * gravity):
        return means
    lo, hi = means.min(axis=0), means.max(axis=0)
    half = np.where(hi > lo, 0.5 * (hi - lo), 1.0)
    return (means - 0.5 * (hi + lo)) / half


FLAT_TOP_STEP = 4
"""A flat top is clipping when it is entered or left by a step of more than this many quantisation
steps: a natural peak of quantised rates (16-bit gyroscopes repeat their peak value too) is
reached by steps of one or two."""


def _flat_tops(x: np.ndarray, v: float) -> np.ndarray:
    """Samples of the runs of at least three at the value v that start or end with a steep step."""
    hit = x == v
    mask = np.zeros(len(x), dtype=bool)
    d = np.abs(np.diff(x))
    step = d[d > 0].min() if np.any(d > 0) else 0.0
    edges = np.diff(np.concatenate([[0], hit.astype(np.int8), [0]]))
    for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)):
        steep = (a > 0 and abs(x[a] - x[a - 1]) > FLAT_TOP_STEP * step) or (
            b < len(x) and abs(x[b] - x[b - 1]) > FLAT_TOP_STEP * step
        )
        if b - a >= 3 and steep:
            mask[a:b] = True
    return mask


def saturated_samples(gyr: np.ndarray, gyro_range: float | None) -> np.ndarray:
    """Boolean mask of samples at the gyroscope's range (clipped).

    With ``gyro_range`` given: any axis at or beyond 99.9 % of it.  Otherwise: runs of at least
    three samples at the extreme value of an axis, entered or left by a steep step (a flat top).
    """
    g = np.asarray(gyr, dtype=float)
    if gyro_range is not None:
        return np.any(np.abs(g) >= 0.999 * float(gyro_range), axis=1)
    mask = np.zeros(len(g), dtype=bool)
    for k in range(3):
        for v in (g[:, k].max(), g[:, k].min()):
            if abs(v) > 0:
                mask |= _flat_tops(g[:, k], v)
    return mask


def _transition(rates, k: int, protocol: Protocol, observed_up, h: float, gyro_bias, saturated: bool):
    """The record of transition k (0-based): the face that came up and, for a known rotation, the
    integrated attitude against the protocol's.  Returns the entry, whether the face matched and
    whether the gyroscope agreed."""
    rot = protocol.rotations[k] if k < len(protocol.rotations) else None
    expected_up = protocol.ups[k + 1] if k + 1 < protocol.n_positions else protocol.ups[0]
    entry = {
        "rotation": k + 1,
        "label": "return to position 1" if k >= len(protocol.rotations) else (rot.label if rot else "free"),
        "from_position": k + 1,
        "to_position": k + 2,
        "expected_up": expected_up,
        "observed_up": observed_up,
        "max_element_difference": None,
        "end_error_deg": None,
        "saturated": saturated,
    }
    gyro_ok = True
    if rot is not None:
        q0 = protocol.quaternions[k]
        q_exp = protocol.quaternions[k + 1]
        q_end = quat.integrate(rates - gyro_bias, h, q0)[-1]
        diff = float(np.max(np.abs(q_end - q_exp)))
        entry["max_element_difference"] = diff
        entry["end_error_deg"] = float(np.degrees(2 * np.arccos(min(1.0, abs(float(q_end @ q_exp))))))
        entry["end_quaternion"] = q_end.tolist()
        entry["expected_quaternion"] = q_exp.tolist()
        entry["tolerance"] = element_tolerance(rot.angle_deg)
        gyro_ok = diff <= entry["tolerance"]
    return entry, observed_up == expected_up, gyro_ok


def _transition_message(entry: dict, k: int, wrong: bool, face_ok: bool, gyro_ok: bool) -> str:
    """What the check of one transition tells: the mistake, the range reached, or ok."""
    to_pos = k + 2
    name = f"rotation {k + 1} ({entry['label']}, from position {k + 1} into position {to_pos})"
    if wrong:
        parts = []
        if not gyro_ok:
            parts.append(
                f"the gyroscope ends {entry['end_error_deg']:.0f}° from the protocol's attitude (largest "
                f"quaternion element difference {entry['max_element_difference']:.2f} > {entry['tolerance']:.2g})"
            )
        if not face_ok:
            parts.append(
                f"position {to_pos} has {entry['observed_up'] or 'no axis'} up instead of {entry['expected_up']}"
            )
        return (
            f"{name} is not the protocol's rotation: "
            + " and ".join(parts)
            + f"; it led into position {to_pos}. The calibration uses positions 1–{k + 1} and the "
            f"rotations before it; redo the sequence from position {k + 1} to use all of them"
        )
    if entry["saturated"]:
        return (
            f"{name} reached the gyroscope's range (clipped samples): it is left out of the gyroscope "
            "calibration; turn more slowly"
        )
    return f"{name} ok"


def check_sequence(
    gyr: np.ndarray,
    acc_means: np.ndarray,
    rotations: tuple,
    protocol: Protocol,
    *,
    sampling_rate_hz: float,
    gyro_bias: np.ndarray,
    gravity: float,
    saturated: np.ndarray | None = None,
) -> SequenceCheck:
    """Check every transition of a recording against its protocol (Särkkä et al., IEEE Sensors Journal
    17(11) 2017, section VII-A-1).

    Parameters
    ----------
    gyr : numpy.ndarray, shape (N, 3)
        Raw (pre-adjusted) rates, rad/s.
    acc_means : numpy.ndarray, shape (P, 3)
        Accelerometer mean of each still position.
    rotations : sequence of (int, int)
        Sample interval of each transition (P − 1 of them).
    protocol : Protocol
    sampling_rate_hz : float
    gyro_bias : numpy.ndarray, shape (3,)
        Bias for the pre-adjustment (the mean rate of the still positions).
    gravity : float
        Reference magnitude in the unit of ``acc_means``.
    saturated : numpy.ndarray of bool, optional
        Samples at the gyroscope's range.

    Returns
    -------
    SequenceCheck
    """
    h = 1.0 / float(sampling_rate_hz)
    dirs = normalised_directions(np.asarray(acc_means, float), gravity)
    observed = [nearest_orientation(d, FACE_MAX_ANGLE_DEG) for d in dirs]
    out = []
    first_wrong = None
    for k, (a, b) in enumerate(rotations):
        entry, face_ok, gyro_ok = _transition(
            gyr[a:b], k, protocol, observed[k + 1], h, gyro_bias, bool(saturated is not None and saturated[a:b].any())
        )
        # A saturated rotation that lands on the right face is a range problem, not a mistake.
        wrong = (not face_ok) or (not gyro_ok and not (entry["saturated"] and face_ok))
        entry["ok"] = not wrong and not entry["saturated"]
        entry["message"] = _transition_message(entry, k, wrong, face_ok, gyro_ok)
        if wrong and first_wrong is None:
            first_wrong = k + 1
        out.append(entry)
    return SequenceCheck(rotations=tuple(out), first_wrong=first_wrong)
