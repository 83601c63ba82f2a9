"""Seeded compass sessions: a device with known hard and soft iron turned in a uniform field.

The readings are ``m = M⁻¹ h + b + ε`` (the model of :mod:`app.calibration.magnetometer`), with
``h`` of magnitude F in directions drawn uniformly over the sphere — or over the part of it a
partial turn reaches — and ε white noise of ``noise_ut`` per axis.
"""

from __future__ import annotations

import numpy as np

EARTH_FIELD_UT = 48.0
"""A mid-latitude field magnitude (Europe, 2025: 47–50 µT)."""


def random_soft_iron(rng: np.random.Generator, size: float = 0.08) -> np.ndarray:
    """A symmetric positive-definite M near the identity: gains and cross-couplings of ±``size``."""
    E = rng.uniform(-size, size, (3, 3))
    return np.eye(3) + 0.5 * (E + E.T)


def directions(rng: np.random.Generator, n: int, *, max_polar_deg: float = 180.0) -> np.ndarray:
    """``n`` unit directions uniform over the cap within ``max_polar_deg`` of +z (180: the sphere)."""
    lowest = np.cos(np.radians(max_polar_deg))
    z = rng.uniform(lowest, 1.0, n)
    phi = rng.uniform(0.0, 2.0 * np.pi, n)
    r = np.sqrt(1.0 - z * z)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def simulate_turn(
    rng: np.random.Generator,
    M: np.ndarray,
    b,
    *,
    field_ut: float = EARTH_FIELD_UT,
    noise_ut: float = 0.3,
    n: int = 400,
    max_polar_deg: float = 180.0,
) -> np.ndarray:
    """Raw readings ``M⁻¹ h + b + ε`` of a turn, shape (n, 3)."""
    h = field_ut * directions(rng, n, max_polar_deg=max_polar_deg)
    return h @ np.linalg.inv(M).T + np.asarray(b, dtype=float) + rng.normal(0.0, noise_ut, (n, 3))


def simulate_session(
    seed: int,
    *,
    n: int = 400,
    noise_ut: float = 0.3,
    max_polar_deg: float = 180.0,
    field_ut: float = EARTH_FIELD_UT,
    hard_iron_ut: float = 60.0,
):
    """One session with its truth: ``(readings, M, b)`` — a phone-like hard iron of tens of µT."""
    rng = np.random.default_rng(seed)
    M = random_soft_iron(rng)
    b = rng.uniform(-hard_iron_ut, hard_iron_ut, 3)
    return simulate_turn(rng, M, b, field_ut=field_ut, noise_ut=noise_ut, n=n, max_polar_deg=max_polar_deg), M, b


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A rotation matrix uniform over SO(3) (the QR of a Gaussian matrix, signs fixed)."""
    Q, R = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q * np.sign(np.diag(R))
    return Q if np.linalg.det(Q) > 0 else -Q


def simulate_rests(
    rng: np.random.Generator,
    M: np.ndarray,
    b,
    *,
    field_ut: float = EARTH_FIELD_UT,
    inclination_deg: float = 64.0,
    gravity: float = 9.81,
    n: int = 6,
    noise_ut: float = 0.0,
):
    """Still moments of the device in random attitudes: ``(acc_mean, mag_mean)`` pairs.

    In the local north-east-down frame the field is ``F (cos I, 0, sin I)`` and the specific force
    at rest ``(0, 0, −g)`` (it points up); the device in attitude R (device → local) reads
    ``Rᵀ f`` on its accelerometer and ``M⁻¹ Rᵀ h + b`` on its magnetometer.
    """
    inc = np.radians(inclination_deg)
    h_local = field_ut * np.array([np.cos(inc), 0.0, np.sin(inc)])
    f_local = np.array([0.0, 0.0, -gravity])
    Minv = np.linalg.inv(M)
    rests = []
    for _ in range(n):
        R = random_rotation(rng)
        mag = Minv @ (R.T @ h_local) + np.asarray(b, dtype=float) + rng.normal(0.0, noise_ut, 3)
        rests.append((R.T @ f_local, mag))
    return rests
