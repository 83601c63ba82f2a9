"""Simulations of Särkkä et al., IEEE Sensors Journal 17(11) 2017, section V (true parameters of Table VI).

Raw units as in the paper: the accelerometer and the magnetometer read volts (S in V per m/s²
and V per µT, b in V), the gyroscope reads *pre-adjusted* rad/s (S dimensionless, b in rad/s).
The noise is Gaussian with the variances of section V: 4·10⁻⁴ (rad/s)² for the gyroscope,
2·10⁻⁸ V² for the accelerometer and 6·10⁻⁸ V² for the magnetometer, per axis.  The field
direction is α = 15°, β = 10° for both references (section V-B), |g| = 9.80665 m/s² and
|B| = 51000 nT = 51 µT.  Rotations follow the protocol's net rotations while their axis wanders
(section V-A).  Every generator takes a seeded :class:`numpy.random.Generator`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from app.calibration.cube import quaternion as quat
from app.calibration.cube.accmag import direction_matrix, reference_direction
from app.calibration.cube.protocols import Protocol, get_protocol, parse_rotation
from app.calibration.shared.gravity import STANDARD_GRAVITY

# Särkkä et al., IEEE Sensors Journal 17(11) 2017, Table VI, in the table's units: D (diag), D⁻¹S, b.
TABLE_VI = {
    "gyr": {
        "D": [0.9581, 0.9539, 0.9765],
        "misalignment": [[1.0000, 0.0003, -0.0008], [-0.0021, 1.0000, 0.0023], [0.0056, -0.0015, 1.0000]],
        "b": [-1.0000, 2.0000, 5.0000],  # mrad/s
    },
    "acc": {
        "D": [5869.3, 6136.6, 6082.0],  # µV/(m/s²)
        "misalignment": [[0.9964, 0.0170, 0.0852], [0.0652, 0.9997, -0.0163], [-0.0493, 0.0164, 0.9965]],
        "b": [1683.0, 1637.0, 1618.0],  # mV
    },
    "mag": {
        "D": [2246.4, 2597.3, 2769.1],  # V/T
        "misalignment": [[1.0000, 0.0089, 0.0088], [0.0010, 1.0000, -0.0007], [-0.0031, -0.0004, 1.0000]],
        "b": [2535.3, 2514.8, 2487.6],  # mV
    },
}

# Factors from the table's units to the simulation's raw units.
_UNIT = {
    "gyr": (1.0, 1e-3),  # D dimensionless; b mrad/s → rad/s
    "acc": (1e-6, 1e-3),  # µV/(m/s²) → V/(m/s²); mV → V
    "mag": (1e-6, 1e-3),  # V/T → V/µT; mV → V
}

NOISE_VAR = {"gyr": 4e-4, "acc": 2e-8, "mag": 6e-8}
"""Per-axis noise variances of Särkkä et al., IEEE Sensors Journal 17(11) 2017, section V: (rad/s)², V², V²."""

ALPHA_DEG = 15.0
BETA_DEG = 10.0
GRAVITY = STANDARD_GRAVITY
FIELD_UT = 51.0


def true_parameters(sensor: str) -> tuple[np.ndarray, np.ndarray]:
    """(S, b) of Särkkä et al., IEEE Sensors Journal 17(11) 2017, Table VI in the simulation's raw
    units, S = D (D⁻¹S)."""
    t = TABLE_VI[sensor]
    ks, kb = _UNIT[sensor]
    S = (np.asarray(t["D"]) * ks)[:, None] * np.asarray(t["misalignment"])
    return S, np.asarray(t["b"], dtype=float) * kb


def _noise_cov(var) -> np.ndarray:
    v = np.asarray(var, dtype=float)
    if v.ndim == 0:
        return float(v) * np.eye(3)
    if v.shape == (3,):
        return np.diag(v)
    return v.reshape(3, 3)


def simulate_position_means(
    rng: np.random.Generator,
    protocol="cube24",
    *,
    sensor: str = "acc",
    n_samples: int = 5000,
    noise_var=None,
    alpha_deg: float = ALPHA_DEG,
    beta_deg: float = BETA_DEG,
    reference: float | None = None,
    S=None,
    b=None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sample means, sample covariances and counts in each position (Särkkä et al., IEEE Sensors
    Journal 17(11) 2017, section V-B).

    The mean of n Gaussian samples is drawn as N(μ, Σ/n) and their sample covariance from the
    Wishart distribution W(Σ, n − 1)/(n − 1): the same joint law as averaging n raw samples, at a
    fraction of the cost, so that 1000-run studies are quick.

    Returns
    -------
    means (P, 3), covariances (P, 3, 3), counts (P,)
    """
    proto = get_protocol(protocol)
    S0, b0 = true_parameters(sensor)
    S = S0 if S is None else np.asarray(S, float)
    b = b0 if b is None else np.asarray(b, float)
    ref = (GRAVITY if sensor == "acc" else FIELD_UT) if reference is None else reference
    cov = _noise_cov(NOISE_VAR[sensor] if noise_var is None else noise_var)
    u = reference_direction(np.radians(alpha_deg), np.radians(beta_deg)) * ref
    mu = np.einsum("ij,pkj,k->pi", S, proto.attitudes, u) + b
    P = len(mu)
    L = np.linalg.cholesky(cov)
    means = mu + (rng.standard_normal((P, 3)) @ L.T) / np.sqrt(n_samples)
    # Wishart(Σ, n−1) by the Bartlett decomposition.
    dof = n_samples - 1
    A = np.zeros((P, 3, 3))
    for i in range(3):
        A[:, i, i] = np.sqrt(rng.chisquare(dof - i, size=P))
    A[:, 1, 0] = rng.standard_normal(P)
    A[:, 2, 0] = rng.standard_normal(P)
    A[:, 2, 1] = rng.standard_normal(P)
    LA = L @ A
    covs = LA @ np.transpose(LA, (0, 2, 1)) / dof
    return means, covs, np.full(P, n_samples)


