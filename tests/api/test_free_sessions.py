"""The free-pose wizard's server side (issue 11, item 5): any still poses, the triangular model from 10 on,
its cross-validated error and the advice after each capture, a target or a Stop."""

from __future__ import annotations

import numpy as np
import pytest
from pydantic import TypeAdapter

from app.api.schemas.calibrations import CalibrationOut
from app.api.schemas.sessions import SessionOut
from app.calibration.still.advice import fibonacci_sphere
from tests.api.test_sessions import auth, start
from tests.api.test_typed_contract import undescribed
from tests.phone_poses import X_TRUE, Y_TRUE, direction_samples

UPS = fibonacci_sphere(16)  # well spread poses
G = 9.80665


def capture(client, s, up, rng, **extra):
    return client.post(
        f"/api/v1/sessions/{s['id']}/captures",
        json=dict(direction_samples(up, rng, noise=0.05), **extra),
        headers=auth(s["token"]),
    )


def test_poses_until_the_target_then_the_calibration_recovers_the_phone(client):
    rng = np.random.default_rng(11)
    s = start(client, protocol="free", capture_s=5)
    assert s["protocol"] == "free" and s["positions"] == [] and s["remaining"] == [] and s["target_mg"] == 2.0
    progress = s["progress"]
    assert progress["count"] == 0 and progress["cv_error_mg"] is None and not progress["target_reached"]
    assert len(progress["advice"]) == 3 and progress["advice"][0]["gain"] is None
    seen = []
    for k, up in enumerate(UPS):
        r = capture(client, s, up, rng)
        assert r.status_code == 201, r.text
        body = r.json()
        assert body["capture"]["position"] == str(k + 1) and body["capture"]["up"] in (
            "+x",
            "-x",
            "+y",
            "-y",
            "+z",
            "-z",
        )
        progress = body["session"]["progress"]
        SessionOut.model_validate(body["session"])
        seen.append(progress)
        if progress["target_reached"]:
            break
    before_fit = [p for p in seen if p["count"] < 10]
    assert all(p["cv_error_mg"] is None and "before the first estimate" in p["message"] for p in before_fit)
    assert before_fit[-1]["message"] == "9 poses captured: 1 more before the first estimate"
    fitted = [p for p in seen if p["count"] >= 10]
    assert all(p["cv_error_mg"] is not None and p["advice"][0]["gain"] > 0 for p in fitted)
    assert seen[-1]["target_reached"] and seen[-1]["count"] >= 12 and seen[-1]["cv_error_mg"] < 2.0
    assert seen[-1]["message"].startswith("target reached: ")
    got = client.get(f"/api/v1/sessions/{s['id']}", headers=auth(s["token"])).json()
    assert got["progress"] == seen[-1]

    r = client.post(f"/api/v1/sessions/{s['id']}/solve", headers=auth(s["token"]))
    assert r.status_code == 201, r.text
    cal = r.json()
    assert cal["method"] == "triangular" and cal["session_id"] == s["id"] and len(cal["captures"]) == seen[-1]["count"]
    assert cal["finish"]["reason"] == "target" and cal["finish"]["text"].startswith("target reached: ")
    assert cal["finish"]["text"].endswith(" mg on new orientations") and len(cal["advice"]) == 3
    assert undescribed(TypeAdapter(CalibrationOut).validate_python(cal)) == []
    # The correction a = K (m + o) undoes the phone's m = X a + y up to a rotation: K X is orthogonal.
    K, o = np.array(cal["model"]["K"]), np.array(cal["model"]["o"])
    R = K @ X_TRUE
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=3e-3)
    np.testing.assert_allclose(K @ (Y_TRUE + o), 0.0, atol=0.03)


def test_a_pose_near_one_taken_is_refused_and_stop_says_so(client):
    rng = np.random.default_rng(12)
    s = start(client, protocol="free", target_mg=0.01)  # unreachable: the person stops
    assert capture(client, s, UPS[0], rng).status_code == 201
    tilted = UPS[0] + np.array([0.08, 0.0, 0.0])
    near = capture(client, s, tilted / np.linalg.norm(tilted), rng)
    assert near.status_code == 422 and near.json()["code"] == "pose_too_close"
    assert "from pose 1, already captured: turn the device at least 10° further" in near.json()["detail"]
    for up in UPS[1:9]:
        assert capture(client, s, up, rng).status_code == 201
    early = client.post(f"/api/v1/sessions/{s['id']}/solve", headers=auth(s["token"]))
    assert early.status_code == 422 and early.json()["code"] == "insufficient_data"
    assert early.json()["detail"].startswith("capture 1 more poses first")
    for up in UPS[9:11]:
        assert capture(client, s, up, rng).status_code == 201
    assert capture(client, s, UPS[11], rng, position="5").status_code == 422  # poses are numbered in order
    r = client.post(f"/api/v1/sessions/{s['id']}/solve", headers=auth(s["token"]))
    assert r.status_code == 201, r.text
    finish = r.json()["finish"]
    assert finish["reason"] == "stopped" and finish["poses"] == 11 and finish["target_mg"] == 0.01
    assert (
        finish["text"]
        == f"stopped at 11 poses: {finish['cv_error_mg']:.1f} mg expected on new orientations, target 0.01 mg"
    )


def test_the_target_defaults_to_the_setting(tmp_path):
    from fastapi.testclient import TestClient

    from app.main import create_app
    from tests.conftest import make_settings

    with TestClient(create_app(make_settings(tmp_path, free_target_mg=3.5))) as c:
        assert start(c, protocol="free")["target_mg"] == 3.5
        assert start(c, protocol="free", target_mg=1.5)["target_mg"] == 1.5
        assert c.post("/api/v1/sessions", json={"protocol": "free", "target_mg": 0}).status_code == 422


@pytest.mark.parametrize("protocol", ["six", "cube24"])
def test_other_protocols_have_no_progress(client, protocol):
    s = start(client, protocol=protocol)
    assert s["progress"] is None and s["target_mg"] is None
