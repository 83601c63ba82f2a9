"""The gyroscope bias of a wizard session (app.calibration.still.gyro_bias), through real HTTP calls: six and free
sessions, the calibration's `gyroscope_bias` and its exports (ArduPilot INS_GYROFFS_*, C header, JSON)."""

from __future__ import annotations

import re

import numpy as np
from pydantic import TypeAdapter
from scipy import stats

from app.api.schemas.calibrations import CalibrationOut
from app.api.schemas.sessions import SessionOut
from app.calibration import CANONICAL_SIX
from app.calibration.still.advice import fibonacci_sphere
from tests.api.test_sessions import auth, start
from tests.api.test_typed_contract import undescribed
from tests.phone_poses import direction_samples, pose_samples

BIAS_DEG_S = np.array([0.35, -0.2, 0.12])  # a phone gyroscope at rest
WANDER_DEG_S = 0.02  # its bias's wander between captures


def _with_gyro(body: dict, rng, *, unit: str = "deg/s") -> dict:
    """A capture whose gyroscope reads the bias, a wander of it and white noise (0.3 °/s per sample)."""
    n = len(body["acc"])
    gyr_deg_s = BIAS_DEG_S + rng.normal(0.0, WANDER_DEG_S, 3) + rng.normal(0.0, 0.3, (n, 3))
    gyr = gyr_deg_s if unit == "deg/s" else np.radians(gyr_deg_s)
    return dict(body, gyr=gyr.tolist(), gyr_unit=unit)


def _post(client, s, body):
    r = client.post(f"/api/v1/sessions/{s['id']}/captures", json=body, headers=auth(s["token"]))
    assert r.status_code == 201, r.text
    return r.json()


def _solve(client, s) -> dict:
    r = client.post(f"/api/v1/sessions/{s['id']}/solve", headers=auth(s["token"]))
    assert r.status_code == 201, r.text
    cal = r.json()
    assert undescribed(TypeAdapter(CalibrationOut).validate_python(cal)) == []
    return cal


def _export(client, s, cal, fmt: str):
    r = client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": fmt}, headers=auth(s["token"]))
    assert r.status_code == 200, r.text
    return r


def _ardupilot_gyroffs(text: str) -> np.ndarray:
    found = dict(re.findall(r"^INS_GYROFFS_([XYZ]) (\S+)$", text, flags=re.M))
    assert sorted(found) == ["X", "Y", "Z"], text
    return np.array([float(found[a]) for a in "XYZ"])


def test_a_six_session_reports_the_gyroscope_bias_and_ardupilot_removes_it(client):
    rng = np.random.default_rng(12)
    s = start(client)
    sent = []
    for label in ("+z", "-x", "+y", "-z", "+x", "-y"):
        body = _with_gyro(pose_samples(label, rng), rng)
        capture = _post(client, s, body)["capture"]
        SessionOut.model_validate(client.get(f"/api/v1/sessions/{s['id']}", headers=auth(s["token"])).json())
        np.testing.assert_allclose(capture["gyr_mean"], np.mean(body["gyr"], axis=0), rtol=0, atol=1e-12)
        assert capture["gyr_count"] == 300 and capture["gyr_unit"] == "deg/s"
        sent.append(np.radians(np.array(body["gyr"])))  # rad/s, as ArduPilot's drivers give the gyroscope
    cal = _solve(client, s)
    bias = cal["gyroscope_bias"]
    means = np.array([g.mean(axis=0) for g in sent])
    np.testing.assert_allclose(bias["rad_s"], means.mean(axis=0), rtol=0, atol=1e-9)
    np.testing.assert_allclose(bias["deg_s"], np.degrees(means.mean(axis=0)), rtol=0, atol=1e-9)
    half = stats.t.ppf(0.975, 5) * means.std(axis=0, ddof=1) / np.sqrt(6)
    np.testing.assert_allclose(bias["half_width_rad_s"], half, rtol=1e-9)
    assert (bias["count"], bias["confidence"], bias["interval_from"]) == (6, 0.95, "captures")
    np.testing.assert_allclose(bias["deg_s"], BIAS_DEG_S, atol=0.05)  # near the truth too
    again = client.get(f"/api/v1/calibrations/{cal['id']}", headers=auth(s["token"])).json()
    assert again["gyroscope_bias"] == bias

    # ArduPilot (AP_InertialSensor_Backend::_rotate_and_correct_gyro): gyro -= _gyro_offset, rad/s, sensor frame.
    text = _export(client, s, cal, "ardupilot").text
    offset = _ardupilot_gyroffs(text)
    np.testing.assert_allclose(offset, bias["rad_s"], rtol=1e-8, atol=0)  # 9 significant digits
    corrected = [g - offset for g in sent]  # corrected = raw − INS_GYROFFS
    np.testing.assert_allclose(np.vstack(corrected).mean(axis=0), 0.0, atol=1e-9)
    for g, raw in zip(corrected, sent):  # each still capture: only its wander and noise are left
        assert np.all(np.abs(g.mean(axis=0)) < np.radians(0.1))
        assert np.all(np.abs(g.mean(axis=0)) < np.abs(raw.mean(axis=0)))
    assert "w_i = m_i - INS_GYROFFS_i, m and INS_GYROFFS in rad/s" in text and "INS_GYR_CAL" in text

    doc = _export(client, s, cal, "json").json()
    assert doc["gyroscope"] == {
        "formula": "w = m - b",
        "unit": "rad/s",
        "bias": bias["rad_s"],
        "half_width": bias["half_width_rad_s"],
        "confidence": 0.95,
        "count": 6,
        "interval_from": "captures",
    }
    header = _export(client, s, cal, "c").text
    values = re.search(r"#define TRICAL_GYRO_BIAS_RAD_S \{(\S+)f, (\S+)f, (\S+)f\}", header)
    np.testing.assert_allclose([float(v) for v in values.groups()], bias["rad_s"], rtol=1e-8)


