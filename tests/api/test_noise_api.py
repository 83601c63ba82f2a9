"""method noise end to end over HTTP: a real upload, the calibration resource, its exports, a moved recording."""

from __future__ import annotations

import io

import numpy as np
import pytest
import yaml

from simulations.noise import simulate_still
from tests.conftest import DATA

FS = 100.0


def _csv(moved: bool = False) -> bytes:
    rng = np.random.default_rng(21)
    n = 18_000
    acc = simulate_still(rng, n_samples=n, sampling_rate_hz=FS, N=2e-3, B=3e-4, K=1e-3, bias=[0.1, -0.2, 9.81])
    gyr = simulate_still(rng, n_samples=n, sampling_rate_hz=FS, N=1e-3, B=1e-4, K=3e-4)
    if moved:  # picked up and turned for 20 s after the first minute
        t = np.arange(2_000) / FS
        acc[6_000:8_000] = np.column_stack([9.81 * np.sin(t), 0.5 * np.sin(3 * t), 9.81 * np.cos(t)])
        gyr[6_000:8_000] += 1.0
    buf = io.StringIO()
    np.savetxt(
        buf,
        np.column_stack([np.arange(n) / FS, acc, gyr]),
        delimiter=",",
        comments="",
        fmt="%.9g",
        header="time_s,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z",
    )
    return buf.getvalue().encode()


def _noise(client, content: bytes) -> dict:
    r = client.post("/api/v1/recordings", files={"file": ("still.csv", content, "text/csv")})
    assert r.status_code == 201, r.text
    r = client.post("/api/v1/calibrations", json={"method": "noise", "recording_id": r.json()["id"]})
    assert r.status_code == 201, r.text
    return r.json()


def test_noise_of_an_upload_and_its_exports(client):
    body = _noise(client, _csv())
    assert body["method"] == "noise" and body["model"]["type"] == "noise" and body["ok"]
    gyr = body["model"]["gyr"]
    assert gyr["unit"] == "rad/s" and gyr["noise_density_unit"] == "rad/s/√Hz"
    np.testing.assert_allclose(gyr["noise_density"], 1e-3, rtol=0.1)
    assert len(body["adev"]["acc"]["tau_s"]) == len(body["adev"]["acc"]["value"])
    assert body["still"]["fraction"] > 0.99
    cal = body["id"]
    kalibr = yaml.safe_load(client.get(f"/api/v1/calibrations/{cal}/export?format=kalibr").text)
    assert kalibr["update_rate"] == FS
    assert abs(kalibr["gyroscope_noise_density"] / max(gyr["noise_density"]) - 1) < 1e-6
    vins = yaml.safe_load(client.get(f"/api/v1/calibrations/{cal}/export?format=vins").text)
    assert set(vins) == {"acc_n", "gyr_n", "acc_w", "gyr_w"}
    ov = client.get(f"/api/v1/calibrations/{cal}/export?format=openvins").text
    assert ov.startswith("%YAML:1.0") and "gyroscope_random_walk" in yaml.safe_load(ov.split("\n", 1)[1])["imu0"]
    table = client.get(f"/api/v1/calibrations/{cal}/export?format=csv").text.splitlines()
    assert (
        table[0] == "tau_s,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z" and len(table) == len(body["adev"]["acc"]["tau_s"]) + 1
    )
    r = client.get(f"/api/v1/calibrations/{cal}/export?format=c")
    assert r.status_code == 422 and r.json()["code"] == "export_refused" and "kalibr" in r.json()["detail"]
    r = client.post(f"/api/v1/calibrations/{cal}/apply", json={"samples": [[0, 0, 9.8]]})
    assert r.status_code == 422 and "corrects nothing" in r.json()["detail"]


def test_a_recording_that_moved_uses_its_still_part_with_a_warning(client):
    body = _noise(client, _csv(moved=True))
    assert body["still"]["fraction"] < 0.95
    assert any("the device moved" in w for w in body["warnings"])


def test_a_sensor_the_recording_lacks_is_refused(client):
    r = client.post("/api/v1/recordings", files={"file": ("still.csv", _csv(), "text/csv")})
    r = client.post(
        "/api/v1/calibrations", json={"method": "noise", "recording_id": r.json()["id"], "sensors": ["mag"]}
    )
    assert r.status_code == 422 and "no mag samples" in r.json()["detail"]