@dataclass(frozen=True)
class SimulatedSession:
    """A simulated recording and the truth behind it."""

    acc: np.ndarray
    gyr: np.ndarray
    mag: np.ndarray
    sampling_rate_hz: float
    protocol: Protocol
    truth: dict
    static_segments: tuple  # (start, end) sample indices, end exclusive
    gravity: float = GRAVITY
    field_ut: float = FIELD_UT
    extra: dict = field(default_factory=dict)


def _rotation_path(q_start, rot, n, wander_deg, rng):
    """Attitudes along one rotation with a wandering axis, ending exactly at rot ⊗ q_start."""
    s = np.linspace(0.0, 1.0, n)

    def attitude(s):
        phi = 0.5 * (1.0 - np.cos(np.pi * s))  # 0 → 1 smoothly
        main = quat.from_axis_angle(np.broadcast_to(rot.axis, (len(s), 3)), np.radians(rot.angle_deg) * phi)
        eps = np.radians(wander_deg) * np.sin(np.pi * s) ** 2
        w = np.cos(2 * np.pi * s + c)[:, None] * p1 + np.sin(2 * np.pi * s + c)[:, None] * p2
        pert = quat.from_axis_angle(w, eps)
        return quat.multiply(quat.multiply(main, pert), q_start)

    a = rot.axis
    helper = np.array([1.0, 0, 0]) if abs(a[0]) < 0.9 else np.array([0, 1.0, 0])
    p1 = np.cross(a, helper)
    p1 /= np.linalg.norm(p1)
    p2 = np.cross(a, p1)
    c = rng.uniform(0, 2 * np.pi)
    return s, attitude


