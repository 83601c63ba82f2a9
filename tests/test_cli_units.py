"""``trical calibrate`` and ``trical export`` with units the data contradict, counts, and --chip, run as a
user runs them (in this process: tests/cli_in_process.py)."""

from __future__ import annotations

import json
import re

import numpy as np

from simulations.logs import simulate_static_log
from simulations.magnetometer import simulate_session
from tests.cli_in_process import trical

G = 9.80665
MAG, _, B_TRUE = simulate_session(7, n=600)


def _write(path, header, columns, fmt="%.6f"):
    timed = header.startswith("t,")
    with open(path, "w") as f:
        f.write(header + "\n")
        for row in np.column_stack(columns):
            f.write(",".join(f"{v:.3f}" if (i == 0 and timed) else (fmt % v) for i, v in enumerate(row)) + "\n")
    return path


def test_a_g_header_over_m_s2_values_calibrates_and_warns(tmp_path):
    six = simulate_static_log(np.random.default_rng(22), sampling_rate_hz=100.0, rest_s=(3.0, 4.0))
    t = np.arange(len(six.samples)) / 100.0
    path = _write(tmp_path / "board.csv", "t,aX (g),aY (g),aZ (g)", [t, six.samples])
    out = trical("calibrate", str(path), "--no-store", tmp_path=tmp_path)
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines()[0].startswith("--method auto, chosen from the recording:")
    assert out.stdout.splitlines()[2].startswith("Apply it:")
    assert re.search(
        r"^warning: the header said g for the accelerometer, but its readings rest at a median norm of "
        r"9\.\d+, about 1 g in m/s\^2: calibrated in m/s\^2$",
        out.stdout,
        re.M,
    ), out.stdout


def test_a_magnetometer_in_counts_prints_counts_and_chip_makes_it_ut(tmp_path):
    path = _write(tmp_path / "mag.csv", "mag_x,mag_y,mag_z", [np.round(MAG / 0.15)], "%.0f")
    counts = trical(
        "calibrate", str(path), "--method", "magnetometer", "--sampling-rate-hz", "50", "--json", tmp_path=tmp_path
    )
    assert counts.returncode == 0, counts.stderr
    body = json.loads(counts.stdout)
    assert body["output_unit"] == "raw" and " counts of the " in body["headline"] and "µT" not in body["headline"]
    refused = trical("export", body["id"], "--format", "ardupilot", tmp_path=tmp_path)
    assert refused.returncode == 2 and len(refused.stderr.splitlines()) == 1
    assert "upload the log again with --chip" in refused.stderr
    human = trical(
        "calibrate",
        str(path),
        "--method",
        "magnetometer",
        "--sampling-rate-hz",
        "50",
        "--chip",
        "ak8963-16bit",
        "--field-ut",
        "48",
        tmp_path=tmp_path,
    )
    assert human.returncode == 0, human.stderr
    assert re.search(r"expect \d\.\d\d µT of the 48\.0 µT field", human.stdout), human.stdout
    b = np.array([float(v) for v in re.search(r"^b = (.*)$", human.stdout, re.M).group(1).split()])
    np.testing.assert_allclose(b, B_TRUE, atol=0.1)
    assert "counts" not in human.stdout


def test_an_unknown_chip_is_one_line(tmp_path):
    path = _write(tmp_path / "mag.csv", "mag_x,mag_y,mag_z", [MAG])
    out = trical("calibrate", str(path), "--chip", "ak8964", tmp_path=tmp_path)
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1
    assert "chip 'ak8964' is not one trical knows: give one of mpu6050-2g" in out.stderr
