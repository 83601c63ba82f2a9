"""method: autocal through POST /api/v1/calibrations on an uploaded .npy recording (issue 4)."""

from __future__ import annotations

import io

import numpy as np

from simulations.autocal import simulate_recording

FS = 10.0


def _npy(x) -> bytes:
    buf = io.BytesIO()
    np.save(buf, x)
    return buf.getvalue()


def _upload(client, data: bytes, name: str):
    return client.post(
        "/api/v1/recordings",
        files={"file": (name, data, "application/octet-stream")},
        data={"sampling_rate_hz": str(FS), "acc_unit": "g"},
    )


def test_autocal_on_uploaded_npy(client):
    x, _truth = simulate_recording(
        np.random.default_rng(11),
        duration_s=6 * 3600,
        sampling_rate_hz=FS,
        rest_median_s=30,
        move_median_s=10,
        posture_fraction=0.3,
    )
    r = _upload(client, _npy(x), "wrist.npy")
    assert r.status_code == 201, r.text
    assert r.json()["format"] == "npy"
    r = client.post("/api/v1/calibrations", json={"method": "autocal", "recording_id": r.json()["id"]})
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["method"] == "autocal" and body["ok"] is True, body["reasons"]
    assert body["model"]["type"] == "triangular" and body["label"] == "wrist.npy"
    assert body["metrics"]["error_after_mg"] < 1.0 < 10.0 < body["metrics"]["error_before_mg"]
    r = client.post(f"/api/v1/calibrations/{body['id']}/apply", json={"samples": [[0.0, 0.0, 1.0]]})
    assert r.status_code == 200, r.text


def test_autocal_without_rest_is_stored_not_ok(client):
    x, _ = simulate_recording(np.random.default_rng(2), duration_s=600, sampling_rate_hz=FS, rest_median_s=0)
    rec = _upload(client, _npy(x), "moving.npy").json()
    r = client.post("/api/v1/calibrations", json={"method": "autocal", "recording_id": rec["id"]})
    assert r.status_code == 201
    # The cause first: it never rested (no unit or rate to give would change that).
    assert r.json()["ok"] is False and r.json()["reasons"][0].startswith("it never rested: all 120 segments")


def test_autocal_bad_requests_are_4xx(client):
    r = client.post("/api/v1/calibrations", json={"method": "autocal", "recording_id": "rec_missing"})
    assert r.status_code == 404
    r = _upload(client, b"\x93NUMPY garbage", "broken.npy")
    assert 400 <= r.status_code < 500