def _shortest_rotation(q, target, label: str):
    """The shortest rotation (calibration frame) from attitude q to attitude target."""
    dq = quat.multiply(target, quat.conjugate(q))
    if dq[0] < 0:
        dq = -dq
    ang = 2 * np.arctan2(np.linalg.norm(dq[1:]), dq[0])
    axis = dq[1:] / max(np.linalg.norm(dq[1:]), 1e-12) if ang > 1e-9 else np.array([0, 0, 1.0])
    return parse_rotation({"axis": axis.tolist(), "angle_deg": float(np.degrees(ang)), "label": label})


def _move(q, rot, n: int, h: float, wander_deg: float, rng):
    """Attitudes and body rates of one rotation of n samples from attitude q."""
    s, attitude = _rotation_path(q, rot, n, wander_deg, rng)
    qs = attitude(s)
    d = 1e-6
    dq_ds = (attitude(s + d) - attitude(s - d)) / (2 * d)
    # Body rate from q̇ = ½ q ⊗ [0, ω] (Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (2));
    # s runs 0 → 1 over (n − 1) steps.
    return qs, 2.0 * quat.multiply(quat.conjugate(qs), dq_ds)[:, 1:] / ((n - 1) * h)


def simulate_session(
    rng: np.random.Generator,
    protocol="cube24",
    *,
    sampling_rate_hz: float = 100.0,
    static_s: float = 5.0,
    rotation_s: float = 2.0,
    alpha_deg: float = ALPHA_DEG,
    beta_deg: float = BETA_DEG,
    noise_var: dict | None = None,
    wander_deg: float = 10.0,
    return_to_start: bool = False,
    drift_per_s: dict | None = None,
    wrong_rotations: dict | None = None,
    gyro_range: float | None = None,
    with_mag: bool = True,
) -> SimulatedSession:
    """A full raw recording of a protocol (Särkkä et al., IEEE Sensors Journal 17(11) 2017, section V):
    still positions and rotations.

    Parameters
    ----------
    rng : numpy.random.Generator
    protocol : str or Protocol
    sampling_rate_hz : float
        Samples per second of every sensor.
    static_s, rotation_s : float
        Duration of each still position and of each rotation.
    alpha_deg, beta_deg : float
        Direction of gravity and of the field in the calibration frame (Särkkä et al., IEEE Sensors
        Journal 17(11) 2017, eq. (8)).
    noise_var : dict, optional
        Per-sensor noise variance (scalar, per-axis 3-vector or 3×3), default :data:`NOISE_VAR`.
    wander_deg : float
        Peak deviation of the rotation from a constant axis (Särkkä et al., IEEE Sensors Journal 17(11)
        2017, section V-A).
    return_to_start : bool
        Rotate back to position 1 after the last position (for the drift of section II).
    drift_per_s : dict, optional
        Linear drift of the raw outputs, sensor → 3-vector in raw units per second.
    wrong_rotations : dict, optional
        1-based rotation number → rotation actually made (``"x+"``...); later rotations are the
        protocol's, applied from wherever the mistake left the device.
    gyro_range : float, optional
        Clip the raw gyroscope at ±range (saturation).
    with_mag : bool
        Also simulate the magnetometer.

    Returns
    -------
    SimulatedSession
    """
    proto = get_protocol(protocol)
    fs = float(sampling_rate_hz)
    h = 1.0 / fs
    nv = dict(NOISE_VAR)
    nv.update(noise_var or {})
    n_static = int(round(static_s * fs))
    n_rot = int(round(rotation_s * fs))
    rots = list(proto.rotations)
    wrong = {int(k): parse_rotation(v) for k, v in (wrong_rotations or {}).items()}
    q = proto.quaternions[0]
    attitudes_q: list[np.ndarray] = []  # per sample
    omegas: list[np.ndarray] = []
    segments = []
    pos = 0
    n_positions = proto.n_positions + (1 if return_to_start else 0)
    for k in range(n_positions):
        segments.append((pos, pos + n_static))
        attitudes_q.append(np.broadcast_to(q, (n_static, 4)))
        omegas.append(np.zeros((n_static, 3)))
        pos += n_static
        if k == n_positions - 1:
            break
        if k < len(rots):
            rot = wrong.get(k + 1, rots[k])
            if rot is None:
                rot = _shortest_rotation(q, proto.quaternions[k + 1], "free")  # straight to the next attitude
        else:
            rot = _shortest_rotation(q, proto.quaternions[0], "return")  # back to position 1 (section II)
        qs, om = _move(q, rot, n_rot, h, wander_deg, rng)
        attitudes_q.append(qs)
        omegas.append(om)
        pos += n_rot
        q = qs[-1]
    Q = np.vstack(attitudes_q)
    W = np.vstack(omegas)
    R = quat.to_matrix(Q)
    Rt = np.transpose(R, (0, 2, 1))
    N = len(Q)
    t = np.arange(N) * h

    def sensor_out(name, f):
        S, b = true_parameters(name)
        L = np.linalg.cholesky(_noise_cov(nv[name]))
        out = f @ S.T + b + rng.standard_normal((N, 3)) @ L.T
        if drift_per_s and name in drift_per_s:
            out = out + t[:, None] * np.asarray(drift_per_s[name], float)
        return out

    C = direction_matrix(np.radians(alpha_deg), np.radians(beta_deg))
    acc = sensor_out("acc", Rt @ (C @ np.array([0, 0, GRAVITY])))
    mag = sensor_out("mag", Rt @ (C @ np.array([0, 0, FIELD_UT]))) if with_mag else None
    gyr = sensor_out("gyr", W)
    if gyro_range is not None:
        gyr = np.clip(gyr, -gyro_range, gyro_range)
    truth = {name: dict(zip(("S", "b"), true_parameters(name))) for name in ("acc", "gyr", "mag")}
    truth["alpha_deg"] = alpha_deg
    truth["beta_deg"] = beta_deg
    return SimulatedSession(
        acc=acc,
        gyr=gyr,
        mag=mag,
        sampling_rate_hz=fs,
        protocol=proto,
        truth=truth,
        static_segments=tuple(segments),
        extra={"omega": W, "attitudes": Q},
    )


