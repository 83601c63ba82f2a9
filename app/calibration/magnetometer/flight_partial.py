"""Update what a flight determines, keep the rest: the compass from a flight where some of its numbers are not
determined.

A flight near level for minutes bounds the offsets' horizontal parts and the motor term long before the vertical
offset or the soft iron. Where the chosen model's 95 % intervals leave some numbers undetermined (the gates of
:mod:`.flight`: an offset's half-width above 5 % of the field, an entry of M's above 0.05, the motor term's over
the power's range above 5 % of the field), those are held at the firmware's stored values and the others refitted
with them fixed: the linear system ``u = S e + b + k p`` (S = M⁻¹, :mod:`.flight_model`) solved for its free
entries, ``A_ff θ_f = g_f − A_fx θ_x``, the held ones ``θ_x`` moved to the right-hand side
(:func:`.flight_model.solve_normal` with ``held``). Its intervals are the
same block jackknife over the free entries (the held ones have none: they are the firmware's), and the update is
judged on flight segments left out, fold by fold: it stands where it lowers the heading error beyond the
interval of that improvement (Student's t over the folds' differences).
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from .flight_model import MATRIX_PARAMETERS

OFFSET_WORDS = ("the x offset", "the y offset", "the z offset")
HELD_WORDS = {"M": "the soft iron", "k": "the motor term"}


def undetermined(half, field: float, power, motor: bool, model: str, limits: tuple[float, float, float]) -> dict:
    """Which numbers the intervals leave undetermined: ``{"b": bool[3], "M": bool, "k": bool}``.

    ``half`` is ``(M's, b's, k's half-widths)``; ``limits`` the gates' (offset share of the field, matrix entry,
    motor share of the field over the power's range)."""
    hw_M, hw_b, hw_k = half
    b_limit, m_limit, k_limit = limits
    return {
        "b": np.asarray(hw_b) > b_limit * field,
        "M": bool(model != "offsets" and np.max(hw_M) > m_limit),
        "k": bool(motor and np.max(hw_k) * np.ptp(power) > k_limit * field),
    }


def fixed_entries(model: str, motor: bool, held: dict, stored: dict) -> tuple[np.ndarray, np.ndarray]:
    """The mask of the linear parameters ``θ = (S's entries, b, k)`` held, and their values from the stored
    calibration (``stored``: ``M``, ``b``, ``k`` in the fit's frame)."""
    pairs = MATRIX_PARAMETERS[model]
    nm = len(pairs)
    size = nm + 3 + (3 if motor else 0)
    mask, values = np.zeros(size, dtype=bool), np.zeros(size)
    if held["M"]:
        S = np.linalg.inv(np.asarray(stored["M"], dtype=float))
        mask[:nm] = True
        values[:nm] = [S[i, j] for i, j in pairs]
    mask[nm : nm + 3] = held["b"]
    values[nm : nm + 3] = stored["b"]
    if motor and held["k"]:
        mask[nm + 3 :] = True
        values[nm + 3 :] = stored["k"]
    return mask, values


def improvement(before_deg, after_deg, fold: np.ndarray, folds: int, confidence: float) -> tuple[float, float]:
    """The rms heading error's drop from ``before`` to ``after`` on the segments left out, fold by fold: its mean
    and the half-width of its interval (Student's t at ``folds − 1``)."""
    drops = []
    for k in range(folds):
        out = fold == k
        rms = [float(np.sqrt(np.mean(np.square(x[out])))) for x in (before_deg, after_deg)]
        drops.append(rms[0] - rms[1])
    d = np.asarray(drops)
    half = float(stats.t.ppf(0.5 + confidence / 2.0, folds - 1) * d.std(ddof=1) / np.sqrt(folds))
    return float(d.mean()), half


def held_words(held: dict) -> list[str]:
    """The held numbers in words: "the z offset", "the soft iron"…"""
    words = [w for w, h in zip(OFFSET_WORDS, held["b"]) if h]
    return words + [HELD_WORDS[key] for key in ("M", "k") if held[key]]


__all__ = ["fixed_entries", "held_words", "improvement", "undetermined"]
