"""Seeded flights for the compass calibrated from a flight (:mod:`app.calibration.magnetometer.flight`).

A multicopter flies a few minutes: slow yaw turns through every heading, pitch and roll of up to ~25°,
a current that rises in climbs and falls in hovers. Its compass, mounted in a frame L rotated from the
body by a firmware rotation Q, reads

    m_L = Qᵀ (M⁻¹ C_nbᵀ B_ned + b + k p) + ε

(the model ``h_body = M (Q m − b − k p)`` solved for m), with ε white noise of a real compass (0.3 µT)
and the attitude in the log off the true one by a small rotation that wanders over seconds (an
estimator's error, 0.3° per axis), so that the residuals of a fit are correlated in time as a real
flight's are.
"""

from __future__ import annotations

import datetime

import numpy as np

from app.calibration.shared.rotations import ardupilot_matrix

from .magnetometer import random_soft_iron


def _rotations(roll, pitch, yaw) -> np.ndarray:
    """``Rz(yaw) Ry(pitch) Rx(roll)`` for arrays of angles in radians, shape (N, 3, 3)."""
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    R = np.empty((len(roll), 3, 3))
    R[:, 0, 0] = cy * cp
    R[:, 0, 1] = cy * sp * sr - sy * cr
    R[:, 0, 2] = cy * sp * cr + sy * sr
    R[:, 1, 0] = sy * cp
    R[:, 1, 1] = sy * sp * sr + cy * cr
    R[:, 1, 2] = sy * sp * cr - cy * sr
    R[:, 2, 0] = -sp
    R[:, 2, 1] = cp * sr
    R[:, 2, 2] = cp * cr
    return R


def _wander(rng, n: int, dt: float, sigma: float, tau_s: float) -> np.ndarray:
    """A first-order Gauss–Markov process of standard deviation ``sigma`` and time constant ``tau_s``."""
    a = np.exp(-dt / tau_s)
    x = np.empty(n)
    x[0] = rng.normal(0.0, sigma)
    drive = rng.normal(0.0, sigma * np.sqrt(1.0 - a * a), n)
    for i in range(1, n):
        x[i] = a * x[i - 1] + drive[i]
    return x


def _euler_deg(C: np.ndarray) -> dict:
    """Roll, pitch and yaw in degrees of ``C = Rz(yaw) Ry(pitch) Rx(roll)``."""
    return {
        "roll_deg": np.degrees(np.arctan2(C[:, 2, 1], C[:, 2, 2])),
        "pitch_deg": np.degrees(-np.arcsin(np.clip(C[:, 2, 0], -1.0, 1.0))),
        "yaw_deg": np.degrees(np.arctan2(C[:, 1, 0], C[:, 0, 0])) % 360.0,
    }


def earth_field_ned(field_ut: float = 50.0, inclination_deg: float = 64.0, declination_deg: float = 2.0) -> np.ndarray:
    """``F (cos I cos D, cos I sin D, sin I)``: the field in north-east-down."""
    i, d = np.radians(inclination_deg), np.radians(declination_deg)
    return field_ut * np.array([np.cos(i) * np.cos(d), np.cos(i) * np.sin(d), np.sin(i)])