# A Ferraris session as a person records it by hand (imucal's protocol, docs/methods.md): an IMU at
# 102.4 Hz reading m/s² and deg/s in 16-bit steps of ±16 g and ±2000 °/s, laid down in each position,
# picked up and re-placed, turned once about each axis.  The rests are placed so that imucal's own
# example section list (tests/data/imucal_example_ferraris_session_list.json) marks them.
HAND_FS = 102.4
ACC_LSB = 16 * 9.81 / 32768  # m/s² per count
GYR_LSB = 2000.0 / 32768  # deg/s per count
HAND_SENSORS = {
    "acc": {
        "S": [[1.0175, 0.0061, -0.0112], [-0.0048, 1.0043, 0.0087], [0.0093, -0.0035, 0.9912]],
        "b": [0.312, -0.556, 0.493],
        "std": 0.018,
        "lsb": ACC_LSB,
    },
    "gyr": {
        "S": [[1.0121, 0.0042, -0.0067], [-0.0031, 0.9874, 0.0055], [0.0078, -0.0024, 1.0046]],
        "b": [-0.592, -0.361, 0.058],
        "std": 0.05,
        "lsb": GYR_LSB,
    },
}
"""raw = S f + b of each sensor (acc in m/s², gyr in deg/s), white noise std and quantisation step."""

HAND_TIMELINE = (
    ("rest", 290),
    ("adjust", 100, 6.0),
    ("rest", 950),  # x_p, after a re-placement
    ("to", "-x", 220),
    ("rest", 860),
    ("to", "+y", 320),
    ("rest", 620),
    ("to", "-y", 330),
    ("rest", 520),
    ("to", "+z", 260),
    ("rest", 570),
    ("to", "-z", 280),
    ("rest", 720),
    ("to", "+x", 290),
    ("rest", 460),
    ("turn", 285),
    ("rest", 385),
    ("adjust", 100, 10.0),
    ("rest", 300),
    ("to", "+y", 90),
    ("rest", 145),
    ("turn", 295),
    ("rest", 410),
    ("to", "+z", 200),
    ("rest", 215),
    ("turn", 285),
    ("rest", 500),
)
"""Steps in samples: rests, free moves to an orientation, handling adjustments (degrees), and
turns of −360° about the vertical (imucal: clockwise seen from above)."""


