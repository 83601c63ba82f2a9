"""Check a stored calibration on a new recording, and compare two, over real HTTP
(POST /api/v1/calibrations/{id}/check, GET /api/v1/calibrations/{id}/compare?with=…)."""

from __future__ import annotations

import io

import numpy as np
import pytest
from pydantic import TypeAdapter

from app.api.schemas.calibrations import CheckOut, CompareOut
from simulations.drift import disturbed_turn
from simulations.magnetometer import simulate_rests, simulate_session, simulate_turn
from tests.api.test_pose_files import six, upload_files
from tests.api.test_typed_contract import undescribed
from tests.conftest import DATA

F = 48.0


def turn_csv(m: np.ndarray, rate_hz: float = 50.0) -> bytes:
    """A compass turn's readings as a logger writes them: a time column in s, then the three axes (µT)."""
    buf = io.StringIO()
    np.savetxt(
        buf,
        np.column_stack([np.arange(len(m)) / rate_hz, m]),
        delimiter=",",
        fmt="%.6f",
        comments="",
        header="time_s,mag_x,mag_y,mag_z",
    )
    return buf.getvalue().encode()


def upload_turn(client, m: np.ndarray) -> str:
    r = client.post(
        "/api/v1/recordings", files={"file": ("turn.csv", turn_csv(m), "text/csv")}, data={"mag_unit": "uT"}
    )
    assert r.status_code == 201, r.text
    return r.json()["id"]


@pytest.fixture()
def compass(client):
    m, M, b = simulate_session(31, n=300)
    r = client.post("/api/v1/calibrations", json={"method": "magnetometer", "mag": m.tolist(), "field_ut": F})
    assert r.status_code == 201, r.text
    return r.json(), M, b


def check(client, cal_id: str, recording_id: str, **extra):
    return client.post(f"/api/v1/calibrations/{cal_id}/check", json={"recording_id": recording_id, **extra})


def test_a_compass_turn_with_a_moved_hard_iron_is_told_to_calibrate_again(client, compass):
    cal, M, b = compass
    rng = np.random.default_rng(5)
    kept = check(client, cal["id"], upload_turn(client, simulate_turn(rng, M, b, n=300)), inclination_deg=64.0)
    assert kept.status_code == 200, kept.text
    assert kept.json()["verdict"] == "keep"
    r = check(client, cal["id"], upload_turn(client, simulate_turn(rng, M, b + [4.0, 0.0, 0.0], n=300)))
    assert r.status_code == 200, r.text
    out = r.json()
    assert undescribed(TypeAdapter(CheckOut).validate_python(out)) == []
    assert out["verdict"] == "calibrate_again" and out["calibration_id"] == cal["id"]
    mag = out["sensors"][0]
    assert mag["drifted"] == ["hard iron"] and mag["angle_kind"] == "heading"
    assert mag["current"]["unit"] == "µT" and mag["current"]["value"] > mag["fresh"]["high"]
    assert "hard iron drifted" in out["reasons"][0]


def test_a_disturbed_turn_is_told_to_move_the_compass(client, compass):
    cal, M, b = compass
    r = check(client, cal["id"], upload_turn(client, disturbed_turn(np.random.default_rng(6), M, b)))
    assert r.status_code == 200, r.text
    assert r.json()["verdict"] == "move_the_compass" and "move it away" in r.json()["reasons"][0]


def test_two_compass_calibrations_compared_say_which_differences_are_real(client, compass):
    cal, M, b = compass
    m2 = simulate_turn(np.random.default_rng(7), M, b + [0.0, 0.0, 5.0], n=300)
    other = client.post("/api/v1/calibrations", json={"method": "magnetometer", "mag": m2.tolist(), "field_ut": F})
    r = client.get(
        f"/api/v1/calibrations/{cal['id']}/compare", params={"with": other.json()["id"], "inclination_deg": 64}
    )
    assert r.status_code == 200, r.text
    out = r.json()
    assert undescribed(TypeAdapter(CompareOut).validate_python(out)) == []
    assert out["with"] == other.json()["id"] and out["missing"] == []
    mag = out["sensors"][0]
    z = next(d for d in mag["differences"] if d["group"] == "offsets" and d["axis"] == "z")
    assert z["real"] and z["parameter"] == "hard iron" and z["unit"] == "µT"
    assert z["difference"] == pytest.approx(5.0, abs=1.0)
    assert mag["effect_kind"] == "heading" and mag["effect_deg"] > 5.0


