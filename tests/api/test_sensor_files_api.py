"""Issue 31, points 3, 4 and 8 through the upload, as the page sends it: one recording in one file per
sensor, JSON arrays of samples, the Betaflight configurator's compass-tumble export, a binary of no known
format, and the page's file chooser offering every format trical reads.
"""

from __future__ import annotations

import json
import re

import numpy as np

from app.io.readers.kinds import ACCEPTED_SUFFIXES
from tests.conftest import DATA

IPHONE = DATA / "real" / "corpus" / "iphone_heading_per_sensor_files"
BETAFLIGHT = (
    DATA / "real" / "corpus" / "betaflight_mag_characterization_model" / "characterization_model_2026-06-26.json"
)


def upload(client, files: list[tuple[str, bytes]], **form):
    return client.post(
        "/api/v1/recordings", files=[("file", (n, b, "application/octet-stream")) for n, b in files], data=form
    )


def test_the_files_of_an_iphones_sensors_are_one_recording_in_any_order(client):
    names = ["gyroscope.csv", "magnetometer.csv", "accelerometer.csv"]  # the accelerometer's clock, wherever it is
    r = upload(client, [(n, (IPHONE / n).read_bytes()) for n in names])
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["channels"] == ["acc", "gyr", "mag"]
    assert rec["units"] == {"acc": "g", "gyr": "rad/s", "mag": "raw"}
    assert rec["n_samples"] == 1490 and abs(rec["sampling_rate_hz"] - 102.9) < 0.1
    assert any(
        n.startswith(
            "one recording in 3 files, one per sensor: gyroscope.csv the gyroscope (rad/s), "
            "magnetometer.csv the magnetometer (raw), accelerometer.csv the accelerometer (g)"
        )
        for n in rec["notes"]
    )
    assert any("merged on the clock of accelerometer.csv" in n for n in rec["notes"])
    assert any(
        w.startswith("magnetometer.csv: the magnetometer's readings show a field of 480") for w in rec["warnings"]
    )


def test_an_accelerometer_and_a_gyroscope_file_of_one_still_recording_are_not_refused_for_their_units(client):
    """The issue's case: the gyroscope's file was read as an accelerometer in counts, and the two files refused."""
    rng = np.random.default_rng(31)
    t = 1000 + np.arange(1500) / 100.0
    acc = np.array([0.02, -0.01, 1.0]) + 0.002 * rng.standard_normal((1500, 3))
    gyr = np.array([-1.2, 0.8, 4.5]) + 0.05 * rng.standard_normal((1500, 3))  # deg/s of a still MPU-6050

    def table(v):
        return (
            "t,x,y,z\n" + "\n".join(f"{a:.3f},{x:.5f},{y:.5f},{z:.5f}" for a, (x, y, z) in zip(t, v)) + "\n"
        ).encode()

    r = upload(client, [("mpu_accelerometer.csv", table(acc)), ("mpu_gyroscope.csv", table(gyr))], gyr_unit="deg/s")
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["channels"] == ["acc", "gyr"] and rec["units"] == {"acc": "g", "gyr": "deg/s"}
    assert rec["n_samples"] == 1500


def test_a_json_array_of_samples_is_read_and_named(client):
    samples = [{"t": round(i * 0.01, 3), "x": 0.01, "y": -0.02, "z": 0.98 + 0.001 * (i % 3)} for i in range(400)]
    r = upload(client, [("samples.json", json.dumps(samples).encode())])
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["channels"] == ["acc"] and rec["units"] == {"acc": "g"} and rec["sampling_rate_hz"] == 100.0
    assert "read as JSON: the top-level array, 400 samples, keys t, x, y, z" in rec["notes"]


def test_a_json_object_of_no_samples_is_refused_naming_what_it_holds(client):
    r = upload(client, [("settings.json", json.dumps({"name": "quad", "rate": 500}).encode())])
    assert r.status_code == 422
    assert "settings.json is a JSON object (keys 'name', 'rate') holding no array of samples" in r.json()["detail"]


def test_the_betaflight_configurators_tumble_export_is_refused_saying_it_holds_no_samples(client):
    r = upload(client, [(BETAFLIGHT.name, BETAFLIGHT.read_bytes())])
    assert r.status_code == 422
    detail = r.json()["detail"]
    assert "the Betaflight configurator's magnetometer characterization model (version 2.2)" in detail
    assert "none of the 250 samples it was fitted to" in detail and "line 1" not in detail


def test_a_binary_of_no_known_format_named_bin_lists_the_formats_trical_reads(client):
    data = bytes(np.random.default_rng(8).integers(0, 256, 4000, dtype=np.uint8))
    data = b"\xba" + data[1:]
    r = upload(client, [("capture.bin", data)])
    assert r.status_code == 415
    detail = r.json()["detail"]
    assert detail.startswith("capture.bin is not a format trical reads: its first bytes (ba ")
    assert "utf-8" not in detail and "wearable device file:" not in detail
    for suffix in ACCEPTED_SUFFIXES:
        assert suffix in detail


def test_the_pages_file_chooser_offers_every_format_trical_reads(client):
    page = client.get("/").text
    accept = re.search(r'id="log-file"[^>]*accept="([^"]*)"', page).group(1).split(",")
    assert accept == list(ACCEPTED_SUFFIXES)
    assert {".csv", ".json", ".zip", ".ulg", ".bin", ".npy", ".parquet", ".cwa", ".gt3x"} <= set(accept)
