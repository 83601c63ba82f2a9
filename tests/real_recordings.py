"""Real still-pose recordings of phones and IMU boards, as still means (tests/data/real/README.md).

Shared by ``tests/api/test_real_recordings.py`` and ``bench/real_recordings.py``.  Each
:class:`Recording` is one session of one device: its still means in ``unit`` with the reference
magnitude ``gravity``, the ``up`` labels when the poses are axis-aligned, and the names of the
same device's other sessions.
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from tests.conftest import seed_table

REAL = Path(__file__).parent / "data" / "real"

MPU6050_LSB_PER_G = 16384.0
"""MPU-6050 at ±2 g: the datasheet's nominal sensitivity, the 'raw' conversion the board's users apply."""

GEORGIEVA_GRAVITY = 9.806
"""Georgieva et al. (ESGI'95) section 2.4: the printed scales correspond to g = 9.806
(tests/calibration/test_nonorthogonal.py)."""


@dataclass(frozen=True)
class Recording:
    """One session of one device: still means (N, 3) and what is known about them."""

    name: str
    device: str
    means: np.ndarray
    unit: str
    gravity: float
    ups: tuple | None = None
    other_sessions: tuple = ()
    peer: dict = field(default_factory=dict)

    @property
    def raw_error_mg(self) -> float:
        """Mean | |m_i| − g | / g over the poses, in mg: the error of the readings as they come."""
        return raw_error_mg(self.means, self.gravity)


def raw_error_mg(means, gravity: float) -> float:
    m = np.asarray(means, dtype=float).reshape(-1, 3)
    return float(1000.0 * np.mean(np.abs(np.linalg.norm(m, axis=1) - gravity) / gravity))


def _rows(path: Path) -> list[list[str]]:
    with path.open(newline="") as f:
        return [row for row in csv.reader(f) if row and not row[0].startswith("#")]


def mpu6050_session1() -> np.ndarray:
    """The ten still means of the MPU-6050 calibration session, in g (sum / count / 16384)."""
    header, *rows = _rows(REAL / "mpu6050_session1_poses.csv")
    a = np.array([[float(v) for v in row] for row in rows])
    col = {name: i for i, name in enumerate(header)}
    sums = a[:, [col["sum_ax"], col["sum_ay"], col["sum_az"]]]
    return sums / a[:, [col["count"]]] / MPU6050_LSB_PER_G


def mpu6050_session2() -> np.ndarray:
    """The one still pose of the MPU-6050 validation session (mean of its first 200 samples), in g."""
    _, *rows = _rows(REAL / "mpu6050_session2_static_head.csv")
    return np.array([[float(v) for v in row] for row in rows]).mean(axis=0, keepdims=True) / MPU6050_LSB_PER_G


def mpu9250_sessions() -> dict[str, tuple[tuple, np.ndarray]]:
    """The four six-position sessions of the MPU-9250: name → (up labels, means in g)."""
    _, *rows = _rows(REAL / "mpu9250_six_position_sessions.csv")
    out: dict[str, tuple[list, list]] = {}
    for session, up, x, y, z, *_ in rows:
        ups, means = out.setdefault(session, ([], []))
        ups.append(up)
        means.append([float(x), float(y), float(z)])
    return {name: (tuple(ups), np.array(means)) for name, (ups, means) in out.items()}


def tedaldi_apply(p: dict, counts) -> np.ndarray:
    """Tedaldi et al. (ICRA 2014) as the peer wrote it: a = T K (raw + b), raw in counts, a in m/s²."""
    a_yz, a_zy, a_zx = p["misalignment"]
    T = np.array([[1.0, -a_yz, a_zy], [0.0, 1.0, -a_zx], [0.0, 0.0, 1.0]])
    return (np.asarray(counts) + p["bias"]) @ (T @ np.diag(p["scale"])).T


def peer(name: str) -> dict:
    return json.loads((REAL / name).read_text())


def recordings() -> list[Recording]:
    """Every real recording, one per session."""
    tedaldi = peer("mpu6050_tedaldi_peer.json")
    out = [
        Recording(
            "mpu6050-session1",
            "MPU-6050 (Arduino UNO), Tedaldi et al. protocol",
            mpu6050_session1(),
            "g",
            1.0,
            other_sessions=("mpu6050-session2",),
            peer={"tedaldi": tedaldi},
        ),
        Recording(
            "mpu6050-session2",
            "MPU-6050 (Arduino UNO), validation",
            mpu6050_session2(),
            "g",
            1.0,
            other_sessions=("mpu6050-session1",),
        ),
    ]
    sessions = mpu9250_sessions()
    for name, (ups, means) in sessions.items():
        out.append(
            Recording(
                f"mpu9250-{name}",
                "MPU-9250 (Raspberry Pi), six-position",
                means,
                "g",
                1.0,
                ups=ups,
                other_sessions=tuple(f"mpu9250-{n}" for n in sessions if n != name),
                peer={"ward": peer("mpu9250_trial1_peer.json")} if name == "trial_1" else {},
            )
        )
    for k, device in (
        (1, "Huawei phone (Georgieva et al. Table 1)"),
        (2, "phone (Georgieva et al. Table 2)"),
        (3, "GT phone (Georgieva et al. Table 3)"),
    ):
        out.append(Recording(f"georgieva-table{k}", device, seed_table(k), "m/s^2", GEORGIEVA_GRAVITY))
    return out


def by_name() -> dict[str, Recording]:
    return {r.name: r for r in recordings()}


def pose_subsets(sizes=(10, 11)) -> list[tuple[Recording, slice]]:
    """The issue's regime, a person's 10 or 11 poses: consecutive runs of the Georgieva phone tables."""
    out = []
    for rec in recordings():
        if not rec.name.startswith("georgieva"):
            continue
        for n in sizes:
            for start in range(0, len(rec.means) - n + 1, n):
                out.append((rec, slice(start, start + n)))
    return out
