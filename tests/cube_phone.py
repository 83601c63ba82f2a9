"""A phone (or IMU board) in the 24-position cube, as its browser would report it.

The motion is Särkkä et al.'s simulation (simulations.cube: the protocol's rotations with a
wandering axis, Särkkä et al. section V-A); the sensors are a phone's: m = X f + y in m/s² rounded to the
browser's 0.1 m/s², the gyroscope S ω + b in deg/s rounded to 0.1 °/s, events at 60 Hz.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from app.calibration.cube import quaternion as quat
from app.calibration.cube.accmag import direction_matrix
from simulations.cube import simulate_session

G = 9.80665
RATE_HZ = 60.0
X_ACC = np.array([[1.02, 0.01, -0.02], [0.005, 0.98, 0.015], [-0.01, 0.02, 1.01]])
Y_ACC = np.array([0.15, -0.22, 0.31])
S_GYR = np.array([[1.01, 0.005, 0.0], [-0.004, 0.99, 0.006], [0.003, 0.0, 1.015]])
B_GYR_DEG_S = np.array([0.4, -0.3, 0.2])


@dataclass
class PhoneCube:
    t_ms: np.ndarray
    acc: np.ndarray  # m/s², browser-rounded
    gyr: np.ndarray  # deg/s, browser-rounded
    static_segments: tuple

    def capture(self, k: int, *, margin: int = 6) -> dict:
        """The still samples of 1-based position k and, after the first, the move into it."""
        a, b = self.static_segments[k - 1]
        a, b = a + margin, b - margin
        body = {
            "acc": self.acc[a:b].tolist(),
            "t_ms": self.t_ms[a:b].tolist(),
            "gyr": self.gyr[a:b].tolist(),
            "gyr_unit": "deg/s",
        }
        if k > 1:
            p = self.static_segments[k - 2][1] - margin
            body["motion"] = {
                "t_ms": self.t_ms[p:a].tolist(),
                "gyr": self.gyr[p:a].tolist(),
                "acc": self.acc[p:a].tolist(),
            }
        return body


def phone_cube(
    seed: int = 0, *, wrong_rotations: dict | None = None, alpha_deg: float = 5.0, static_s: float = 3.0
) -> PhoneCube:
    rng = np.random.default_rng(seed)
    sim = simulate_session(
        rng,
        "cube24",
        sampling_rate_hz=RATE_HZ,
        static_s=static_s,
        rotation_s=1.5,
        alpha_deg=alpha_deg,
        beta_deg=0.0,
        with_mag=False,
        wrong_rotations=wrong_rotations,
    )
    R = quat.to_matrix(sim.extra["attitudes"])
    g_cal = direction_matrix(np.radians(alpha_deg), 0.0) @ np.array([0.0, 0.0, G])
    f = np.einsum("nji,j->ni", R, g_cal)  # Rᵀ g: specific force in the sensor frame at rest
    n = len(f)
    acc = f @ X_ACC.T + Y_ACC + rng.normal(0, 0.03, (n, 3))
    gyr = np.degrees(sim.extra["omega"]) @ S_GYR.T + B_GYR_DEG_S + rng.normal(0, 0.05, (n, 3))
    t_ms = 1000.0 * np.arange(n) / RATE_HZ + 5000.0
    return PhoneCube(t_ms=t_ms, acc=np.round(acc, 1), gyr=np.round(gyr, 1), static_segments=sim.static_segments)
