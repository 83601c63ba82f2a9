"""A phone resting in the six poses, as its browser reports it (the wizard's six flow).

m = X a + y (Georgieva et al. (ESGI'95), eq. (3)) with a = g × the up axis, plus noise, rounded to
the browser's 0.1 m/s², with event timestamps in ms at 60 Hz and a gyroscope at rest in deg/s.
"""

from __future__ import annotations

import numpy as np

from app.calibration import STANDARD_GRAVITY, up_vector

G = STANDARD_GRAVITY
X_TRUE = np.array([[1.02, 0.01, -0.02], [0.005, 0.98, 0.015], [-0.01, 0.02, 1.01]])
Y_TRUE = np.array([0.15, -0.22, 0.31])


def pose_samples(label: str, rng, n: int = 300, rate_hz: float = 60.0, noise: float = 0.03, step: float = 0.1):
    """What a phone's browser reports resting with ``label`` up: m = X a + y (Georgieva et al. eq. (3)) plus noise,
    rounded to the browser's 0.1 m/s², with event timestamps in ms."""
    return direction_samples(up_vector(label), rng, n=n, rate_hz=rate_hz, noise=noise, step=step)


def direction_samples(up, rng, n: int = 300, rate_hz: float = 60.0, noise: float = 0.03, step: float = 0.1):
    """The same resting with any unit direction ``up`` up (the free flow)."""
    m = X_TRUE @ (G * np.asarray(up, dtype=float)) + Y_TRUE
    acc = m + rng.normal(0.0, noise, (n, 3))
    acc = np.round(acc / step) * step
    t_ms = 1000.0 * np.arange(n) / rate_hz
    return {"acc": acc.tolist(), "t_ms": (12345.6 + t_ms).tolist(), "gyr": rng.normal(0, 0.3, (n, 3)).tolist()}
