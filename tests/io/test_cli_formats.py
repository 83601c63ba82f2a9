"""The trical command reads every log format too: a Sensor Logger zip and an Arduino log in counts (the command
run in this process: tests/cli_in_process.py)."""

from __future__ import annotations

import json

import numpy as np

from tests.cli_in_process import trical
from tests.conftest import DATA

SAMPLES = DATA / "formats"
TRUTH = json.loads((SAMPLES / "format_samples.json").read_text())


def test_calibrate_a_zip_and_export_ardupilot(tmp_path):
    out = trical("calibrate", str(SAMPLES / "sensor_logger_ios.zip"), "--json", tmp_path=tmp_path, check=True)
    body = json.loads(out.stdout)
    assert body["unit"] == "g"
    np.testing.assert_allclose(body["model"]["X"], TRUTH["model"]["X"], atol=5e-3)
    params = trical("export", body["id"], "--format", "ardupilot", tmp_path=tmp_path, check=True).stdout
    assert "INS_ACCSCAL_Z" in params and "firmware_norm_error_max_mg" in params


def test_calibrate_counts_with_lsb_per_g(tmp_path):
    out = trical(
        "calibrate",
        str(SAMPLES / "arduino_serial_plotter.txt"),
        "--sampling-rate-hz",
        "50",
        "--lsb-per-g",
        "4096",
        "--log-format",
        "arduino",
        "--json",
        "--no-store",
        tmp_path=tmp_path,
    )
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["unit"] == "g"


def test_calibrate_a_headerless_log_with_columns(tmp_path):
    log = SAMPLES / "headerless_imu_comma.csv"
    out = trical(
        "calibrate",
        str(log),
        "--columns",
        "t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z",
        "--json",
        "--no-store",
        tmp_path=tmp_path,
    )
    assert out.returncode == 0, out.stderr
    body = json.loads(out.stdout)
    assert body["unit"] == "g"
    np.testing.assert_allclose(body["model"]["X"], TRUTH["model"]["X"], atol=5e-3)
    bad = trical("calibrate", str(log), "--columns", "t,acc_x,acc_y,acc_z", "--no-store", tmp_path=tmp_path)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1
    assert "--columns names 4 columns (t, acc_x, acc_y, acc_z) but" in bad.stderr and "has 7 per line" in bad.stderr


def test_sign_option_overrides_the_ios_detection(tmp_path):
    log = str(SAMPLES / "sensorlog_ios.csv")
    detected = json.loads(trical("calibrate", log, "--json", "--no-store", tmp_path=tmp_path, check=True).stdout)
    kept = json.loads(
        trical("calibrate", log, "--sign", "1", "--json", "--no-store", tmp_path=tmp_path, check=True).stdout
    )
    np.testing.assert_allclose(detected["model"]["X"], TRUTH["model"]["X"], atol=5e-3)
    # Readings negated, their labels too: m' = -(X a + y) = X (-a) - y, the same X and the offset negated.
    np.testing.assert_allclose(kept["model"]["X"], detected["model"]["X"], atol=1e-9)
    np.testing.assert_allclose(kept["model"]["y"], -np.array(detected["model"]["y"]), atol=1e-9)
    bad = trical("calibrate", log, "--sign", "2", "--no-store", tmp_path=tmp_path)
    assert bad.returncode == 2 and "--sign" in bad.stderr and "Traceback" not in bad.stderr
