"""A flight controller's warm-up, as PX4 and ArduPilot log it, calibrated for temperature on a chosen IMU instance:
the readers' temperature (``sensor_accel.temperature``, ``IMU.T``) reaches the method, and the firmware's own file
comes out. The warm-up is the seeded simulation of the temperature tests (a known cubic, a real MPU-6050's noise),
written by the test writers of the formats (tests/flight_logs.py); the other instance rests at a constant
temperature, so only the instance asked for can be calibrated."""

from __future__ import annotations

import numpy as np
import pytest

from app.calibration.temperature import shift_polynomial
from simulations.temperature import ACC_TRUTH, GYR_TRUTH, T_POLY_REF_C
from tests.cli_in_process import run_main
from tests.flight_logs import ardupilot_file, px4_file
from tests.temperature_logs import warm_up

RATE_HZ = 50.0


def padded(coefficients) -> np.ndarray:
    """Each axis's coefficients (increasing powers, as many as its order) as four."""
    return np.array([list(c) + [0.0] * (4 - len(c)) for c in coefficients])


def warm_instances(seed: int) -> list[dict]:
    """Instance 0 at a constant 40 °C, instance 1 warming from 15 °C (FRD: at rest z reads −g)."""
    w = warm_up(seed, duration_s=900, sampling_rate_hz=RATE_HZ, gravity=(0.0, 0.0, -9.80665))
    time_us = (1_000_000 + np.round(w.time_s * 1e6)).astype(np.uint64)
    flat = {
        "time_us": time_us,
        "acc": np.tile([0.0, 0.0, -9.80665], (len(time_us), 1)) + 0.01,
        "gyr": np.zeros((len(time_us), 3)) + 1e-3,
        "temperature": np.full(len(time_us), 40.0),
    }
    return [flat, {"time_us": time_us, "acc": w.acc, "gyr": w.gyr, "temperature": w.temperature_c}]


@pytest.mark.parametrize("writer", [px4_file, ardupilot_file], ids=["px4_ulog", "ardupilot_dataflash"])
def test_a_flight_log_warm_up_is_calibrated_for_temperature_on_its_instance(client, tmp_path, writer):
    log = writer(tmp_path / ("warm.ulg" if writer is px4_file else "warm.bin"), warm_instances(41))
    with open(log, "rb") as f:
        r = client.post(
            "/api/v1/recordings",
            files={"file": (log.name, f.read(), "application/octet-stream")},
            data={"instance": "1"},
        )
    assert r.status_code == 201, r.text
    rec = r.json()
    assert (
        rec["flight"]["imu"]["instance"] == 1 and rec["temperature_c"]["min"] < 16 and rec["temperature_c"]["max"] > 45
    )
    r = client.post("/api/v1/calibrations", json={"method": "temperature", "recording_id": rec["id"]})
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["ok"], body["reasons"]
    # The gyroscope's offset polynomial is the truth's, moved to the fit's reference temperature.
    gyr = body["model"]["gyr"]
    truth = shift_polynomial(GYR_TRUTH, T_POLY_REF_C, gyr["t_ref_c"])
    T = np.linspace(gyr["t_min_c"], gyr["t_max_c"], 25)
    powers = np.vander(T - gyr["t_ref_c"], 4, increasing=True)
    fitted = powers @ padded(gyr["coefficients"]).T
    np.testing.assert_allclose(fitted, powers @ truth.T, atol=2e-4)  # rad/s; the drift is ~5e-3 over the range
    # The accelerometer's drift relative to its reading at the reference temperature.
    acc = body["model"]["acc"]
    truth = shift_polynomial(ACC_TRUTH, T_POLY_REF_C, acc["t_ref_c"])
    powers = np.vander(T - acc["t_ref_c"], 4, increasing=True)
    drift = powers @ padded(acc["coefficients"]).T
    expected = powers @ truth.T - truth[:, 0]
    np.testing.assert_allclose(drift - drift[12], expected - expected[12], atol=0.01)  # m/s²; ~0.1 over the range
    params = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "px4"}).text
    assert "TC_G_ENABLE" in params and "TC_A0_X1_0" in params
    # PX4 applies a slot only to the sensor whose device id it names: instance 1's, as the log recorded it
    # (the test writer's sensor_accel and sensor_gyro device_id 2424843); ArduPilot's IMU messages carry none.
    ids = {"TC_A0_ID": 2424843, "TC_G0_ID": 2424843} if writer is px4_file else {"TC_A0_ID": 0, "TC_G0_ID": 0}
    for name, value in ids.items():
        assert f"\t{name}\t{value}\t6" in params, params
    assert body.get("sensor_ids") == ({"acc": 2424843, "gyr": 2424843} if writer is px4_file else None)
    parm = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "ardupilot"}).text
    assert "INS_TCAL1_ENABLE" in parm


def test_the_instance_at_one_temperature_is_refused_in_words(client, tmp_path):
    """Instance 0 rests at 40 °C throughout: no polynomial of temperature can be fitted, and the answer says why."""
    log = px4_file(tmp_path / "warm.ulg", warm_instances(42))
    with open(log, "rb") as f:
        rec = client.post(
            "/api/v1/recordings",
            files={"file": ("warm.ulg", f.read(), "application/octet-stream")},
            data={"instance": "0"},
        ).json()
    r = client.post("/api/v1/calibrations", json={"method": "temperature", "recording_id": rec["id"]})
    assert r.status_code == 422, r.text
    detail = r.json()["detail"]
    assert "40.0–40.0 °C" in detail and "10 °C or more" in detail and "cold board" in detail, detail


def test_trical_temperature_reads_the_instance_of_a_flight_log(tmp_path):
    log = ardupilot_file(tmp_path / "warm.bin", warm_instances(43))
    run = run_main(  # the command in this process (tests/cli_in_process.py)
        ["temperature", str(log), "--instance", "1", "--sensor", "gyr"],
        {"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 't.db'}"},
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "ok = True" in run.stdout and "gyr (rad/s)" in run.stdout