def test_real_pose_files_calibration_checked_on_its_own_session_is_kept(client):
    """The MPU-6050 of tests/data/real/mpu6050_pose_files: its six-position calibration on its own six poses (the
    affine model of known orientations refitted on them)."""
    rec = upload_files(client, six()).json()
    cal = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]}).json()
    r = check(client, cal["id"], rec["id"])
    assert r.status_code == 200, r.text
    acc = r.json()["sensors"][0]
    assert acc["verdict"] == "keep" and acc["count"] == 6 and acc["angle_kind"] == "tilt"


def test_a_turn_s_readings_sent_as_read_are_checked_as_its_recording_is(client, compass):
    """The page's live turn: the readings in the body, no upload; the same answer as the same turn uploaded."""
    cal, M, b = compass
    moved = simulate_turn(np.random.default_rng(5), M, b + [4.0, 0.0, 0.0], n=300)
    r = client.post(f"/api/v1/calibrations/{cal['id']}/check", json={"mag": moved.tolist()})
    assert r.status_code == 200, r.text
    assert r.json()["verdict"] == "calibrate_again" and r.json()["sensors"][0]["drifted"] == ["hard iron"]
    uploaded = check(client, cal["id"], upload_turn(client, moved)).json()
    assert r.json()["sensors"][0]["current"]["value"] == pytest.approx(uploaded["sensors"][0]["current"]["value"], 1e-5)
    both = client.post(f"/api/v1/calibrations/{cal['id']}/check", json={"mag": moved.tolist(), "recording_id": "x"})
    neither = client.post(f"/api/v1/calibrations/{cal['id']}/check", json={})
    for answer in (both, neither):
        assert answer.status_code == 422 and "give recording_id" in answer.json()["detail"], answer.text
    rec = upload_files(client, six()).json()
    acc = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]}).json()
    r = client.post(f"/api/v1/calibrations/{acc['id']}/check", json={"mag": moved.tolist()})
    assert r.status_code == 422 and "not the compass" in r.json()["detail"] and "recording_id" in r.json()["detail"]


def test_what_cannot_be_checked_or_compared_is_a_4xx_naming_the_cause(client, compass):
    cal = compass[0]
    missing = check(client, cal["id"], "rec_nothing")
    assert missing.status_code == 404
    rec = upload_files(client, six()).json()  # an accelerometer's poses: nothing a compass calibration corrects
    r = check(client, cal["id"], rec["id"])
    assert r.status_code == 422 and "corrects mag" in r.json()["detail"]
    acc = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]}).json()
    r = client.get(f"/api/v1/calibrations/{cal['id']}/compare", params={"with": acc["id"]})
    assert r.status_code == 422 and "no sensor in common" in r.json()["detail"]
    assert client.get(f"/api/v1/calibrations/{cal['id']}/compare").status_code == 422  # `with` is required


def test_a_flight_log_s_compass_is_not_checked_and_the_answer_says_what_to_do(client):
    """The real ArduPilot log171.bin: its compass calibrated from the flight, then checked on that flight. The field's
    strength in flight moves with the motors' current, so the check cannot tell and says what would."""
    log = DATA / "real" / "flight" / "log171.bin"
    rec = client.post("/api/v1/recordings", files={"file": (log.name, log.read_bytes())}).json()
    cal = client.post(
        "/api/v1/calibrations", json={"method": "compass_flight", "recording_id": rec["id"], "mag_instance": 0}
    ).json()
    r = check(client, cal["id"], rec["id"])
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["verdict"] == "cannot_tell" and out["sensors"][0]["sensor"] == "mag"
    assert "turn through all directions" in out["reasons"][0] and "compare the two" in out["reasons"][0]


