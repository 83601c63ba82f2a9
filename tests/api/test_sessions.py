"""The wizard's server side: /api/v1/sessions (issue 6, docs/rest.md), through real HTTP calls."""

from __future__ import annotations

import numpy as np
import pytest
from fastapi.testclient import TestClient

from app.calibration import CANONICAL_SIX, STANDARD_GRAVITY, fit_six_position
from app.main import create_app
from tests.conftest import make_settings
from tests.phone_poses import X_TRUE, pose_samples

G = STANDARD_GRAVITY


def auth(token: str) -> dict:
    return {"Authorization": f"Bearer {token}"}


def start(client, **fields) -> dict:
    r = client.post("/api/v1/sessions", json={"protocol": "six", **fields})
    assert r.status_code == 201, r.text
    return r.json()


def test_six_poses_in_any_order_give_the_closed_form_of_the_captures(client):
    rng = np.random.default_rng(6)
    s = start(client, capture_s=5, device_id="phone-1")
    assert s["positions"] == list(CANONICAL_SIX) and s["remaining"] == list(CANONICAL_SIX)
    assert s["token"].startswith("tks_") and s["captures"] == []
    sent = {}
    for label in ("+z", "-x", "+y", "-z", "+x", "-y"):
        sent[label] = pose_samples(label, rng)
        r = client.post(f"/api/v1/sessions/{s['id']}/captures", json=sent[label], headers=auth(s["token"]))
        assert r.status_code == 201, r.text
        assert r.json()["capture"]["position"] == label
        assert r.json()["capture"]["sampling_rate_hz"] == pytest.approx(60.0)
    assert r.json()["session"]["remaining"] == []
    r = client.post(f"/api/v1/sessions/{s['id']}/solve", headers=auth(s["token"]))
    assert r.status_code == 201, r.text
    cal = r.json()
    means = [np.mean(sent[label]["acc"], axis=0) for label in CANONICAL_SIX]
    expected = fit_six_position(means, list(CANONICAL_SIX), gravity=G)  # Georgieva et al. section 3.3.1
    np.testing.assert_allclose(cal["model"]["X"], expected.X, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(cal["model"]["y"], expected.y, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(cal["model"]["X"], X_TRUE, atol=0.01)  # and near the truth
    assert cal["session_id"] == s["id"] and cal["device_id"] == "phone-1" and cal["ok"]
    assert any("rounds its sensor values to 0.1 m/s²" in w for w in cal["warnings"])
    assert any("may already calibrate" in w for w in cal["warnings"])
    # The session records its calibration; the token reads and exports it; nobody else does.
    assert client.get(f"/api/v1/sessions/{s['id']}", headers=auth(s["token"])).json()["calibration_id"] == cal["id"]
    got = client.get(f"/api/v1/calibrations/{cal['id']}", headers=auth(s["token"]))
    assert got.status_code == 200 and got.json() == cal
    export = client.get(f"/api/v1/calibrations/{cal['id']}/export?format=json", headers=auth(s["token"]))
    assert export.status_code == 200 and export.json()["model"]["X"] == cal["model"]["X"]
    assert client.get(f"/api/v1/calibrations/{cal['id']}").status_code == 404


def test_a_board_s_session_has_no_notes_of_a_phone_s_browser(client):
    # The same captures from a board's lines (source board): the same fit, and neither the browser's
    # rounding nor the phone system's own calibration is said.
    rng = np.random.default_rng(6)
    s = start(client, capture_s=5, source="board")
    assert s["source"] == "board" and start(client)["source"] == "phone"
    sent = {label: pose_samples(label, rng) for label in ("+z", "-x", "+y", "-z", "+x", "-y")}
    for _label, capture in sent.items():
        r = client.post(f"/api/v1/sessions/{s['id']}/captures", json=capture, headers=auth(s["token"]))
        assert r.status_code == 201, r.text
    cal = client.post(f"/api/v1/sessions/{s['id']}/solve", headers=auth(s["token"])).json()
    expected = fit_six_position(
        [np.mean(sent[label]["acc"], axis=0) for label in CANONICAL_SIX], list(CANONICAL_SIX), gravity=G
    )
    np.testing.assert_allclose(cal["model"]["X"], expected.X, rtol=1e-12, atol=1e-14)
    assert not any("rounds its sensor values" in w or "may already calibrate" in w for w in cal["warnings"])
    assert cal["source"] == "board"  # the page offers a board's calibration for its firmware first (app/web/uses.py)
    r = client.post("/api/v1/sessions", json={"protocol": "six", "source": "arduino"})
    assert r.status_code == 422 and "source" in r.text


def test_a_pose_already_captured_is_refused_naming_what_remains_and_redo_replaces_it(client):
    rng = np.random.default_rng(7)
    s = start(client)
    url, h = f"/api/v1/sessions/{s['id']}/captures", auth(s["token"])
    assert client.post(url, json=pose_samples("+z", rng), headers=h).status_code == 201
    assert client.post(url, json=pose_samples("-x", rng), headers=h).status_code == 201
    again = client.post(url, json=pose_samples("+z", rng), headers=h)
    assert again.status_code == 409
    assert again.json()["detail"].startswith("+z is already captured; remaining: +x, -y, +y, -z.")
    assert "redo=true" in again.json()["detail"]
    first = client.get(f"/api/v1/sessions/{s['id']}", headers=h).json()["captures"][0]
    redo = client.post(url, json={**pose_samples("+z", rng), "redo": True}, headers=h)
    assert redo.status_code == 201
    captures = redo.json()["session"]["captures"]
    assert sorted(c["position"] for c in captures) == ["+z", "-x"]
    assert next(c for c in captures if c["position"] == "+z")["mean"] != first["mean"]


@pytest.mark.parametrize(
    "change, message",
    [
        (
            lambda p: {**p, "acc": (np.array(p["acc"]) + np.random.default_rng(1).normal(0, 1.0, (300, 3))).tolist()},
            "the device moved during the capture",
        ),
        (
            lambda p: {**p, "acc": (np.array(p["acc"]) + np.linspace(0, 0.6, 300)[:, None] * [1, 0, 0]).tolist()},
            "slid or tilted",
        ),
        (lambda p: {**p, "acc": [[6.9, 0.0, 6.9]] * 300}, "no axis points up within 20°"),
        (lambda p: {**p, "acc": [[0.0, 0.0, 5.0]] * 300}, "not gravity's"),
        (lambda p: {**p, "position": "-y"}, "the device is in the +z pose, not -y"),
        (lambda p: {**p, "t_ms": p["t_ms"][::-1]}, "goes back in time"),
        (lambda p: {**p, "t_ms": p["t_ms"][:-1]}, "t_ms has 299 timestamps for 300 samples"),
        (lambda p: {**p, "acc": p["acc"][:5], "t_ms": p["t_ms"][:5], "gyr": None}, "at least 10 samples"),
        (lambda p: {**p, "gyr": [[20.0, 0.0, 0.0]] * 300}, "turning during the capture"),
        (lambda p: {**p, "gyr": p["gyr"][:10]}, "gyr has 10 samples for 300 acc samples"),
        (lambda p: {**p, "unit": "g"}, "this session takes samples in m/s^2"),
        (lambda p: {**p, "acc": p["acc"][:-1] + [[0.0, 0.0, None]]}, "acc[299][2]"),
    ],
)
def test_bad_captures_are_refused_with_the_reason_and_nothing_is_stored(client, change, message):
    s = start(client)
    h = auth(s["token"])
    r = client.post(
        f"/api/v1/sessions/{s['id']}/captures", json=change(pose_samples("+z", np.random.default_rng(2))), headers=h
    )
    assert r.status_code == 422, r.text
    assert message in r.json()["detail"]
    assert client.get(f"/api/v1/sessions/{s['id']}", headers=h).json()["captures"] == []


def test_solving_before_every_pose_names_the_missing_ones(client):
    s = start(client)
    h = auth(s["token"])
    client.post(f"/api/v1/sessions/{s['id']}/captures", json=pose_samples("-z", np.random.default_rng(3)), headers=h)
    r = client.post(f"/api/v1/sessions/{s['id']}/solve", headers=h)
    assert r.status_code == 422
    assert r.json()["detail"].startswith("capture -x, +x, -y, +y, +z first")


def test_a_session_opens_only_with_its_own_token(client):
    a, b = start(client), start(client)
    rng = np.random.default_rng(4)
    assert client.get(f"/api/v1/sessions/{a['id']}").status_code == 401
    assert client.get(f"/api/v1/sessions/{a['id']}", headers=auth("tks_forged")).status_code == 401
    r = client.get(f"/api/v1/sessions/{a['id']}", headers=auth(b["token"]))
    assert r.status_code == 404 and "no session" in r.json()["detail"]
    r = client.post(f"/api/v1/sessions/{a['id']}/captures", json=pose_samples("+z", rng), headers=auth(b["token"]))
    assert r.status_code == 404
    assert client.get(f"/api/v1/sessions/{a['id']}", headers=auth(a["token"])).json()["captures"] == []
    assert "token" not in client.get(f"/api/v1/sessions/{a['id']}", headers=auth(a["token"])).json()


def test_two_people_calibrating_at_once_never_see_each_others_data(client):
    rng = np.random.default_rng(5)
    people = [start(client), start(client)]
    for label in CANONICAL_SIX:  # interleaved, pose by pose
        for s in people:
            r = client.post(
                f"/api/v1/sessions/{s['id']}/captures", json=pose_samples(label, rng), headers=auth(s["token"])
            )
            assert r.status_code == 201
    cals = [client.post(f"/api/v1/sessions/{s['id']}/solve", headers=auth(s["token"])).json() for s in people]
    assert cals[0]["id"] != cals[1]["id"] and cals[0]["model"] != cals[1]["model"]
    for mine, theirs, s in ((0, 1, people[0]), (1, 0, people[1])):
        assert client.get(f"/api/v1/calibrations/{cals[theirs]['id']}", headers=auth(s["token"])).status_code == 404
        listed = client.get("/api/v1/calibrations", headers=auth(s["token"])).json()["items"]
        assert [c["id"] for c in listed] == [cals[mine]["id"]]


def _cube_session(client):
    s = start(client, protocol="cube24")
    assert s["positions"] == [str(k) for k in range(1, 25)]
    return s, f"/api/v1/sessions/{s['id']}/captures", auth(s["token"])


def test_the_cube24_flow_checks_each_turn_and_solves_by_003(client, tmp_path):
    """24 positions in order, each turn checked at once (Särkkä et al. section VII-A-1); the solution is Särkkä et al.'s
    method on the joined recording, and recovers the phone's accelerometer and gyroscope."""
    from app.calibration.cube import calibrate_cube
    from tests.cube_phone import B_GYR_DEG_S, S_GYR, X_ACC, Y_ACC, phone_cube

    phone = phone_cube(1)
    s, url, h = _cube_session(client)
    for k in range(1, 25):
        r = client.post(url, json=phone.capture(k), headers=h)
        assert r.status_code == 201, (k, r.text)
        capture = r.json()["capture"]
        assert capture["position"] == str(k)
    assert r.json()["session"]["remaining"] == []
    r = client.post(f"/api/v1/sessions/{s['id']}/solve", headers=h)
    assert r.status_code == 201, r.text
    cal = r.json()
    assert cal["method"] == "cube" and cal["model"]["type"] == "cube" and cal["session_id"] == s["id"]
    assert cal["first_wrong_rotation"] is None, cal["sequence"]
    # The same as Särkkä et al.'s method on the recording the captures join into (the still parts and the moves).
    a, b = phone.static_segments[0][0] + 6, phone.static_segments[-1][1] - 6
    direct = calibrate_cube(
        phone.acc[a:b], np.radians(phone.gyr[a:b]), None, sampling_rate_hz=60.0, protocol="cube24", gravity=G
    )
    np.testing.assert_allclose(cal["model"]["acc"]["S"], direct.acc.S, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(cal["model"]["gyr"]["S"], direct.gyr.S, rtol=1e-6, atol=1e-9)
    # And the phone's parameters: raw = S f + b (Särkkä et al. eq. (1)).
    np.testing.assert_allclose(cal["model"]["acc"]["S"], X_ACC, atol=0.01)
    np.testing.assert_allclose(cal["model"]["acc"]["b"], Y_ACC, atol=0.05)
    np.testing.assert_allclose(cal["model"]["gyr"]["S"], S_GYR, atol=0.01)
    np.testing.assert_allclose(cal["model"]["gyr"]["b"], np.radians(B_GYR_DEG_S), atol=np.radians(0.05))
    assert any("may already calibrate" in w for w in cal["warnings"])
    from tests.api.test_cube import check_cube_exports

    check_cube_exports(client, cal, tmp_path, headers=h)  # exports read with the session's token


def test_a_wrong_cube_turn_is_named_at_once_and_the_right_one_is_then_accepted(client):
    from tests.cube_phone import phone_cube

    wrong = phone_cube(2, wrong_rotations={3: "z-"})  # position 3 → 4 turned clockwise
    right = phone_cube(2)
    s, url, h = _cube_session(client)
    for k in (1, 2, 3):
        assert client.post(url, json=wrong.capture(k), headers=h).status_code == 201
    r = client.post(url, json=wrong.capture(4), headers=h)
    assert r.status_code == 422
    detail = r.json()["detail"]
    assert detail.startswith("wrong turn into position 4: the cube made a quarter turn clockwise (seen from above)")
    assert "Put it back in position 3, then turn the cube a quarter counter-clockwise" in detail
    assert client.get(f"/api/v1/sessions/{s['id']}", headers=h).json()["remaining"][0] == "4"
    assert client.post(url, json=right.capture(4), headers=h).status_code == 201


def test_cube_positions_go_in_order_and_need_the_gyroscope(client):
    from tests.cube_phone import phone_cube

    phone = phone_cube(3)
    _s, url, h = _cube_session(client)
    r = client.post(url, json={**phone.capture(1), "position": "2"}, headers=h)
    assert r.status_code == 422 and "goes in order: this capture is position 1" in r.json()["detail"]
    r = client.post(url, json={**phone.capture(1), "gyr": None}, headers=h)
    assert r.status_code == 422 and "needs the gyroscope" in r.json()["detail"]
    r = client.post(url, json=phone.capture(5), headers=h)  # −x up where position 1 wants +z
    assert r.status_code == 422 and "position 1 should have +z up" in r.json()["detail"]
    assert client.post(url, json=phone.capture(1), headers=h).status_code == 201
    r = client.post(url, json={k: v for k, v in phone.capture(2).items() if k != "motion"}, headers=h)
    assert r.status_code == 422 and "needs the move from position 1" in r.json()["detail"]
    r = client.post(url, json={**phone.capture(1), "redo": True}, headers=h)
    assert r.status_code == 201 and r.json()["capture"]["position"] == "1"


def test_a_gyroscope_reporting_rad_s_is_recognised_from_the_turn(client):
    from tests.cube_phone import phone_cube

    phone = phone_cube(4)
    _s, url, h = _cube_session(client)
    for k in (1, 2):
        body = phone.capture(k)
        body["gyr"] = np.radians(body["gyr"]).tolist()  # an old browser: rad/s though it says deg/s
        if "motion" in body:
            body["motion"]["gyr"] = np.radians(body["motion"]["gyr"]).tolist()
        r = client.post(url, json=body, headers=h)
        assert r.status_code == 201, r.text
    assert r.json()["capture"]["gyr_to_rad_s"] == 1.0


def test_with_api_keys_a_key_starts_a_session_and_its_token_carries_it(tmp_path):
    with TestClient(create_app(make_settings(tmp_path, api_keys=("k1",))), raise_server_exceptions=False) as client:
        assert client.post("/api/v1/sessions", json={"protocol": "six"}).status_code == 401
        r = client.post("/api/v1/sessions", json={"protocol": "six"}, headers=auth("k1"))
        assert r.status_code == 201
        s = r.json()
        rng = np.random.default_rng(8)
        for label in CANONICAL_SIX:
            assert (
                client.post(
                    f"/api/v1/sessions/{s['id']}/captures", json=pose_samples(label, rng), headers=auth(s["token"])
                ).status_code
                == 201
            )
        cal = client.post(f"/api/v1/sessions/{s['id']}/solve", headers=auth(s["token"])).json()
        assert client.get(f"/api/v1/calibrations/{cal['id']}", headers=auth(s["token"])).status_code == 200
        assert client.get(f"/api/v1/calibrations/{cal['id']}", headers=auth("k1")).status_code == 404


def test_session_requests_are_validated(client):
    assert "capture_s" in client.post("/api/v1/sessions", json={"capture_s": 0.1}).json()["detail"]
    assert client.post("/api/v1/sessions", json={"protocol": "eight"}).status_code == 422
    s = start(client, gravity=9.81)
    assert s["gravity"] == 9.81 and s["capture_s"] == 5.0
    r = client.post(f"/api/v1/sessions/{s['id']}/captures", json={"acc": [[0, 0, 9.8]]}, headers=auth(s["token"]))
    assert r.status_code == 422 and "t_ms" in r.json()["detail"]
