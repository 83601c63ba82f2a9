"""Flight controllers' logs uploaded and calibrated on a chosen instance: six and free poses from the rests, the
compass from a tumble, the noise and the gyroscope's bias from a still log (logs written by tests/flight_logs.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

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

DATA = Path(__file__).resolve().parents[1] / "data" / "flight_logs"
FREE_POSES = [
    [0.0, 0.0, 1.0],
    [0.0, 0.0, -1.0],
    [1.0, 0.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, -1.0, 0.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, -1.0],
    [1.0, -1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, -1.0],
    [-1.0, 1.0, 0.0],
    [0.0, -1.0, -1.0],
]
"""Fourteen poses, the six and eight between them: enough for the nine parameters of the triangular model."""


def _upload(client, path: Path, **fields):
    r = client.post(
        "/api/v1/recordings",
        files={"file": (path.name, path.read_bytes())},
        data={k: str(v) for k, v in fields.items()},
    )
    return r


def _calibrate(client, recording_id: str, method: str, **extra):
    r = client.post("/api/v1/calibrations", json={"method": method, "recording_id": recording_id, **extra})
    assert r.status_code == 201, r.text
    return r.json()


@pytest.mark.parametrize("write", [px4_file, ardupilot_file])
def test_six_poses_of_the_chosen_imu(client, tmp_path, write):
    path = write(tmp_path / ("six.ulg" if write is px4_file else "six.bin"), imu_instances(3))
    r = _upload(client, path, instance=1)
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["format"] == ("ulog" if write is px4_file else "dataflash")
    assert rec["read_with"]["instance"] == 1 and rec["flight"]["imu"]["instance"] == 1
    assert rec["sampling_rate_hz"] == pytest.approx(200.0, rel=1e-9)
    assert rec["temperature_c"]["min"] == pytest.approx(31.0, abs=1e-3)
    assert rec["temperature_c"]["max"] == pytest.approx(35.0, abs=1e-3)
    listed = {(i["sensor"], i["instance"]) for i in rec["flight"]["instances"]}
    assert listed == {("acc", 0), ("acc", 1), ("gyr", 0), ("gyr", 1)}
    assert sorted(s["up"] for s in rec["segments"]) == sorted(["+x", "-x", "+y", "-y", "+z", "-z"])
    # The stored file is read again with its instance: the fit is instance 1's error, not instance 0's.
    body = _calibrate(client, rec["id"], "six_position")
    X, y = TRUTH[1]
    assert body["ok"], body["reasons"]
    assert body["source"] == ("px4" if write is px4_file else "ardupilot")  # its firmware's parameters first
    np.testing.assert_allclose(body["model"]["X"], X, atol=3e-4)
    np.testing.assert_allclose(body["model"]["y"], y, atol=3e-3)
    assert np.abs(np.asarray(body["model"]["y"]) - y).max() < np.abs(TRUTH[0][1] - y).max() / 20
    assert r.json()["flight"]["imu"] == client.get(f"/api/v1/recordings/{rec['id']}").json()["flight"]["imu"]


def test_free_poses_of_the_chosen_imu(client, tmp_path):
    path = ardupilot_file(tmp_path / "free.bin", imu_instances(8, orientations=FREE_POSES, rest_s=(3.0, 4.0)))
    rec = _upload(client, path, instance=1).json()
    assert len(rec["segments"]) == len(FREE_POSES)
    body = _calibrate(client, rec["id"], "triangular")
    X, y = TRUTH[1]
    assert body["ok"], body["reasons"]
    # a = K (v + o) with K = X⁻¹ (lower triangular) and o = −y: Farago, Maczak and Gingl, IEEE Access, eq. (6)
    np.testing.assert_allclose(body["model"]["K"], np.linalg.inv(X), atol=5e-4)
    np.testing.assert_allclose(body["model"]["o"], -y, atol=5e-3)


@pytest.mark.parametrize("write", [px4_file, ardupilot_file])
def test_compass_of_the_chosen_instance_from_a_tumble(client, tmp_path, write):
    imus, mags, Ms = compass_tumble(5)
    path = write(tmp_path / ("tumble.ulg" if write is px4_file else "tumble.bin"), imus, mags)
    rec = _upload(client, path, mag_instance=1).json()
    assert rec["channels"] == ["acc", "gyr"]  # on the IMU's clock; the compass is read on its own
    rows = {(i["sensor"], i["instance"]): i for i in rec["flight"]["instances"]}
    assert rows[("mag", 1)]["sampling_rate_hz"] == pytest.approx(50.0, rel=1e-6)
    assert rows[("mag", 1)]["n_samples"] == 1000
    body = _calibrate(client, rec["id"], "magnetometer", field_ut=48.0)
    assert body["ok"], body["reasons"]
    # int16 milligauss (ArduPilot) rounds to 0.1 µT; noise 0.2 µT over 1000 readings
    np.testing.assert_allclose(body["model"]["b"], HARD_IRON_UT[1], atol=0.1)
    assert np.all(np.abs(np.asarray(body["model"]["b"]) - HARD_IRON_UT[1]) <= 4 * np.asarray(body["uncertainty"]["b"]))
    np.testing.assert_allclose(body["model"]["M"], Ms[1], atol=3e-3)
    # the default compass is instance 0, whose hard iron differs
    other = _calibrate(client, _upload(client, path).json()["id"], "magnetometer", field_ut=48.0)
    np.testing.assert_allclose(other["model"]["b"], HARD_IRON_UT[0], atol=0.1)


def test_noise_and_gyroscope_bias_of_the_chosen_imu(client, tmp_path):
    path = px4_file(tmp_path / "still.ulg", still_board(9))
    rec = _upload(client, path, instance=1).json()
    assert rec["temperature_c"] == {"min": 41.0, "max": 41.0}
    body = _calibrate(client, rec["id"], "noise")
    assert body["ok"], body["reasons"]
    gyr = body["model"]["gyr"]
    low, high = np.asarray(body["uncertainty"]["gyr"]["bias"]).T
    assert np.all((low <= GYR_BIAS[1]) & (GYR_BIAS[1] <= high)), (low, high)
    np.testing.assert_allclose(gyr["bias"], GYR_BIAS[1], atol=5e-4)
    np.testing.assert_allclose(gyr["noise_density"], 2e-3, rtol=0.08)
    np.testing.assert_allclose(body["model"]["acc"]["noise_density"], 3e-3, rtol=0.08)


def test_noise_of_the_compass_on_its_own_clock(client, tmp_path):
    imus = still_board(2, rate_hz=200.0, duration_s=60.0)
    rng = np.random.default_rng(12)
    n = 60 * 50
    mags = [
        {
            "time_us": (1_000_000 + np.arange(n) * 20_000).astype(np.uint64),
            "mag": np.array([20.0, -5.0, 40.0]) + rng.normal(0.0, 0.3, (n, 3)),
        }
    ]
    rec = _upload(client, px4_file(tmp_path / "still_mag.ulg", imus, mags)).json()
    body = _calibrate(client, rec["id"], "noise", sensors=["mag"])
    assert body["sampling_rate_hz"] == pytest.approx(50.0, rel=1e-6)
    # white noise of 0.3 µT per sample at 50 Hz: σ(τ) = N/√τ with σ(1/50 s) = 0.3, so N = 0.3/√50 µT/√Hz
    np.testing.assert_allclose(body["model"]["mag"]["noise_density"], 0.3 / np.sqrt(50.0), rtol=0.08)
    r = client.post(
        "/api/v1/calibrations", json={"method": "noise", "recording_id": rec["id"], "sensors": ["acc", "mag"]}
    )
    assert r.status_code == 422 and "compass is read on its own clock" in r.json()["detail"]


def test_sample_logs_upload_with_their_instances(client):
    rec = _upload(client, DATA / "test.BIN").json()
    rows = {(i["sensor"], i["instance"]): i for i in rec["flight"]["instances"]}
    assert set(rows) == {("acc", 0), ("acc", 1), ("gyr", 0), ("gyr", 1), ("mag", 0), ("mag", 1), ("mag", 2)}
    assert rows[("acc", 1)]["temperature_min_c"] == pytest.approx(39.92295, abs=1e-4)
    assert rows[("acc", 0)]["device"]["bus_type"] == "spi"
    rec = _upload(client, DATA / "sample_log_small.ulg", instance=2).json()
    assert rec["flight"]["imu"] == {"instance": 2, "source": "sensor_accel", "gyr_source": "sensor_gyro"}
    assert rec["n_samples"] == 6 and rec["temperature_c"]["min"] == pytest.approx(29.4344215, abs=1e-5)


@pytest.mark.parametrize(
    "name, cut, fields, words",
    [
        ("test.BIN", None, {"instance": 4}, "has no IMU instance 4: its IMU instances are 0, 1"),
        ("test.BIN", None, {"mag_instance": 3}, "its magnetometer instances are 0, 1, 2"),
        ("sample_log_small.ulg", None, {"instance": 3}, "its IMU instances are 0, 1, 2"),
        ("sample_log_small.ulg", 400, {}, "PX4 ULog"),
        ("test.BIN", 500, {}, "DataFlash log without IMU samples"),
        ("test.BIN", None, {"chip": "mpu6050-2g"}, "chip is for text logs"),
    ],
)
def test_bad_flight_logs_and_instances_are_refused_naming_the_problem(client, tmp_path, name, cut, fields, words):
    data = (DATA / name).read_bytes()
    path = tmp_path / name
    path.write_bytes(data if cut is None else data[:cut])
    r = _upload(client, path, **fields)
    assert r.status_code == 422, r.text
    assert words in r.json()["detail"]


def test_an_instance_is_refused_for_a_csv(client, tmp_path):
    path = tmp_path / "still.csv"
    path.write_text("t,ax,ay,az\n" + "".join(f"{i / 100},0,0,9.81\n" for i in range(400)))
    r = _upload(client, path, instance=0)
    assert r.status_code == 422 and "flight controller's log" in r.json()["detail"]
    r = _upload(client, DATA / "test.BIN", instance=-1)
    assert r.status_code == 422