def test_a_free_session_in_rad_s_reports_the_bias_in_rad_s(client):
    rng = np.random.default_rng(13)
    s = start(client, protocol="free", capture_s=5)
    sent = []
    for up in fibonacci_sphere(16)[:12]:
        body = _with_gyro(direction_samples(up, rng, noise=0.05), rng, unit="rad/s")
        assert _post(client, s, body)["capture"]["gyr_unit"] == "rad/s"
        sent.append(np.array(body["gyr"]))
    cal = _solve(client, s)
    assert cal["method"] == "triangular"
    means = np.array([g.mean(axis=0) for g in sent])
    np.testing.assert_allclose(cal["gyroscope_bias"]["rad_s"], means.mean(axis=0), rtol=0, atol=1e-9)
    assert cal["gyroscope_bias"]["count"] == 12
    offset = _ardupilot_gyroffs(_export(client, s, cal, "ardupilot").text)
    np.testing.assert_allclose(np.vstack(sent).mean(axis=0) - offset, 0.0, atol=1e-9)


def test_one_capture_with_the_gyroscope_takes_the_interval_from_its_samples(client):
    rng = np.random.default_rng(14)
    s = start(client)
    for label in CANONICAL_SIX:
        body = pose_samples(label, rng)
        body = _with_gyro(body, rng) if label == "+z" else dict(body, gyr=None)
        _post(client, s, body)
        if label == "+z":
            gyr = np.radians(np.array(body["gyr"]))
    bias = _solve(client, s)["gyroscope_bias"]
    assert (bias["count"], bias["interval_from"]) == (1, "samples")
    np.testing.assert_allclose(bias["rad_s"], gyr.mean(axis=0), rtol=0, atol=1e-9)
    half = stats.t.ppf(0.975, 299) * gyr.std(axis=0, ddof=1) / np.sqrt(300)
    np.testing.assert_allclose(bias["half_width_rad_s"], half, rtol=1e-9)


def test_without_the_gyroscope_there_is_no_bias_and_the_exports_are_as_before(client):
    rng = np.random.default_rng(15)
    s = start(client)
    for label in CANONICAL_SIX:
        capture = _post(client, s, dict(pose_samples(label, rng), gyr=None))["capture"]
        assert capture["gyr_mean"] is None and capture["gyr_count"] is None
    cal = _solve(client, s)
    assert "gyroscope_bias" not in cal
    assert "INS_GYROFFS" not in _export(client, s, cal, "ardupilot").text
    assert "gyroscope" not in _export(client, s, cal, "json").json()
    assert "TRICAL_GYRO_BIAS_RAD_S" not in _export(client, s, cal, "c").text
