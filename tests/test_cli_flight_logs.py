"""`trical calibrate/noise LOG --instance N` on flight controllers' logs, as a user runs it (its output and exit
status, run in this process: tests/cli_in_process.py)."""

from __future__ import annotations

import json

import numpy as np

from tests.cli_in_process import trical
from tests.flight_logs import (
    GYR_BIAS,
    HARD_IRON_UT,
    TRUTH,
    ardupilot_file,
    compass_tumble,
    imu_instances,
    px4_file,
    still_board,
)


def test_calibrate_six_poses_of_an_instance(tmp_path):
    path = ardupilot_file(tmp_path / "00000007.BIN", imu_instances(3))
    out = trical(
        "calibrate", str(path), "--method", "six_position", "--instance", "1", "--json", "--no-store", tmp_path=tmp_path
    )
    assert out.returncode == 0, out.stderr
    body = json.loads(out.stdout)
    np.testing.assert_allclose(body["model"]["X"], TRUTH[1][0], atol=3e-4)
    np.testing.assert_allclose(body["model"]["y"], TRUTH[1][1], atol=3e-3)
    out = trical("calibrate", str(path), "--instance", "2", "--no-store", tmp_path=tmp_path)
    assert out.returncode == 2 and "has no IMU instance 2: its IMU instances are 0, 1" in out.stderr
    out = trical("calibrate", str(path), "--instance", "x", "--no-store", tmp_path=tmp_path)
    assert out.returncode == 2 and "not an integer" in out.stderr


def test_compass_of_an_instance_on_its_own_clock(tmp_path):
    imus, mags, _ = compass_tumble(5)
    path = px4_file(tmp_path / "tumble.ulg", imus, mags)
    out = trical(
        "calibrate",
        str(path),
        "--method",
        "magnetometer",
        "--mag-instance",
        "1",
        "--field-ut",
        "48",
        "--json",
        "--no-store",
        tmp_path=tmp_path,
    )
    assert out.returncode == 0, out.stderr
    np.testing.assert_allclose(json.loads(out.stdout)["model"]["b"], HARD_IRON_UT[1], atol=0.1)


def test_noise_and_gyroscope_bias_of_an_instance(tmp_path):
    path = px4_file(tmp_path / "still.ulg", still_board(9, duration_s=40.0))
    out = trical("noise", str(path), "--instance", "1", "--sensor", "gyr", "--json", tmp_path=tmp_path)
    assert out.returncode == 0, out.stderr
    body = json.loads(out.stdout)
    assert list(body["model"]) == ["type", "gyr"]
    # within four standard errors of the mean (white noise of 2e-3 rad/s/√Hz at 400 Hz over 40 s: 3.2e-4 rad/s)
    se = np.asarray(body["metrics"]["gyr"]["bias_standard_error"])
    assert np.all(np.abs(np.asarray(body["model"]["gyr"]["bias"]) - GYR_BIAS[1]) <= 4 * se), (body["model"], se)
    assert np.all(se < 1.5e-3)


def test_compass_from_a_flight_log(tmp_path):
    from tests.flight_compass_logs import seeded_flight, write_flight_compass_logs

    path, _ = write_flight_compass_logs(tmp_path, seeded_flight(9, orientation=12))
    out = trical("calibrate", "--method", "compass_flight", str(path), "--no-store", tmp_path=tmp_path)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert (
        lines[0].startswith("ArduPilot ArduCopter V4.5.0 (TimeUS, MAG with I)")
        and "compass 0, 4500 samples" in lines[0]
    )
    assert lines[1].startswith("Apply it: heading error on flight segments left out") and lines[1].endswith("°.")
    assert "COMPASS_ORIENTn 12" in out.stdout  # the mounting found, not the one stored
    out = trical("calibrate", "--method", "compass_flight", str(path), "--json", "--no-store", tmp_path=tmp_path)
    body = json.loads(out.stdout)
    assert body["ok"] and body["flight"]["rotation_nearest"]["ardupilot"] == 12


def test_a_real_px4_flight_log_runs_its_compass_from_its_own_gps_fix(tmp_path):
    """`trical calibrate LOG` with no method on a real PX4 1.9 flight (tests/data/real/flight): the recording
    decides, with the place and date read from the log's GPS fix as the upload reads them."""
    from tests.conftest import DATA

    path = DATA / "real" / "flight" / "px4_1.9_esc_status_log.ulg"
    out = trical("calibrate", str(path), "--no-store", tmp_path=tmp_path)
    assert out.returncode == 3, out.stderr  # ok false: 117 samples
    first = out.stdout.splitlines()[0]
    assert first.startswith("--method compass_flight, chosen from the recording") and "2019-05-13" in first, first
