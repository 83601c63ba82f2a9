"""A person's free-pose session of a phone: still poses in random directions, read with noise and
the settling of a hand that has just let go.

The phone's errors are those of the model a = K (v + o) of Farago, Maczak and Gingl, IEEE Access,
eqs. (17)–(19) (scales within 10 %, misalignments within 5 %, offsets within 0.1 g — the "unit
errors" of an uncalibrated MEMS part).  Each pose's mean reading gets Gaussian noise of the
averaged sensor (``noise_g``) and a per-pose error from hand tremor: with probability
``tremor_rate`` the phone was still settling and its mean is off by ``tremor_g`` in a random
direction.  Fresh poses read the same way are what a person gets on new orientations.
All in units of g.
"""

from __future__ import annotations

import numpy as np

from app.calibration.shared.norm_metrics import norm_errors

from .triangular import draw_parameters, random_unit_vectors, uncalibrate

NOISE_G = 0.0005
"""Noise of a pose's mean reading: a phone's ~3 mg sample noise averaged over a few seconds."""

TREMOR_G = 0.003
TREMOR_RATE = 0.3
"""A third of the poses are read while the phone still settles, off by 3 mg."""


def read_poses(
    rng: np.random.Generator,
    p,
    up,
    *,
    noise_g: float = NOISE_G,
    tremor_g: float = TREMOR_G,
    tremor_rate: float = TREMOR_RATE,
) -> np.ndarray:
    """The mean readings of a phone of parameters ``p`` resting with ``up`` up (unit vectors, (N, 3))."""
    m = uncalibrate(p, up)
    m = m + rng.normal(scale=noise_g, size=m.shape)
    settling = rng.random(len(m)) < tremor_rate
    m[settling] += tremor_g * random_unit_vectors(rng, int(settling.sum()))
    return m


def free_pose_session(rng: np.random.Generator, n: int, **reading) -> tuple[np.ndarray, np.ndarray]:
    """True parameters and the n mean readings of one session (``reading``: see :func:`read_poses`)."""
    p = draw_parameters(rng)
    return p, read_poses(rng, p, random_unit_vectors(rng, n), **reading)


def fresh_error_mg(rng: np.random.Generator, p, apply, *, count: int = 1000, **reading) -> tuple[float, float]:
    """Mean | |a| − 1 g | in mg over ``count`` fresh poses read the same way, calibrated by ``apply``
    and raw: what a person gets on new orientations, with and without the calibration."""
    errors = norm_errors(read_poses(rng, p, random_unit_vectors(rng, count), **reading), apply, 1.0)
    return errors["error_after_mg"], errors["error_before_mg"]