def test_a_link_reads_its_own_calibration_and_neither_checks_nor_compares_it(client, compass):
    """A short link's token reads its one calibration: a comparison names another and a check reads a recording, so
    both are refused (401)."""
    cal = compass[0]
    other = client.post(
        "/api/v1/calibrations", json={"method": "magnetometer", "mag": simulate_session(32, n=300)[0].tolist()}
    ).json()
    code = client.post(f"/api/v1/calibrations/{cal['id']}/links").json()["code"]
    token = client.get(f"/api/v1/links/{code}").json()["token"]
    r = client.get(
        f"/api/v1/calibrations/{cal['id']}/compare",
        params={"with": other["id"]},
        headers={"Authorization": f"Bearer {token}"},
    )
    assert r.status_code == 401 and "its own calibration only" in r.json()["detail"]
    assert client.get(f"/api/v1/calibrations/{cal['id']}/compare", params={"with": other["id"]}).status_code == 200
    r = client.post(
        f"/api/v1/calibrations/{cal['id']}/check",
        json={"recording_id": "rec_any"},
        headers={"Authorization": f"Bearer {token}"},
    )
    assert r.status_code == 401 and "its own calibration only" in r.json()["detail"]


def turn_with_rests(rng, m: np.ndarray, rests) -> bytes:
    """A recording of acc and mag at 50 Hz: each rest 2 s, then a part of the turn (the accelerometer moving)."""
    rows, step = [], len(m) // len(rests)
    for k, (acc, mag) in enumerate(rests):
        rows += [np.r_[acc + rng.normal(0, 0.01, 3), mag + rng.normal(0, 0.2, 3)] for _ in range(100)]
        rows += [np.r_[[0.3, -0.2, 9.4] + rng.normal(0, 2.0, 3), v] for v in m[k * step : (k + 1) * step]]
    data = np.array(rows)
    buf = io.StringIO()
    np.savetxt(
        buf,
        np.column_stack([np.arange(len(data)) / 50.0, data]),
        delimiter=",",
        fmt="%.6f",
        comments="",
        header="time_s,acc_x,acc_y,acc_z,mag_x,mag_y,mag_z",
    )
    return buf.getvalue().encode()


def test_a_compass_remounted_against_the_accelerometer_is_named_by_the_rests_of_the_new_recording(client):
    rng = np.random.default_rng(23)
    m, M, b = simulate_session(23, n=1200, hard_iron_ut=40.0)
    first = turn_with_rests(rng, m, simulate_rests(rng, M, b, inclination_deg=64.0, n=6))
    up = client.post("/api/v1/recordings", files={"file": ("first.csv", first, "text/csv")}, data={"mag_unit": "uT"})
    cal = client.post(
        "/api/v1/calibrations", json={"method": "magnetometer", "recording_id": up.json()["id"], "field_ut": F}
    ).json()
    assert cal["metrics"]["measured_inclination_deg"] == pytest.approx(64.0, abs=1.0)
    same = turn_with_rests(rng, simulate_turn(rng, M, b, n=1200), simulate_rests(rng, M, b, inclination_deg=64.0, n=6))
    up = client.post("/api/v1/recordings", files={"file": ("same.csv", same, "text/csv")}, data={"mag_unit": "uT"})
    assert check(client, cal["id"], up.json()["id"]).json()["verdict"] == "keep"
    angle = np.radians(25.0)
    remount = np.array([[np.cos(angle), 0.0, np.sin(angle)], [0.0, 1.0, 0.0], [-np.sin(angle), 0.0, np.cos(angle)]])
    rests = [
        (acc, np.linalg.solve(M, remount @ (M @ (mag - b))) + b)
        for acc, mag in simulate_rests(rng, M, b, inclination_deg=64.0, n=6)
    ]
    again = turn_with_rests(rng, simulate_turn(rng, M, b, n=1200), rests)
    up = client.post("/api/v1/recordings", files={"file": ("again.csv", again, "text/csv")}, data={"mag_unit": "uT"})
    r = check(client, cal["id"], up.json()["id"])
    assert r.status_code == 200, r.text
    mag = r.json()["sensors"][0]
    assert mag["verdict"] == "calibrate_again" and mag["drifted"] == ["orientation"], mag["reasons"]
    assert "turned against the accelerometer" in mag["reasons"][-1]