def test_half_a_second_of_a_real_still_board_is_too_short_everywhere_it_is_read(client):
    """The first 0.5 s of a real MPU-6050 resting (tests/data/real/mpu6050_session2_still_30s.csv): the upload lists
    the noise as not ready for the recording's length, the noise method answers ok false for the same cause with
    the same length to record (never a remedy asking for less than the list does), and still poses say that it is
    too short, not that it never rested."""
    lines = (DATA / "real" / "mpu6050_session2_still_30s.csv").read_text().splitlines()
    content = "\n".join([ln for ln in lines if not ln.startswith("#")][:51]).encode()  # the header and 50 rows
    r = client.post(
        "/api/v1/recordings",
        files={"file": ("still.csv", content, "text/csv")},
        data={"columns": "acc_x,acc_y,acc_z", "acc_unit": "raw", "lsb_per_g": "16384", "sampling_rate_hz": "100"},
    )
    assert r.status_code == 201, r.text
    rec = r.json()
    noise = next(s for s in rec["supports"] if s["method"] == "noise")
    assert not noise["ready"] and noise["why"] == "the recording lasts 0.5 s (the noise needs one rest of 5 s or more)"
    body = client.post("/api/v1/calibrations", json={"method": "noise", "recording_id": rec["id"]}).json()
    assert body["ok"] is False and body["reasons"][0].startswith("too short: the still part lasts 0.5 s (50 samples)")
    assert "5 s or more" in body["reasons"][0] and body["verdict"]["apply"] is False
    r = client.post("/api/v1/calibrations", json={"method": "auto", "recording_id": rec["id"]})
    assert r.status_code == 422 and r.json()["detail"].startswith("the recording is too short: it lasts 0.5 s")


def _without_lines(path, start_s: float, stop_s: float) -> bytes:
    """A real tagged log with the lines of [start_s, stop_s) from its first line removed: a logger that lost them."""
    lines = path.read_text().splitlines()
    t0 = float(lines[0].split()[1])
    return "\n".join(ln for ln in lines if not start_s <= (float(ln.split()[1]) - t0) / 1e3 < stop_s).encode()


def test_the_noise_is_read_on_the_longest_still_stretch_without_a_gap(client):
    """A real board's still gyroscope (tests/data/real/corpus/tagged_lines_gyro_still, 11.7 s, times in ms) with
    1.5 s of its lines removed after 7 s: the still part holds the gap, and the 7 s before it are taken, the gap
    named in a note, ok true; with a second gap no stretch lasts 5 s, and the gap is the reason, with a board's
    remedy (the serial port's), never a flight controller's."""
    gyro = DATA / "real" / "corpus" / "tagged_lines_gyro_still" / "gyro.txt"
    body = _noise(client, _without_lines(gyro, 7.0, 8.5))
    assert body["ok"], body["reasons"]
    (note,) = [w for w in body["warnings"] if "the longest stretch without one" in w]
    assert "(the longest 1.5 s at 7.0 s)" in note and "0.0–7.0 s" in note
    assert body["still"]["n_samples"] == pytest.approx(7.0 * body["sampling_rate_hz"], abs=2)
    lines = _without_lines(gyro, 7.0, 8.5).decode().splitlines()
    t0 = float(lines[0].split()[1])
    twice = "\n".join(ln for ln in lines if not 3.5 <= (float(ln.split()[1]) - t0) / 1e3 < 4.0).encode()
    body = _noise(client, twice)
    assert not body["ok"] and "no stretch without a gap lasts 5 s" in body["reasons"][0]
    assert "a faster serial baud rate" in body["reasons"][0]


def test_torn_reads_are_removed_and_named(client):
    """A seeded still MPU-6050 gyroscope in counts whose y axis holds 45 torn reads (±256 counts for one sample):
    the noise answer names the 45 spikes and reads the density of the clean recording."""
    rng = np.random.default_rng(46)
    n = 6_000
    gyr = np.round(simulate_still(rng, n_samples=n, sampling_rate_hz=FS, N=0.12, B=0.5, K=0.02, bias=[-427, 147, -81]))
    clean = _noise(client, _counts_csv(gyr))
    gyr[rng.choice(np.arange(50, n - 50, 100), size=45, replace=False), 1] += 256.0  # apart: 45 spikes, 45 samples
    body = _noise(client, _counts_csv(gyr))
    (said,) = [w for w in body["warnings"] if "spike" in w]
    assert "holds 45 spikes (45 on y)" in said and "torn read" in said
    np.testing.assert_allclose(body["model"]["gyr"]["noise_density"], clean["model"]["gyr"]["noise_density"], rtol=0.03)


def _counts_csv(gyr: np.ndarray) -> bytes:
    buf = io.StringIO()
    np.savetxt(
        buf,
        np.column_stack([np.arange(len(gyr)) / FS, gyr]),
        delimiter=",",
        comments="",
        fmt="%.6g",
        header="time_s,gyr_x,gyr_y,gyr_z",
    )
    return buf.getvalue().encode()
