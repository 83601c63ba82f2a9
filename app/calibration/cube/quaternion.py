"""Quaternions for the cube method (Särkkä et al. (IEEE Sensors J. 2017), section III-B).

Hamilton convention, scalar first: ``q = [w, x, y, z]``.  A quaternion q is the attitude of the
sensor in the calibration frame: ``v_cal = q ⊗ v_sensor ⊗ q*``, i.e. ``R(q)`` maps sensor
coordinates to calibration coordinates.  With the body angular velocity ω (what a gyroscope
measures) the attitude obeys ``q̇ = ½ W(ω) q`` (Särkkä et al. eq. (2)), which is ``q̇ = ½ q ⊗ [0, ω]``.
Everything here is vectorised over leading axes.
"""

from __future__ import annotations

import numpy as np


def multiply(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product ``p ⊗ q`` of quaternion arrays of shape (..., 4)."""
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    pw, px, py, pz = np.moveaxis(p, -1, 0)
    qw, qx, qy, qz = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
        ],
        axis=-1,
    )


def conjugate(q: np.ndarray) -> np.ndarray:
    """Conjugate (inverse of a unit quaternion)."""
    return np.asarray(q, dtype=float) * np.array([1.0, -1.0, -1.0, -1.0])


def from_axis_angle(axis, angle_rad) -> np.ndarray:
    """Unit quaternion of a right-hand rotation by ``angle_rad`` about ``axis``.

    The branch follows the angle: a 360° rotation gives ``[-1, 0, 0, 0]``, not the identity,
    which is how Särkkä et al. section III-B tells a full turn from no turn (footnote 2).
    """
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis, axis=-1, keepdims=True)
    half = 0.5 * np.asarray(angle_rad, dtype=float)[..., None]
    return np.concatenate([np.cos(half), np.sin(half) * axis], axis=-1)


def to_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrix R(q) (sensor → calibration frame), shape (..., 3, 3)."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=-2,
    )


def from_matrix(R: np.ndarray) -> np.ndarray:
    """Unit quaternion (w ≥ 0) of a rotation matrix of shape (3, 3)."""
    R = np.asarray(R, dtype=float)
    # Shepperd's method: pivot on the largest of the four squared components.
    tr = np.trace(R)
    cand = np.array([1 + tr, 1 + 2 * R[0, 0] - tr, 1 + 2 * R[1, 1] - tr, 1 + 2 * R[2, 2] - tr])
    k = int(np.argmax(cand))
    s = 2.0 * np.sqrt(cand[k])
    if k == 0:
        q = [s / 4, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    elif k == 1:
        q = [(R[2, 1] - R[1, 2]) / s, s / 4, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s]
    elif k == 2:
        q = [(R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, s / 4, (R[1, 2] + R[2, 1]) / s]
    else:
        q = [(R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, s / 4]
    quat = np.asarray(q)
    return quat if quat[0] >= 0 else -quat


def omega_matrix(omega: np.ndarray) -> np.ndarray:
    """W(ω) of Särkkä et al. eq. (2), shape (..., 4, 4)."""
    wx, wy, wz = np.moveaxis(np.asarray(omega, dtype=float), -1, 0)
    o = np.zeros_like(wx)
    return np.stack(
        [
            np.stack([o, -wx, -wy, -wz], -1),
            np.stack([wx, o, wz, -wy], -1),
            np.stack([wy, -wz, o, wx], -1),
            np.stack([wz, wy, -wx, o], -1),
        ],
        axis=-2,
    )


def xi_matrix(q: np.ndarray) -> np.ndarray:
    """Ξ(q), shape (..., 4, 3), with ``W(ω) q = Ξ(q) ω`` (W of Särkkä et al. eq. (2))."""
    w, x, y, z = np.moveaxis(np.asarray(q, dtype=float), -1, 0)
    return np.stack(
        [
            np.stack([-x, -y, -z], -1),
            np.stack([w, -z, y], -1),
            np.stack([z, w, -x], -1),
            np.stack([-y, x, w], -1),
        ],
        axis=-2,
    )


def cumulative_product(steps: np.ndarray) -> np.ndarray:
    """Prefix products ``d_0 ⊗ d_1 ⊗ … ⊗ d_j`` for j = 0 … n−1 (log-depth parallel scan)."""
    out = np.array(steps, dtype=float, copy=True)
    n = len(out)
    k = 1
    while k < n:
        out[k:] = multiply(out[:-k], out[k:])
        k *= 2
    return out


def integrate(omega: np.ndarray, step_s: float, q0) -> np.ndarray:
    """Forward solution of Särkkä et al. eq. (2) from ``q0`` over samples of body angular velocity.

    Each step rotates by the trapezoidal mean ``(ω_j + ω_{j+1}) / 2`` over ``step_s`` (exact
    exponential of that mean, so the quaternion stays on the unit sphere).

    Parameters
    ----------
    omega : numpy.ndarray, shape (N, 3)
        Angular velocity in rad/s, sensor frame.
    step_s : float
        Sampling interval h.
    q0 : array_like, shape (4,)
        Attitude at the first sample.

    Returns
    -------
    numpy.ndarray, shape (N, 4)
        Attitude at every sample; row 0 is ``q0``.
    """
    omega = np.asarray(omega, dtype=float)
    q0 = np.asarray(q0, dtype=float)
    if len(omega) < 2:
        return q0[None, :].copy()
    rot = 0.5 * (omega[1:] + omega[:-1]) * step_s
    angle = np.linalg.norm(rot, axis=1)
    safe = np.where(angle > 0, angle, 1.0)
    half = 0.5 * angle
    # sin(θ/2)/θ with its limit 1/2 at θ → 0.
    sinc = np.where(angle > 1e-8, np.sin(half) / safe, 0.5 - angle**2 / 48.0)
    steps = np.concatenate([np.cos(half)[:, None], sinc[:, None] * rot], axis=1)
    cum = cumulative_product(steps)
    return np.vstack([q0, multiply(q0, cum)])
