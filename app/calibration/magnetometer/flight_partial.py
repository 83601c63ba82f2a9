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

An axis's offset held holds that axis's motor term too (:func:`with_motor_axes`): on that axis the residual is
``b + k p`` plus what the field explains, and with the offset fixed at a stored value that may be stale, the motor
term takes up the difference as far as the power's mean allows. On 200 seeded level flights with offsets stored
5 µT stale (21 partial updates; the level-flight study of ``bench/flight_compass_intervals.py``), the updated motor
terms held the truth inside their 95 % intervals 65 % of the time with only the open numbers held, 95.3 % holding
each held offset's axis too; the updated offsets 97.7 % either way.
"""

from __future__ import annotations

import numpy as np

from ..shared.uncertainty import t_quantile
from .flight_model import MATRIX_PARAMETERS

OFFSET_WORDS = ("the x offset", "the y offset", "the z offset")
MOTOR_WORDS = ("the motor term on x", "the motor term on y", "the motor term on z")
HELD_WORDS = {"M": "the soft iron", "k": "the motor term"}


def undetermined(half, field: float, power, motor: bool, model: str, limits: tuple[float, float, float]) -> dict:
    """Which numbers the intervals leave undetermined: ``{"b": bool[3], "M": bool, "k": bool[3]}``.

    ``half`` is ``(M's, b's, k's half-widths)``; ``limits`` the gates' (offset share of the field, matrix entry,
    motor share of the field over the power's range)."""
    hw_M, hw_b, hw_k = half
    b_limit, m_limit, k_limit = limits
    return {
        "b": np.asarray(hw_b) > b_limit * field,
        "M": bool(model != "offsets" and np.max(hw_M) > m_limit),
        "k": (np.asarray(hw_k) * np.ptp(power) > k_limit * field) if motor else np.zeros(3, dtype=bool),
    }


def with_motor_axes(held: dict) -> dict:
    """``held`` with the motor term held on every axis whose offset is held (module docstring)."""
    return {**held, "k": np.asarray(held["k"], dtype=bool) | np.asarray(held["b"], dtype=bool)}


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
    if motor and np.any(held["k"]):
        mask[nm + 3 :] = held["k"]
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
    half = t_quantile(folds - 1, confidence) * float(d.std(ddof=1)) / np.sqrt(folds)
    return float(d.mean()), half


def held_words(held: dict) -> list[str]:
    """The held numbers in words: "the z offset", "the soft iron", "the motor term on z"…"""
    words = [w for w, h in zip(OFFSET_WORDS, held["b"]) if h]
    words += [HELD_WORDS["M"]] if held["M"] else []
    return words + motor_words(held["k"])


def motor_words(axes) -> list[str]:
    """The motor term's axes in words: "the motor term" for all three, else each axis's; an old result's single
    bool stands for all three."""
    axes = [bool(axes)] * 3 if isinstance(axes, bool) else [bool(a) for a in axes]
    return [HELD_WORDS["k"]] if all(axes) else [w for w, a in zip(MOTOR_WORDS, axes) if a]


__all__ = ["fixed_entries", "held_words", "improvement", "motor_words", "undetermined", "with_motor_axes"]
