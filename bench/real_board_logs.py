"""trical on makers' real board logs beside the makers' own fits (tests/data/real/README.md).

    python bench/real_board_logs.py

Three logs as makers write them over a serial port, each read by the same loader the API and the
CLI use (``app.io.readers.read_log``), then calibrated through the method table (``methods.calibrate``), as they do:

- an MPU-6050's six pose files, one per pose (``x_axis_pos.csv`` …), as one recording in parts,
  beside the maker's Ferraris fit (imucal) of the same first 100 samples per file, g = 9.81;
- a QMC5883L turned by hand (raw counts), beside the maker's Dorveaux et al. fit;
- a still MPU-6050 (30 s), beside the white-noise variance the maker read from 6 hours of it.
"""

from __future__ import annotations

import json
import sys
import tempfile
import zipfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from app import methods  # noqa: E402 - after sys.path.insert
from app.io.readers import read_log  # noqa: E402 - after sys.path.insert
from app.io.readers.read_options import ReadOptions  # noqa: E402 - after sys.path.insert
from app.workflows.recordings import RecordingSource, describe_log  # noqa: E402 - after sys.path.insert

REAL = ROOT / "tests" / "data" / "real"
ORDER = ("x_axis_pos", "x_axis_neg", "y_axis_pos", "y_axis_neg", "z_axis_pos", "z_axis_neg")


def calibrate(path: Path, request: dict, **read_with) -> tuple[dict, dict]:
    options = ReadOptions(**{"units": {}, **read_with})
    log = read_log(path, options, name=path.name)
    meta = describe_log(log, options)
    body = methods.calibrate(
        methods.parse_calibration_request({**request, "recording_id": path.name}),
        RecordingSource(meta=meta, path=path, log=log),
    ).body()
    return meta, body


def pose_files(tmp: Path) -> None:
    peer = json.loads((REAL / "mpu6050_pose_files_peer.json").read_text())
    n = peer["samples_per_pose"]
    joined = tmp / "poses.zip"
    with zipfile.ZipFile(joined, "w") as zf:
        for s in ORDER:
            lines = (REAL / "mpu6050_pose_files" / f"{s}.csv").read_text().splitlines(keepends=True)
            zf.writestr(f"{s}.csv", "".join(lines[: n + 1]))
    _meta, body = calibrate(joined, {"method": "six_position", "gravity": peer["gravity"]}, units={"acc": "m/s^2"})
    g = peer["gravity"]
    K, R, b = np.diag(peer["K"]), np.asarray(peer["R"]), np.asarray(peer["b"])
    means = np.array([r["mean"] for r in body["readings"]])
    peer_cal = (np.linalg.inv(R) @ np.linalg.inv(K) @ (means - b).T).T

    def mg(a):
        return 1000 * np.abs(np.linalg.norm(a, axis=1) - g) / g

    print(f"MPU-6050, six pose files ({n} samples each), six_position beside imucal's Ferraris:")
    for r, m_peer in zip(body["readings"], mg(peer_cal)):
        print(
            f"  {r['source']:15s} {r['up']}  raw {r['norm_error_raw'] * 1000:6.2f} mg   trical "
            f"{r['norm_error'] * 1000:5.2f} mg   peer {m_peer:5.2f} mg"
        )
    print(
        f"  mean: raw {body['metrics']['error_before_mg']:.2f} mg, trical {body['metrics']['error_after_mg']:.2f} mg, "
        f"peer {mg(peer_cal).mean():.2f} mg; "
        f"max |X − K R| = {np.abs(np.asarray(body['model']['X']) - K @ R).max():.1e}; "
        f"y − b = {np.round(np.asarray(body['model']['y']) - b, 4).tolist()} m/s²"
    )


def compass() -> None:
    peer = json.loads((REAL / "magnetometer" / "tomisuarez2_qmc5883l_peer.json").read_text())
    path = REAL / "magnetometer" / "tomisuarez2_qmc5883l_turn_every10.csv"
    _, body = calibrate(
        path, {"method": "magnetometer"}, units={"mag": "raw"}, columns="mag_x,mag_y,mag_z", sampling_rate_hz=5.0
    )
    m = np.loadtxt(path, delimiter=",", skiprows=4)[int(peer["skipped_s"] * 5) :]
    A, B = np.asarray(peer["A"]), np.asarray(peer["B"])
    F = body["metrics"]["field_ut"]
    ours = np.linalg.norm((m - body["model"]["b"]) @ np.asarray(body["model"]["M"]).T, axis=1) / F
    theirs = np.linalg.norm(m @ A.T + B, axis=1)
    raw = np.linalg.norm(m - body["model"]["b"], axis=1)

    def rms(x):
        return 100 * np.sqrt(np.mean((x - 1) ** 2))

    print("QMC5883L hand turn (raw counts), magnetometer beside the maker's Dorveaux fit:")
    print(
        f"  offset: trical {np.round(body['model']['b'], 1).tolist()}, peer "
        f"{np.round(-np.linalg.solve(A, B), 1).tolist()} counts"
    )
    print(
        f"  |h| relative RMS over the turn: raw {rms(raw / raw.mean()):.2f} %, trical {rms(ours):.3f} %, "
        f"peer {rms(theirs):.3f} %; trical on new directions {100 * body['metrics']['cv_error_ut'] / F:.2f} %"
    )


def still() -> None:
    peer = json.loads((REAL / "mpu6050_noise_peer.json").read_text())
    _, body = calibrate(
        REAL / "mpu6050_session2_still_30s.csv",
        {"method": "noise"},
        units={"acc": "raw"},
        lsb_per_g=16384.0,
        columns="acc_x,acc_y,acc_z",
        sampling_rate_hz=100.0,
    )
    ours = np.asarray(body["model"]["acc"]["noise_density"]) * 1000
    theirs = np.sqrt(np.asarray(peer["R"]) / peer["sampling_rate_hz"]) * 1000
    print("MPU-6050 still 30 s, noise density (mm/s²/√Hz) beside the maker's 6-hour Allan figure:")
    print(
        f"  trical {np.round(ours, 2).tolist()}   peer {np.round(theirs, 2).tolist()}   ratio "
        f"{np.round(ours / theirs, 3).tolist()}"
    )


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as tmp:
        pose_files(Path(tmp))
    compass()
    still()
