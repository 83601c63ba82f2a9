"""The trical command reads every log format too: a Sensor Logger zip and an Arduino log in counts."""

from __future__ import annotations

import json

import numpy as np

from tests.conftest import DATA
from tests.test_cli import trical

SAMPLES = DATA / "formats"
TRUTH = json.loads((SAMPLES / "format_samples.json").read_text())


def test_calibrate_a_zip_and_export_ardupilot(tmp_path):
    out = trical("calibrate", str(SAMPLES / "sensor_logger_ios.zip"), "--json", tmp_path=tmp_path, check=True)
    body = json.loads(out.stdout)
    assert body["unit"] == "g"
    np.testing.assert_allclose(body["model"]["X"], TRUTH["model"]["X"], atol=5e-3)
    params = trical("export", body["id"], "--format", "ardupilot", tmp_path=tmp_path, check=True).stdout
    assert "INS_ACCSCAL_Z" in params and "dropped_terms_residual_max" in params


def test_calibrate_counts_with_lsb_per_g(tmp_path):
    out = trical("calibrate", str(SAMPLES / "arduino_serial_plotter.txt"), "--sampling-rate-hz", "50",
                 "--lsb-per-g", "4096", "--log-format", "arduino", "--json", "--no-store", tmp_path=tmp_path)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["unit"] == "g"
