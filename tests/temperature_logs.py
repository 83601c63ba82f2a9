"""Warm-up recordings for the temperature calibration's tests: a still board warming up, its offsets a
known cubic of temperature, its noise drawn from a real still MPU-6050 recording (tests/data/real,
``mpu6050_session2_still_30s.csv``, see tests/data/README.md), written as a CSV with a ``temp_c`` column."""

from __future__ import annotations

import io
from functools import lru_cache
from pathlib import Path

import numpy as np

from simulations.temperature import simulate_warm_up

REAL_STILL = Path(__file__).parent / "data" / "real" / "mpu6050_session2_still_30s.csv"


@lru_cache(maxsize=1)
def real_still_noise() -> np.ndarray:
    """The real MPU-6050's still accelerometer counts (±2 g, 16384 LSB/g), as m/s²."""
    counts = np.loadtxt(REAL_STILL, delimiter=",", skiprows=3)
    return counts / 16384.0 * 9.80665


def warm_up(seed: int, **kw):
    """A seeded warm-up (simulations.temperature) with the real log's noise."""
    return simulate_warm_up(np.random.default_rng(seed), noise=real_still_noise(), **kw)


def warm_up_csv(seed: int = 5, *, temperature_header: str = "temp_c", acc_in_g: bool = False, **kw) -> bytes:
    """The warm-up as CSV text: time_s, acc (m/s², or g), gyr (rad/s) and the temperature."""
    w = warm_up(seed, **kw)
    acc = w.acc / 9.80665 if acc_in_g else w.acc
    buf = io.StringIO()
    np.savetxt(
        buf,
        np.column_stack([w.time_s, acc, w.gyr, w.temperature_c]),
        delimiter=",",
        comments="",
        fmt="%.9g",
        header=f"time_s,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z,{temperature_header}",
    )
    return buf.getvalue().encode()
