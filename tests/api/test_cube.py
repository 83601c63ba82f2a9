"""Method `cube` (003) through the API: a simulated 24-position session uploaded as a CSV log."""

from __future__ import annotations

import io

import numpy as np
import pytest

from app.calibration.cube.simulate import FIELD_UT, simulate_session, true_parameters

FS = 100.0


def session_csv(session, *, with_gyr=True) -> bytes:
    cols = [session.acc] + ([session.gyr] if with_gyr else []) + [session.mag]
    names = ["acc_x", "acc_y", "acc_z"] + (["gyr_x", "gyr_y", "gyr_z"] if with_gyr else []) + ["mag_x", "mag_y", "mag_z"]
    buf = io.StringIO()
    np.savetxt(buf, np.hstack(cols), delimiter=",", header=",".join(names), comments="", fmt="%.9g")
    return buf.getvalue().encode()


def upload_session(client, session, **kw):
    r = client.post("/api/v1/recordings", files={"file": ("cube.csv", session_csv(session, **kw), "text/csv")},
                    data={"sampling_rate_hz": str(FS), "acc_unit": "raw", "gyr_unit": "raw", "mag_unit": "raw"})
    assert r.status_code == 201, r.text
    return r.json()


@pytest.fixture(scope="module")
def good_session():
    return simulate_session(np.random.default_rng(21), sampling_rate_hz=FS)


def test_cube24_session_through_the_api(client, good_session):
    rec = upload_session(client, good_session)
    assert rec["channels"] == ["acc", "gyr", "mag"]
    r = client.post("/api/v1/calibrations", json={"method": "cube", "recording_id": rec["id"], "protocol": "cube24",
                                                  "field_ut": FIELD_UT})
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["ok"], body["reasons"]
    model, unc = body["model"], body["uncertainty"]
    assert model["type"] == "cube" and set(model["acc"]) >= {"S", "b", "D", "misalignment", "alpha_deg", "beta_deg"}
    for sensor in ("acc", "gyr", "mag"):
        S, b = true_parameters(sensor)
        assert np.all(np.abs(np.array(model[sensor]["S"]) - S) <= 3 * np.array(unc[sensor]["S"])), sensor
        assert np.all(np.abs(np.array(model[sensor]["b"]) - b) <= 3 * np.array(unc[sensor]["b"])), sensor
    assert len(body["sequence"]) == 23 and all(step["ok"] for step in body["sequence"])
    # raw = S f + b: applying the gyroscope model inverts it.
    f = np.array([[0.1, -0.2, 0.3]])
    S, b = np.array(model["gyr"]["S"]), np.array(model["gyr"]["b"])
    raw = f @ S.T + b
    out = client.post(f"/api/v1/calibrations/{body['id']}/apply", json={"samples": raw.tolist(), "sensor": "gyr"})
    np.testing.assert_allclose(out.json()["samples"], f, atol=1e-9)
    assert client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "json"}).status_code == 200
    c = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "c"})
    assert c.status_code == 422 and "json export" in c.json()["detail"]


def test_wrong_rotation_is_named(client):
    s = simulate_session(np.random.default_rng(12), sampling_rate_hz=FS, wrong_rotations={18: "y+"})
    rec = upload_session(client, s)
    body = client.post("/api/v1/calibrations", json={"method": "cube", "recording_id": rec["id"],
                                                     "field_ut": FIELD_UT}).json()
    assert body["ok"] is False and body["first_wrong_rotation"] == 18
    assert any("18" in reason for reason in body["reasons"])


def test_cube_bad_input(client, good_session):
    no_gyr = upload_session(client, good_session, with_gyr=False)
    r = client.post("/api/v1/calibrations", json={"method": "cube", "recording_id": no_gyr["id"], "field_ut": FIELD_UT})
    assert r.status_code == 422 and "no gyroscope columns" in r.json()["detail"]
    rec = upload_session(client, good_session)
    r = client.post("/api/v1/calibrations", json={"method": "cube", "recording_id": rec["id"], "protocol": "ferraris",
                                                  "field_ut": FIELD_UT})
    assert r.status_code == 422 and "ferraris" in r.json()["detail"]
    r = client.post("/api/v1/calibrations", json={"method": "cube", "recording_id": rec["id"]})
    assert r.status_code == 422 and "field_ut" in r.json()["detail"]
    r = client.post("/api/v1/calibrations", json={"method": "cube", "recording_id": rec["id"], "protocol": "dodecahedron"})
    assert r.status_code == 422 and "protocol" in r.json()["detail"]
    r = client.post("/api/v1/calibrations", json={"method": "cube", "recording_id": rec["id"], "field_ut": FIELD_UT,
                                                  "protocol": {"rotations": "nonsense"}})
    assert r.status_code == 422
