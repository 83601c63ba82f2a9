"""Still gyroscope captures of a wizard session with a known bias (app.calibration.still.gyro_bias).

Each capture k reads b + w_k + e_ki: the session's bias b, a wander w_k of the bias between
captures (independent, normal, standard deviation ``wander``: the bias instability and turn-on
effects of IEEE Std 952-1997, Annex C, seen at the spacing of the captures) and white noise e_ki
of standard deviation ``noise`` per sample.
"""

from __future__ import annotations

import numpy as np


def simulate_captures(
    rng: np.random.Generator, *, bias, n_captures: int, n_samples: int, noise: float, wander: float
) -> list[np.ndarray]:
    """The samples of ``n_captures`` still captures, each of shape (n_samples, 3), in the unit of ``bias``.

    Parameters
    ----------
    rng : numpy.random.Generator
        Seeded.
    bias : array_like of 3
        The session's bias b.
    n_captures, n_samples : int
    noise : float
        White noise per sample (standard deviation).
    wander : float
        Standard deviation of each capture's offset from b.
    """
    b = np.asarray(bias, dtype=float).reshape(3)
    return [b + rng.normal(0.0, wander, 3) + rng.normal(0.0, noise, (n_samples, 3)) for _ in range(n_captures)]


def capture_statistics(captures: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each capture's mean, standard deviation (ddof 1) and count: what a session keeps per capture."""
    return (
        np.array([c.mean(axis=0) for c in captures]),
        np.array([c.std(axis=0, ddof=1) for c in captures]),
        np.array([len(c) for c in captures]),
    )
