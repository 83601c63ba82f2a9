"""trical calibrate --method magnetometer, run as a user runs it (in this process: tests/cli_in_process.py), and
its ArduPilot export."""

from __future__ import annotations

import json

import numpy as np

from simulations.magnetometer import simulate_session
from tests.cli_in_process import trical


def _log(tmp_path, n=400, **kwargs):
    m, M, b = simulate_session(31, n=n, **kwargs)
    acc = np.tile([0.1, 0.2, 9.8], (len(m), 1))
    path = tmp_path / "turn.csv"
    np.savetxt(
        path,
        np.column_stack([np.arange(len(m)) / 20.0, acc, m]),
        delimiter=",",
        fmt="%.6f",
        comments="",
        header="time_s,acc_x,acc_y,acc_z,mag_x,mag_y,mag_z",
    )
    return path, M, b


def test_calibrate_a_turn_then_export_for_ardupilot(tmp_path):
    path, M, b = _log(tmp_path)
    out = trical(
        "calibrate",
        str(path),
        "--method",
        "magnetometer",
        "--mag-unit",
        "uT",
        "--field-ut",
        "48",
        "--json",
        tmp_path=tmp_path,
    )
    assert out.returncode == 0, out.stderr
    body = json.loads(out.stdout)
    assert body["method"] == "magnetometer" and body["ok"], body["reasons"]
    np.testing.assert_allclose(body["model"]["b"], b, atol=0.2)
    np.testing.assert_allclose(body["model"]["M"], M, atol=0.008)
    parm = trical("export", body["id"], "--format", "ardupilot", tmp_path=tmp_path)
    assert parm.returncode == 0, parm.stderr
    assert "COMPASS_OFS_X" in parm.stdout and "COMPASS_ODI_Z" in parm.stdout
    human = trical(
        "calibrate", str(path), "--method", "magnetometer", "--mag-unit", "uT", "--no-store", tmp_path=tmp_path
    )
    assert human.returncode == 0, human.stderr
    assert "M =" in human.stdout and "b = " in human.stdout and "on new directions expect" in human.stdout
    assert "warning: no place and date, so the field's magnitude is estimated" in human.stdout


def test_a_refused_compass_calibration_exits_3_with_the_reason(tmp_path):
    path, _, _ = _log(tmp_path, max_polar_deg=80.0)
    out = trical(
        "calibrate",
        str(path),
        "--method",
        "magnetometer",
        "--mag-unit",
        "uT",
        "--field-ut",
        "48",
        "--no-store",
        tmp_path=tmp_path,
    )
    assert out.returncode == 3 and "still missing" in out.stdout


def test_bad_dates_and_longitudes_are_one_line(tmp_path):
    path, _, _ = _log(tmp_path, n=60)
    for option, value in (("--date", "2026-13-01"), ("--longitude-deg", "200")):
        out = trical("calibrate", str(path), "--method", "magnetometer", option, value, tmp_path=tmp_path)
        assert out.returncode == 2 and "Traceback" not in out.stderr and len(out.stderr.splitlines()) == 1
