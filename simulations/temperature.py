"""Synthetic warm-ups for the temperature calibration: a cold board powered on and left still.

The board's temperature follows a first-order warm-up, T(t) = T_end − (T_end − T_start) e^(−t/τ) (the
shape of PX4's thermal calibration procedure: cold soak, then powered and left still), read by the
sensor with a little noise. Each axis's offset is a known cubic of temperature; the noise is either
white (Gaussian) or blocks of a real still recording's noise drawn at random (its correlation in time
kept within each block), and the sample times jitter as a flight controller's logged samples do.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

T_POLY_REF_C = 35.0
"""The temperature the true polynomials are written about."""

ACC_TRUTH = np.array(
    [
        [0.0, 2.0e-3, -6.0e-5, 1.5e-6],  # m/s² about 35 °C: X0, X1, X2, X3 per axis
        [0.0, -1.5e-3, 4.0e-5, 0.0],
        [0.0, 4.0e-3, 3.0e-5, -1.0e-6],
    ]
)
GYR_TRUTH = np.array(
    [
        [1.0e-3, 8.0e-5, -2.0e-6, 5.0e-8],  # rad/s
        [-2.0e-3, -5.0e-5, 1.0e-6, 0.0],
        [5.0e-4, 1.2e-4, 0.0, -4.0e-8],
    ]
)


@dataclass(frozen=True)
class WarmUp:
    time_s: np.ndarray
    temperature_c: np.ndarray
    true_temperature_c: np.ndarray
    acc: np.ndarray
    gyr: np.ndarray
    gravity_body: np.ndarray


def _noise(rng, n: int, source, std: float, block: int) -> np.ndarray:
    if source is None:
        return rng.normal(0.0, std, (n, 3))
    src = np.asarray(source, dtype=float)
    src = src - src.mean(axis=0)
    src = src / src.std(axis=0) * std
    out = np.empty((n, 3))
    block = min(block, len(src))
    for a in range(0, n, block):
        b = min(n, a + block)
        start = int(rng.integers(0, len(src) - (b - a) + 1))
        out[a:b] = src[start : start + (b - a)][:, rng.permutation(3)] * rng.choice([-1.0, 1.0], 3)
    return out


def simulate_warm_up(
    rng: np.random.Generator,
    *,
    duration_s: float = 1200.0,
    sampling_rate_hz: float = 50.0,
    t_start_c: float = 15.0,
    t_end_c: float = 55.0,
    tau_s: float = 400.0,
    acc_truth=ACC_TRUTH,
    gyr_truth=GYR_TRUTH,
    acc_std: float = 0.03,
    gyr_std: float = 1.0e-3,
    noise=None,
    block_s: float = 5.0,
    temp_noise_c: float = 0.02,
    jitter: float = 0.02,
    gravity=(0.0, 0.0, 9.80665),
) -> WarmUp:
    """A still board warming up: readings = gravity (accelerometer) + offset(T) + noise.

    Parameters
    ----------
    rng : numpy.random.Generator
        Seeded.
    noise : array_like (M, 3), optional
        A real still recording's samples: its noise (mean removed, scaled to ``acc_std`` or ``gyr_std``)
        is drawn in blocks of ``block_s``; Gaussian white noise without it.
    jitter : float
        Standard deviation of each sample's time step as a fraction of the interval (a logged FIFO's).
    """
    n = int(duration_s * sampling_rate_hz)
    steps = (1.0 + jitter * rng.standard_normal(n)) / sampling_rate_hz
    time_s = np.concatenate(([0.0], np.cumsum(np.clip(steps, 0.2 / sampling_rate_hz, None))[:-1]))
    true_t = t_end_c - (t_end_c - t_start_c) * np.exp(-time_s / tau_s)
    x = np.vander(true_t - T_POLY_REF_C, 4, increasing=True)
    block = max(1, int(block_s * sampling_rate_hz))
    acc = np.asarray(gravity) + x @ np.asarray(acc_truth).T + _noise(rng, n, noise, acc_std, block)
    gyr = x @ np.asarray(gyr_truth).T + _noise(rng, n, noise, gyr_std, block)
    measured_t = true_t + rng.normal(0.0, temp_noise_c, n)
    return WarmUp(time_s, measured_t, true_t, acc, gyr, np.asarray(gravity, dtype=float))
