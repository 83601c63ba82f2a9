"""Noise calibration bodies (``method: "noise"``) built from simulated sensors, for the plot and
export tests: the overlapping Allan deviation is computed here with numpy, independently of the
core, and the terms are the simulation's truth.

The overlapping estimator: σ²(τ) = Σ (θ[k+2m] − 2 θ[k+m] + θ[k])² / (2 τ² (n − 2m)), θ the
integrated rate, τ = m / fs (IEEE Std 952-1997, Annex C, eq. C.10 ff.).
"""

from __future__ import annotations

import numpy as np
from scipy.stats import chi2

UNITS = {"acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}


def overlapping_adev(rate: np.ndarray, fs: float, per_decade: int = 8) -> tuple[np.ndarray, ...]:
    """τ (s), σ (n × 3) and its 95 % band (lo, hi) from chi-square with n/m degrees of freedom."""
    n = rate.shape[0]
    theta = np.vstack([np.zeros((1, rate.shape[1])), np.cumsum(rate, axis=0) / fs])
    ms = np.unique(np.round(np.logspace(0, np.log10(n // 10), per_decade * int(np.log10(n // 10)) + 1)).astype(int))
    tau = ms / fs
    value = np.empty((ms.size, rate.shape[1]))
    for j, m in enumerate(ms):
        d = theta[2 * m :] - 2 * theta[m:-m] + theta[: -2 * m]
        value[j] = np.sqrt((d**2).sum(axis=0) / (2 * tau[j] ** 2 * (theta.shape[0] - 2 * m)))
    edf = np.maximum(n / ms - 1, 1.0)[:, None]
    lo = value * np.sqrt(edf / chi2.ppf(0.975, edf))
    hi = value * np.sqrt(edf / chi2.ppf(0.025, edf))
    return tau, value, lo, hi


def simulate(seed: int, fs: float, seconds: float, n_density, k_walk) -> np.ndarray:
    """A 3-axis rate signal: white noise of density N per axis plus a rate random walk K."""
    rng = np.random.default_rng(seed)
    n = int(fs * seconds)
    white = rng.standard_normal((n, 3)) * np.asarray(n_density) * np.sqrt(fs)
    walk = np.cumsum(rng.standard_normal((n, 3)) * np.asarray(k_walk) / np.sqrt(fs), axis=0)
    return 0.01 + white + walk


def noise_body(
    sensors=("gyr",),
    seed: int = 13,
    fs: float = 200.0,
    seconds: float = 1000.0,
    n_density=(2e-3, 2.6e-3, 1.5e-3),
    k_walk=(4e-5, 6e-5, 3e-5),
    null=(),
) -> dict:
    """A stored-calibration-like noise body; ``null`` lists (sensor, term, axis index) set to null."""
    model, adev = {"type": "noise"}, {}
    for j, sensor in enumerate(sensors):
        scale = {"acc": 10.0, "gyr": 1.0, "mag": 100.0}[sensor]
        nd, kw = np.asarray(n_density) * scale, np.asarray(k_walk) * scale
        tau, value, lo, hi = overlapping_adev(simulate(seed + j, fs, seconds, nd, kw), fs)
        floor = value.min(axis=0)
        terms = {"noise_density": nd.tolist(), "random_walk": kw.tolist(), "bias_instability": (floor / 0.664).tolist()}
        for s, term, i in null:
            if s == sensor:
                terms[term][i] = None
        unit = UNITS[sensor]
        model[sensor] = {
            "unit": unit,
            "bias": [0.01] * 3,
            **terms,
            "noise_density_unit": f"({unit})/√Hz",
            "random_walk_unit": f"({unit})·√Hz",
            "bias_instability_unit": unit,
        }
        adev[sensor] = {"tau_s": tau.tolist(), "value": value.tolist(), "lo": lo.tolist(), "hi": hi.tolist()}
    return {
        "id": "cal_noise_fixture",
        "method": "noise",
        "created_at": "2025-01-31T12:34:56.789Z",
        "model": model,
        "adev": adev,
        "ok": True,
        "reasons": [],
        "warnings": [],
        "metrics": {},
    }


def three_sensors_body() -> dict:
    """Accelerometer, gyroscope and magnetometer, 10 min each, every term present."""
    return noise_body(("acc", "gyr", "mag"), seconds=600)


def short_gyr_body() -> dict:
    """A gyroscope too short for its random walk (null on every axis) and with y's noise density null."""
    null = [("gyr", "random_walk", i) for i in range(3)] + [("gyr", "noise_density", 1)]
    return noise_body(("gyr",), seconds=300, null=null)