def simulate_flight(
    seed: int,
    *,
    duration_s: float = 180.0,
    rate_hz: float = 25.0,
    orientation: int = 2,
    noise_ut: float = 0.3,
    attitude_error_deg: float = 0.3,
    attitude_tau_s: float = 3.0,
    hard_iron_ut: float = 120.0,
    soft_iron: float = 0.08,
    motor_ut_per_a: float = 0.5,
    tilt_deg: float = 20.0,
    turns: float | None = None,
    earth_ned=None,
) -> dict:
    """One seeded flight with its truth.

    Parameters
    ----------
    seed : int
    duration_s, rate_hz : float
        Length and compass rate.
    orientation : int
        ArduPilot ``COMPASS_ORIENT`` number of the true mounting (2: yaw 90°; 8: roll 180°).
    noise_ut : float
        The compass's white noise per axis.
    attitude_error_deg, attitude_tau_s : float
        The logged attitude's error per axis, a Gauss–Markov process of this time constant.
    hard_iron_ut, soft_iron, motor_ut_per_a : float
        Bounds of the uniform draws of b, of M's entries around the identity and of k.
    tilt_deg : float
        Amplitude of the pitch and roll.
    turns : float, optional
        Full yaw turns in the flight (one a minute by default); 0 for a flight without turns.
    earth_ned : array_like of shape (3,), optional
        The field in NED, µT (50 µT at 64° of dip by default).

    Returns
    -------
    dict
        ``time_s``, ``attitude_c_nb`` (N, 3, 3, the logged attitude) and its ``roll_deg``, ``pitch_deg``,
        ``yaw_deg`` (as ArduPilot's ATT logs them, yaw in 0–360), ``mag_raw_ut`` (N, 3, frame L),
        ``current_a``, ``throttle`` (0..1), ``earth_ned``, ``lat``, ``lon``, ``alt_m``, ``utc``,
        ``expected_ut`` (``C_nbᵀ B_ned`` with the logged attitude), ``mag_firmware_ut`` (the field of a
        firmware that applies no rotation and a stale offset), and ``truth``: ``b``, ``M``, ``k``, ``Q``,
        ``orientation``.
    """
    rng = np.random.default_rng(seed)
    n = int(round(duration_s * rate_hz))
    dt = 1.0 / rate_hz
    t = np.arange(n) * dt
    turns = duration_s / 60.0 if turns is None else turns
    yaw = rng.uniform(0, 2 * np.pi) + 2 * np.pi * turns * t / duration_s + 0.3 * np.sin(2 * np.pi * t / 23.0)
    tilt = np.radians(tilt_deg)
    pitch = tilt * np.sin(2 * np.pi * t / 7.3 + rng.uniform(0, 2 * np.pi)) * (0.6 + 0.4 * np.sin(2 * np.pi * t / 41.0))
    roll = tilt * np.sin(2 * np.pi * t / 11.1 + rng.uniform(0, 2 * np.pi)) * (0.6 + 0.4 * np.cos(2 * np.pi * t / 53.0))
    C_true = _rotations(roll, pitch, yaw)
    err = np.radians(attitude_error_deg)
    C_log = C_true @ _rotations(*(_wander(rng, n, dt, err, attitude_tau_s) for _ in range(3)))

    B = earth_field_ned() if earth_ned is None else np.asarray(earth_ned, dtype=float)
    climbs = np.clip(np.sin(2 * np.pi * t / 37.0 + rng.uniform(0, 2 * np.pi)), 0.0, None)
    current = 12.0 + 18.0 * climbs + 3.0 * np.sin(2 * np.pi * t / 5.0) + rng.normal(0.0, 0.5, n)
    throttle = np.clip(0.25 + 0.5 * (current - 12.0) / 20.0, 0.0, 1.0)

    M = random_soft_iron(rng, soft_iron)
    b = rng.uniform(-hard_iron_ut, hard_iron_ut, 3)
    k = rng.uniform(-motor_ut_per_a, motor_ut_per_a, 3)
    Q = ardupilot_matrix(orientation)
    h_true = np.einsum("nji,j->ni", C_true, B)  # C_nbᵀ B
    body = h_true @ np.linalg.inv(M).T + b + np.outer(current, k)
    mag = body @ Q + rng.normal(0.0, noise_ut, (n, 3))  # Qᵀ applied to rows
    b_stale = b + rng.normal(0.0, 5.0, 3)
    firmware = mag - b_stale  # no rotation, stale offsets, no soft iron
    return {
        "time_s": t,
        "attitude_c_nb": C_log,
        **_euler_deg(C_log),
        "mag_raw_ut": mag,
        "current_a": current,
        "throttle": throttle,
        "earth_ned": B,
        "lat": 47.4,
        "lon": 8.5,
        "alt_m": 430.0,
        "utc": datetime.datetime(2025, 6, 1, 10, 0, tzinfo=datetime.UTC),
        "expected_ut": np.einsum("nji,j->ni", C_log, B),
        "mag_firmware_ut": firmware,
        "truth": {"b": b, "M": M, "k": k, "Q": Q, "orientation": orientation},
    }


__all__ = ["earth_field_ned", "simulate_flight"]
