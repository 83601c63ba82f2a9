"""The trical command, run as a user runs it (a subprocess, a real database file)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np

from tests.conftest import DATA
from tests.live_server import ROOT


def trical(*args, tmp_path, check=False):
    env = {"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}", "PATH": "/usr/bin:/bin"}
    return subprocess.run(
        [sys.executable, "-m", "app.cli", *args],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        check=check,
        timeout=120,
    )


def test_calibrate_json_then_export(tmp_path):
    log = DATA / "six_orientations_150hz.csv"
    out = trical(
        "calibrate", str(log), "--method", "six_position", "--sampling-rate-hz", "150", "--json", tmp_path=tmp_path
    )
    assert out.returncode == 0, out.stderr
    body = json.loads(out.stdout)
    assert body["method"] == "six_position" and body["ok"] and body["id"].startswith("cal_")
    truth = json.loads((DATA / "six_orientations_150hz.json").read_text())
    np.testing.assert_allclose(body["model"]["X"], truth["model"]["X"], atol=2e-3)
    # The fixture drifts by 0.05 m/s² over the minute (tests/data/make_six_orientation_log.py).
    np.testing.assert_allclose(body["model"]["y"], truth["model"]["y"], atol=5e-2)

    header = trical("export", body["id"], "--format", "c", tmp_path=tmp_path)
    assert header.returncode == 0 and "trical_acc_apply" in header.stdout
    human = trical("calibrate", str(log), "--sampling-rate-hz", "150", "--no-store", tmp_path=tmp_path)
    assert human.returncode == 0 and "X =" in human.stdout and "fit error max" in human.stdout
    # The default method is auto: it says what it chose, then what to expect on new orientations
    # (six poses: no figure, and how to get one) before the in-sample figure.
    lines = human.stdout.splitlines()
    # What the recording supports first, the method run and why (the start page runs the same one).
    assert lines[0].startswith("--method auto, chosen from the recording: 6 still poses covering the six axes"), lines[
        0
    ]
    lines = lines[1:]
    # The verdict first: apply it, on the six poses' own figure (raw → calibrated), saying why it is in-sample.
    assert lines[1].startswith("Apply it: error on the 6 poses fitted ") and "Six poses leave none out" in lines[2]
    chose = next(i for i, line in enumerate(lines) if line.startswith("method auto chose six_position: "))
    assert lines[chose + 1].startswith("no figure for new orientations") and "add poses" in lines[chose + 1]
    assert "on the poses fitted (in-sample)" in lines[chose + 1]
    tri = trical(
        "calibrate", str(log), "--sampling-rate-hz", "150", "--method", "orientations", "--no-store", tmp_path=tmp_path
    )
    assert tri.returncode == 0 and "norm error max" in tri.stdout


def test_errors_are_one_line_without_traceback(tmp_path):
    missing = trical("calibrate", str(tmp_path / "nope.csv"), "--sampling-rate-hz", "100", tmp_path=tmp_path)
    assert missing.returncode == 2 and missing.stderr.startswith("trical: error: no such file")
    # Still poses need no rate; the noise does, and says which option gives it.
    poses = trical("calibrate", str(DATA / "six_orientations_150hz.csv"), "--no-store", tmp_path=tmp_path)
    assert poses.returncode == 0 and "without a sampling rate" in poses.stdout, poses.stderr
    no_rate = trical("noise", str(DATA / "six_orientations_150hz.csv"), tmp_path=tmp_path)
    assert no_rate.returncode == 2 and "--sampling-rate-hz" in no_rate.stderr
    unknown = trical("export", "cal_missing", tmp_path=tmp_path)
    assert unknown.returncode == 2 and "no calibration with id" in unknown.stderr
    for result in (missing, no_rate, unknown):
        assert "Traceback" not in result.stderr and result.stderr.count("\n") == 1


def test_calibrate_triangular_prints_the_next_pose(tmp_path):
    # A log of 12 still poses in random directions (3 s each at 50 Hz) joined by 1 s turns.
    rng = np.random.default_rng(4)
    ups = rng.normal(size=(12, 3))
    ups /= np.linalg.norm(ups, axis=1, keepdims=True)
    X, y, g = np.diag([1.01, 0.99, 1.02]), np.array([0.1, -0.2, 0.15]), 9.80665
    rows = []
    for k, u in enumerate(ups):
        if k:
            for s in np.linspace(0, 1, 50, endpoint=False):
                v = (1 - s) * ups[k - 1] + s * u
                rows.append(X @ (g * v / np.linalg.norm(v)) + y + rng.normal(0, 0.3, 3))
        rows += list(X @ (g * u) + y + rng.normal(0, 0.01, (150, 3)))
    log = tmp_path / "poses.csv"
    np.savetxt(log, np.array(rows), delimiter=",", header="acc_x,acc_y,acc_z", comments="", fmt="%.5f")
    out = trical(
        "calibrate", str(log), "--sampling-rate-hz", "50", "--method", "triangular", "--no-store", tmp_path=tmp_path
    )
    assert out.returncode in (0, 3), out.stderr
    lines = [line for line in out.stdout.splitlines() if line.startswith("next pose: ")]
    assert len(lines) == 3 and " up (" in lines[0] and "generalized variance by" in lines[0]