def simulate_hand_ferraris(
    rng: np.random.Generator, *, timeline=HAND_TIMELINE, sensors=None, tilt_deg: float = 0.5, wander_deg: float = 3.0
) -> SimulatedSession:
    """A Ferraris session recorded by hand, with pauses and re-placements (module constants).

    Each placement has a random heading and a tilt of about ``tilt_deg`` from its nominal up axis;
    each turn is about the vertical with its axis wandering by ``wander_deg``; the outputs are
    quantised.  ``truth`` holds each sensor's S and b (raw = S f + b, f in m/s² and deg/s), and
    ``extra["rests"]`` the still intervals.

    Returns
    -------
    SimulatedSession
        ``acc`` in m/s², ``gyr`` in deg/s (not rad/s), ``mag`` None.
    """
    from app.calibration.cube.protocols import attitude_for_up

    cfg = HAND_SENSORS if sensors is None else sensors
    h = 1.0 / HAND_FS
    vertical = np.array([0.0, 0.0, 1.0])

    def placed(up, heading_rad):
        """Laid down with ``up`` up at a heading, tilted by about tilt_deg (an uneven table, a case)."""
        axis = np.array([*rng.normal(size=2), 0.0])
        tilt = quat.from_axis_angle(axis / np.linalg.norm(axis), np.radians(tilt_deg) * abs(rng.normal()))
        heading = quat.from_axis_angle(vertical, heading_rad)
        return quat.multiply(tilt, quat.multiply(heading, quat.from_matrix(attitude_for_up(up))))

    up, heading = "+x", rng.uniform(0, 2 * np.pi)
    q = placed(up, heading)
    qs_all, w_all, rests, pos = [], [], [], 0
    for step in timeline:
        kind, n = step[0], step[1] if step[0] != "to" else step[2]
        if kind == "rest":
            qs, om = np.broadcast_to(q, (n, 4)), np.zeros((n, 3))
            rests.append((pos, pos + n))
        else:
            if kind == "to":
                up, heading = step[1], rng.uniform(0, 2 * np.pi)
                rot = _shortest_rotation(q, placed(up, heading), "free")
            elif kind == "adjust":  # picked up and laid down again, turned by a few degrees
                heading += np.radians(step[2])
                rot = _shortest_rotation(q, placed(up, heading), "adjust")
            else:
                rot = parse_rotation({"axis": vertical.tolist(), "angle_deg": -360.0, "label": "turn"})
            qs, om = _move(q, rot, n, h, wander_deg, rng)
            q = qs[-1]
        qs_all.append(qs)
        w_all.append(om)
        pos += n
    Q = np.vstack(qs_all)
    Rt = np.transpose(quat.to_matrix(Q), (0, 2, 1))
    f = {"acc": Rt @ np.array([0.0, 0.0, 9.81]), "gyr": np.degrees(np.vstack(w_all))}
    out, truth = {}, {}
    for name in ("acc", "gyr"):
        S, b = np.asarray(cfg[name]["S"], float), np.asarray(cfg[name]["b"], float)
        raw = f[name] @ S.T + b + cfg[name]["std"] * rng.standard_normal(f[name].shape)
        out[name] = np.round(raw / cfg[name]["lsb"]) * cfg[name]["lsb"]
        truth[name] = {"S": S, "b": b}
    return SimulatedSession(
        acc=out["acc"],
        gyr=out["gyr"],
        mag=None,
        sampling_rate_hz=HAND_FS,
        protocol=get_protocol("ferraris"),
        truth=truth,
        static_segments=tuple(rests),
        gravity=9.81,
        extra={"attitudes": Q},
    )
