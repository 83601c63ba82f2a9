"""Seeded drifts of a calibrated device: what a check (:mod:`app.calibration.check`) must tell apart.

A device calibrated in one session is recorded again in another; between them its accelerometer's offsets or
scales may have moved (a knock, a temperature, the solder's stress), its compass's hard iron (a magnet added to a
case), or the compass may sit in a field that changes with its attitude (steel or a motor beside it), which no
ellipsoid fits. Each function returns the new session's readings, the truth given.
"""

from __future__ import annotations

import numpy as np

from .free_poses import read_poses
from .magnetometer import EARTH_FIELD_UT, directions
from .triangular import random_unit_vectors


def drifted_poses(
    rng: np.random.Generator,
    p,
    n: int,
    *,
    offset_g=(0.0, 0.0, 0.0),
    scale=(1.0, 1.0, 1.0),
) -> np.ndarray:
    """The mean readings (g) of ``n`` still poses in random directions of a phone of parameters ``p``
    (:mod:`simulations.free_poses`) whose raw readings have since moved by ``offset_g`` and been scaled per axis by
    ``scale``: ``m' = diag(scale) m + offset``."""
    m = read_poses(rng, p, random_unit_vectors(rng, n))
    return m * np.asarray(scale, dtype=float) + np.asarray(offset_g, dtype=float)


def disturbed_turn(
    rng: np.random.Generator,
    M: np.ndarray,
    b,
    *,
    strength: float = 0.7,
    width: float = 0.15,
    field_ut: float = EARTH_FIELD_UT,
    noise_ut: float = 0.3,
    n: int = 300,
) -> np.ndarray:
    """Raw readings of a turn in a field that changes with the device's attitude: where the field points near the
    direction w (within about ``width`` of 1 − cos), a source beside the compass adds up to ``strength`` × F along w,
    ``h' = h + s F exp(−(1 − û·w) / width) w``; no ellipsoid fits it."""
    u = directions(rng, n)
    w = np.array([0.0, 0.6, 0.8])
    h = field_ut * u + strength * field_ut * np.exp(-(1.0 - u @ w) / width)[:, None] * w
    return h @ np.linalg.inv(M).T + np.asarray(b, dtype=float) + rng.normal(0.0, noise_ut, (n, 3))
