"""trical check and trical compare, run as a user runs them (in this process: tests/cli_in_process.py)."""

from __future__ import annotations

import json

import numpy as np

from simulations.magnetometer import simulate_session, simulate_turn
from tests.api.test_check_api import turn_csv
from tests.cli_in_process import trical
from tests.conftest import DATA


def turn_log(path, m: np.ndarray):
    path.write_bytes(turn_csv(m, rate_hz=20.0))
    return path


def calibrate(tmp_path, log) -> dict:
    out = trical(
        "calibrate",
        log,
        "--method",
        "magnetometer",
        "--mag-unit",
        "uT",
        "--field-ut",
        "48",
        "--json",
        tmp_path=tmp_path,
    )
    assert out.returncode in (0, 3), out.stderr
    return json.loads(out.stdout)


def test_check_a_stored_compass_calibration_on_a_new_turn_and_compare_two(tmp_path):
    m, M, b = simulate_session(41, n=300)
    first = calibrate(tmp_path, turn_log(tmp_path / "turn1.csv", m))
    rng = np.random.default_rng(2)
    same = turn_log(tmp_path / "same.csv", simulate_turn(rng, M, b, n=300))
    kept = trical("check", first["id"], same, "--mag-unit", "uT", "--inclination-deg", "64", tmp_path=tmp_path)
    assert kept.returncode == 0, kept.stderr
    assert kept.stdout.startswith("verdict: keep it") and "current calibration:" in kept.stdout
    moved = turn_log(tmp_path / "moved.csv", simulate_turn(rng, M, b + [0.0, 4.0, 0.0], n=300))
    again = trical("check", first["id"], moved, "--mag-unit", "uT", "--json", tmp_path=tmp_path)
    assert again.returncode == 3, again.stderr
    out = json.loads(again.stdout)
    assert out["verdict"] == "calibrate_again" and out["sensors"][0]["drifted"] == ["hard iron"]
    second = calibrate(tmp_path, moved)
    compared = trical("compare", first["id"], second["id"], "--inclination-deg", "64", tmp_path=tmp_path)
    assert compared.returncode == 0, compared.stderr
    assert (
        "hard iron y: +" in compared.stdout
        and "real" in compared.stdout
        and "a heading off by up to" in compared.stdout
    )
    # a calibration's JSON file is read as well as its id
    saved = tmp_path / "first.json"
    saved.write_text(json.dumps(first))
    as_file = trical("compare", saved, second["id"], "--json", tmp_path=tmp_path)
    assert as_file.returncode == 0 and json.loads(as_file.stdout)["with"] == second["id"]


def test_check_the_real_pose_files_own_calibration_and_refuse_what_cannot_be_checked(tmp_path):
    poses = sorted((DATA / "real" / "mpu6050_pose_files").glob("*.csv"))
    cal = trical("calibrate", *poses, "--method", "six_position", "--unit", "m/s^2", "--json", tmp_path=tmp_path)
    assert cal.returncode == 0, cal.stderr
    body = json.loads(cal.stdout)
    m, _, _ = simulate_session(3, n=300)
    turn = turn_log(tmp_path / "turn.csv", m)
    refused = trical("check", body["id"], turn, "--mag-unit", "uT", tmp_path=tmp_path)
    assert refused.returncode == 2 and "corrects acc" in refused.stderr and "Traceback" not in refused.stderr
    missing = trical("check", "cal_missing", turn, tmp_path=tmp_path)
    assert missing.returncode == 2 and "cal_missing" in missing.stderr
