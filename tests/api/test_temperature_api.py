"""Method temperature over real HTTP: a CSV with a temp_c column uploaded, calibrated, exported and drawn."""

from __future__ import annotations

import numpy as np
import pytest

from tests.temperature_logs import warm_up_csv


def _upload(client, name: str, content: bytes) -> str:
    r = client.post("/api/v1/recordings", files={"file": (name, content, "text/csv")})
    assert r.status_code == 201, r.text
    return r.json()["id"]


@pytest.mark.parametrize("header", ["temp_c", "T (°C)", "temperature"])
def test_a_warm_up_is_calibrated_exported_and_drawn(client, header):
    rec = _upload(
        client,
        "warm.csv",
        warm_up_csv(31, temperature_header=header, acc_in_g=True, duration_s=900, sampling_rate_hz=20),
    )
    r = client.post("/api/v1/calibrations", json={"method": "temperature", "recording_id": rec, "device_id": "fc1"})
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["ok"] and body["model"]["type"] == "temperature" and set(body["model"]) == {"type", "acc", "gyr"}
    assert body["model"]["acc"]["unit"] == "m/s^2"  # read in g, fitted in m/s² (the firmwares' unit)
    assert body["verdict"]["kind"] == "apply" and body["verdict"]["unit"] == "mg"
    assert body["headline"].startswith("offset drift over 15–")
    assert body["verdict"]["after"] < 0.25 * body["verdict"]["before"]
    for fmt, media in (
        ("px4", "text/plain"),
        ("ardupilot", "text/plain"),
        ("json", "application/json"),
        ("temperature_svg", "image/svg+xml"),
    ):
        e = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": fmt})
        assert e.status_code == 200, (fmt, e.text)
        assert e.headers["content-type"].startswith(media)
    assert "TC_G0_X1_2" in client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "px4"}).text
    e = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "c"})
    assert e.status_code == 422 and "temperature" in e.json()["detail"]


def test_a_log_without_temperature_is_refused_naming_what_to_give(client):
    text = warm_up_csv(32, duration_s=300, sampling_rate_hz=20).decode()
    lines = [",".join(line.split(",")[:-1]) for line in text.splitlines()]
    rec = _upload(client, "no_temp.csv", ("\n".join(lines) + "\n").encode())
    r = client.post("/api/v1/calibrations", json={"method": "temperature", "recording_id": rec})
    assert r.status_code == 422, r.text
    detail = r.json()["detail"]
    assert "temp_c column" in detail and "flight" in detail and "Traceback" not in detail


def test_applying_a_temperature_calibration_without_temperatures_is_a_4xx(client):
    rec = _upload(client, "warm.csv", warm_up_csv(33, duration_s=900, sampling_rate_hz=20))
    cal = client.post("/api/v1/calibrations", json={"method": "temperature", "recording_id": rec}).json()
    r = client.post(f"/api/v1/calibrations/{cal['id']}/apply", json={"samples": [[0, 0, 9.8]]})
    assert r.status_code == 422 and "temperature" in r.json()["detail"]


def test_unknown_sensors_are_refused_by_the_schema(client):
    r = client.post("/api/v1/calibrations", json={"method": "temperature", "recording_id": "rec_x", "sensors": ["mag"]})
    assert r.status_code == 422 and r.json()["code"] == "invalid_request"
    np.testing.assert_equal(r.json()["detail"].startswith("sensors[0]"), True)
