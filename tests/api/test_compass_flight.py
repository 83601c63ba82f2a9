"""The compass calibrated from a flight (method ``compass_flight``) over HTTP, as a user runs it: a flight log
uploaded with POST /api/v1/recordings, then POST /api/v1/calibrations {"method": "compass_flight", ...}.

- A seeded simulated flight with known offsets, soft iron and motor coefficients, its compass mounted at
  PITCH_180 (12) while both firmwares stored orientation 0, written as an ArduPilot DataFlash log and a PX4
  ULog (tests/flight_compass_logs.py): the orientation is found, every parameter lies inside its 95 %
  interval (this seed; the rate over 200 flights is bench/flight_compass_logs.py's), and the firmware's
  export, applied with that firmware's own formula written in tests/io/test_export_flight_compass.py,
  reproduces the model's correction of the raw readings.
- The real ArduPilot Copter 3.3 log tests/data/real/flight/log171.bin (parked most of its 4 minutes, few
  turns): every compass answers with ok false and reasons in words, its figure and the firmware's stored
  calibration (tests/data/real/flight/README.md, "compass from the flight", holds the figures).
- What a user gets wrong: a file that is no flight log, a log without GPS, a compass the log does not have,
  and the export of a failed fit.
"""

from __future__ import annotations

import datetime

import numpy as np
import pytest

from tests.flight_compass_logs import seeded_flight, write_flight_compass_logs
from tests.io.test_export_flight_compass import ardupilot_correct, parse_ardupilot, parse_px4, px4_correct

from .test_flight_corpus_api import LOG171

ORIENTATION = 12  # PITCH_180 in both firmwares' tables; 0 stored
SEED = 9
CSV = LOG171.parents[2] / "six_orientations_150hz.csv"


def _upload(client, path, **form) -> str:
    r = client.post("/api/v1/recordings", files={"file": (path.name, path.read_bytes())}, data=form)
    assert r.status_code == 201, r.text
    return r.json()["id"]


def _calibrate(client, recording_id: str, **fields):
    return client.post(
        "/api/v1/calibrations", json={"method": "compass_flight", "recording_id": recording_id, **fields}
    )


@pytest.fixture(scope="module")
def flight():
    return seeded_flight(SEED, orientation=ORIENTATION)


@pytest.fixture(scope="module")
def logs(flight, tmp_path_factory):
    return write_flight_compass_logs(tmp_path_factory.mktemp("flight"), flight)


def _model_correction(body: dict, mag: np.ndarray, power: np.ndarray) -> np.ndarray:
    """``h = M (Q m − b − k p)`` with the response's numbers."""
    m = {key: np.asarray(body["model"][key], dtype=float) for key in ("M", "b", "k", "Q")}
    return (mag @ m["Q"].T - m["b"] - np.outer(power, m["k"])) @ m["M"].T


@pytest.mark.parametrize("firmware", ["ardupilot", "px4"])
def test_a_simulated_flight_is_calibrated_from_either_firmwares_log(client, flight, logs, firmware):
    path = logs[0] if firmware == "ardupilot" else logs[1]
    r = _calibrate(client, _upload(client, path))
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["ok"] is True, body["reasons"]
    assert body["flight"]["firmware"] == firmware
    assert (body["flight"]["structure"], body["flight"]["motor"]) == ("soft_iron", "current")
    # the orientation: found, and not the one stored
    nearest = body["flight"]["rotation_nearest"]
    assert (nearest["ardupilot"], nearest["px4"], nearest["name"]) == (ORIENTATION, ORIENTATION, "PITCH_180")
    assert body["flight"]["orientation_agrees"] is False and body["flight"]["angle_left_deg"] < 2.0
    assert body["flight"]["stored"]["orientation"] == 0
    # every parameter inside its 95 % interval, in the model's frame: b and k in the body frame, M symmetric
    truth, half = flight["truth"], body["uncertainty"]
    assert half["confidence"] == 0.95
    for key in ("b", "M", "k"):
        error = np.abs(np.asarray(body["model"][key]) - truth[key])
        assert np.all(error <= np.asarray(half[key], dtype=float)), (key, error, half[key])
    assert np.allclose(body["model"]["Q"], truth["Q"], atol=1e-9)
    # the verdict first, in degrees: the stale stored calibration at the wrong orientation before, the fit after
    verdict, metrics = body["verdict"], body["metrics"]
    assert verdict["apply"] is True and verdict["kind"] == "apply" and verdict["unit"] == "°"
    assert verdict["basis"] == "heading error on flight segments left out"
    assert verdict["before"] == pytest.approx(metrics["heading_error_before_deg"]) and verdict["before"] > 50.0
    assert verdict["after"] == pytest.approx(metrics["heading_error_after_deg"]) and verdict["after"] < 1.5
    assert f"{verdict['after']:.2f}" in verdict["words"] and "°" in verdict["words"]
    # the firmware's export applied by its own formula to the raw readings reproduces the model's correction
    cal = body["id"]
    export = client.get(f"/api/v1/calibrations/{cal}/export", params={"format": firmware})
    assert export.status_code == 200, export.text
    mag, current = flight["mag_raw_ut"], flight["current_a"]
    if firmware == "ardupilot":
        params = parse_ardupilot(export.text)
        assert params["COMPASS_ORIENT"] == ORIENTATION and params["COMPASS_MOTCT"] == 2
        h = ardupilot_correct(params, 0, 0, mag, current, 2)
    else:
        params = parse_px4(export.text)
        assert params["CAL_MAG0_ROT"] == ORIENTATION and params["CAL_MAG_COMP_TYP"] == 2
        h = px4_correct(params, 0, 0, mag, current * 0.001)
    model = _model_correction(body, mag, current)
    assert np.abs(h - model).max() < 1e-3
    # and that correction is the field the attitude expects, to the compass's noise and the attitude's error
    assert np.sqrt(np.mean((model - flight["expected_ut"]) ** 2)) < 1.0


@pytest.fixture
def log171(client) -> str:
    return _upload(client, LOG171)


@pytest.mark.parametrize("instance", [0, 1, 2])
def test_a_real_copter_log_parked_most_of_its_flight_is_not_ok_in_words(client, log171, instance):
    r = _calibrate(client, log171, mag_instance=instance)
    assert r.status_code == 201, r.text
    body = r.json()
    assert "damaged" not in r.text
    assert body["ok"] is False and body["verdict"]["apply"] is False
    assert body["reasons"] and all(len(reason.split()) >= 6 for reason in body["reasons"])
    # what to do first: the vehicle flew mostly one way (68 % of its flying part, the 29 % on the ground left out,
    # in one 45° sector of heading)
    assert body["reasons"][0].startswith(
        "the flight held one heading for most of it (8 of 8 sectors of 45° reached, but 68% of the flight in one"
    ), body["reasons"][0]
    assert any(w.startswith("the flying part is fitted: ") for w in body["warnings"])
    assert body["flight"]["generation"] == f"ArduPilot Copter V3.3-dev (TimeMS, {('MAG', 'MAG2', 'MAG3')[instance]})"
    assert body["flight"]["instance"] == instance
    # the figure, before and after, in degrees, on segments left out
    assert body["verdict"]["unit"] == "°"
    assert 5.0 < body["metrics"]["heading_error_before_deg"] < 40.0
    assert 5.0 < body["metrics"]["heading_error_after_deg"] < 15.0
    # the calibration the firmware stored in the log's parameters, beside trical's
    stored = body["flight"]["stored"]
    assert stored["firmware"] == "ardupilot" and len(stored["offsets_ut"]) == 3
    s = ("", "2", "3")[instance]
    if instance < 2:
        assert stored["offsets_ut"][0] == pytest.approx(0.1 * stored["params"][f"COMPASS_OFS{s}_X"])
    assert body["flight"]["place"]["date"] == "2015-11-21"
    # a failed fit is not exported to the firmware, and the refusal says why
    export = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "ardupilot"})
    assert export.status_code == 422 and export.json()["code"] == "export_refused"
    assert (
        "failed its checks" in export.json()["detail"] and "must not be written to ArduPilot" in export.json()["detail"]
    )


def test_a_compass_the_log_does_not_have_names_those_it_has(client, log171):
    r = _calibrate(client, log171, mag_instance=5)
    assert 400 <= r.status_code < 500, r.text
    assert "no compass instance 5" in r.json()["detail"] and "0, 1, 2" in r.json()["detail"]


def test_a_file_that_is_no_flight_log_is_refused_naming_what_to_upload(client):
    r = _calibrate(client, _upload(client, CSV))
    assert 400 <= r.status_code < 500, r.text
    detail = r.json()["detail"]
    assert "ULog (.ulg)" in detail and "DataFlash log (.bin)" in detail


@pytest.mark.parametrize("which", [0, 1])
def test_a_log_without_gps_asks_for_the_place_and_date(client, tmp_path, which):
    flight = seeded_flight(SEED, orientation=ORIENTATION, duration_s=120.0)
    rec = _upload(client, write_flight_compass_logs(tmp_path, flight, gps=False)[which])
    r = _calibrate(client, rec)
    assert 400 <= r.status_code < 500, r.text
    assert "latitude_deg and longitude_deg" in r.json()["detail"] and "date" in r.json()["detail"]
    r = _calibrate(client, rec, latitude_deg=flight["lat"], longitude_deg=flight["lon"])
    assert 400 <= r.status_code < 500 and "give its date" in r.json()["detail"], r.text
    r = _calibrate(
        client,
        rec,
        latitude_deg=flight["lat"],
        longitude_deg=flight["lon"],
        height_m=flight["alt_m"],
        date=flight["utc"].date().isoformat(),
    )
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["ok"] is True, body["reasons"]
    assert body["flight"]["place"] == {
        "latitude_deg": flight["lat"],
        "longitude_deg": flight["lon"],
        "height_m": flight["alt_m"],
        "date": datetime.date(2025, 6, 1).isoformat(),
    }
    assert body["flight"]["rotation_nearest"]["ardupilot"] == ORIENTATION


@pytest.mark.parametrize("which, switch", [(0, "COMPASS_USE"), (1, "CAL_MAG0_PRIO")])
def test_a_dead_compass_is_said_not_to_measure_with_the_setting_that_stops_its_use(client, tmp_path, which, switch):
    """A compass unplugged in flight reads 0: ArduPilot's log then shows its stored offsets, PX4's zeros. The
    answer names that, and the firmware's own switch, before anything is fitted or called better."""
    flight = seeded_flight(SEED, orientation=ORIENTATION, duration_s=120.0)
    flight["mag_raw_ut"] = np.zeros_like(flight["mag_raw_ut"])
    r = _calibrate(client, _upload(client, write_flight_compass_logs(tmp_path, flight)[which]))
    assert r.status_code == 422 and r.json()["code"] == "compass_not_measuring", r.text
    detail = r.json()["detail"]
    assert detail.startswith("this compass does not measure: the compass reads 0.0 µT for the whole flight"), detail
    assert f"set {switch} = 0" in detail and "better" not in detail


def test_a_px4_1_9_log_with_only_vehicle_magnetometer_lists_its_compass_and_calibrates_it(client):
    """The real PX4 1.9 flight of tests/data/real/flight (px4-ulog-rs's esc_status_log.ulg) logs its compass only as
    vehicle_magnetometer (calibrated, body frame, 117 samples): the upload lists it, the compass from the flight
    is the first ready (a GPS fix: Zurich, 2019-05-13), compass 0 is taken by number, and the answer is ok false
    for the too few samples (108 of its flying part), with the firmware's stored calibration (CAL_MAG0, enabled by
    CAL_MAG0_EN)."""
    path = LOG171.parent / "px4_1.9_esc_status_log.ulg"
    r = client.post("/api/v1/recordings", files={"file": (path.name, path.read_bytes())})
    assert r.status_code == 201, r.text
    rec = r.json()
    assert [(i["instance"], i["source"]) for i in rec["flight"]["instances"] if i["sensor"] == "mag"] == [
        (0, "vehicle_magnetometer")
    ]
    first = next(s for s in rec["supports"] if s["ready"])
    assert first["method"] == "compass_flight" and "(47.36°, 8.52°, 2019-05-13)" in first["why"], first
    answer = _calibrate(client, rec["id"], mag_instance=0)
    assert answer.status_code == 201, answer.text
    body = answer.json()
    assert body["ok"] is False and body["reasons"][0].startswith("only 108 samples"), body["reasons"]
    assert body["flight"]["generation"] == "PX4 v1.9.0 (vehicle_magnetometer)"
    assert body["flight"]["stored"]["switch"] == "CAL_MAG0_EN"
    assert body["metrics"]["field_ut"] == pytest.approx(48.04, abs=0.01)  # IGRF-14 at the first 3-D fix


@pytest.mark.parametrize("which", [0, 1])
def test_a_minimal_log_without_imu_is_read_for_its_compass_from_the_flight(client, flight, tmp_path, which):
    """A minimal log (attitude, compass, GPS, power; no IMU message, as ArduPlane's minimal LOG_BITMASK writes
    it) is read for what needs no IMU: the compass from the flight is listed, first and ready, and gives the
    answer the same flight's full log gives; nothing that needs the IMU is offered."""
    full = write_flight_compass_logs(tmp_path, flight)[which]
    bare = write_flight_compass_logs(tmp_path, flight, imu=False, stem="minimal")[which]
    rec = client.post("/api/v1/recordings", files={"file": (bare.name, bare.read_bytes())})
    assert rec.status_code == 201, rec.text
    body = rec.json()
    assert [i["sensor"] for i in body["flight"]["instances"]] == ["mag"]
    assert [(s["method"], s["ready"]) for s in body["supports"]] == [("compass_flight", True), ("noise", False)]
    assert any(n.startswith("the log holds no IMU samples: read for what needs none") for n in body["notes"])
    answers = [_calibrate(client, rid).json() for rid in (body["id"], _upload(client, full))]
    assert answers[0]["ok"] is True and answers[0]["model"] == answers[1]["model"]
    # an IMU asked of it names what the log holds
    refused = client.post("/api/v1/recordings", files={"file": (bare.name, bare.read_bytes())}, data={"instance": "0"})
    assert refused.status_code == 422 and "holds no IMU" in refused.json()["detail"], refused.text


def test_the_compass_method_on_a_flights_readings_says_the_model_they_determine(client):
    """`magnetometer` on each compass of log171.bin (the firmware's corrected field, near level most of the
    flight): the external MAG determines the full ellipsoid and passes (4.33 → 1.75 µT on new directions); MAG2
    determines only a scale per axis and MAG3 (no stored calibration) only its offsets, each refused for the field
    that moves with the motors' current, pointed to the compass from the flight; all against the field at the
    log's GPS fix, as what the turn puts beyond the firmware's own calibration."""
    got = []
    for instance in range(3):
        rid = _upload(client, LOG171, mag_instance=str(instance))
        r = client.post("/api/v1/calibrations", json={"method": "magnetometer", "recording_id": rid})
        assert r.status_code == 201, r.text
        body = r.json()
        assert body["metrics"]["field_source"] == "model" and body["metrics"]["field_ut"] == pytest.approx(
            58.19, abs=0.01
        )
        assert any(w.startswith("the Earth's field at the log's first GPS fix (-35.36237°") for w in body["warnings"])
        assert any("beyond the firmware's own calibration" in w and "compass_flight" in w for w in body["warnings"])
        got.append((body["ok"], body["metrics"]["structure"]))
        if instance:
            assert "spreads over" in body["reasons"][0] and body["verdict"]["apply"] is False
    assert got == [(True, "soft_iron"), (False, "scale"), (False, "offsets")]


def test_the_part_of_the_log_fitted_is_the_flying_part_unless_asked(client, flight, tmp_path):
    """The log's first 40 s on the ground (throttle 0): left out by default, with a note of what was kept; `window`
    all fits every sample; from_s and to_s cut the log by seconds, and a cut that leaves too little is refused
    naming them."""
    grounded = {**flight, "throttle": np.where(flight["time_s"] < 40.0, 0.0, flight["throttle"])}
    log = write_flight_compass_logs(tmp_path, grounded)[0]
    rid = _upload(client, log)
    total = len(flight["time_s"])
    flying = _calibrate(client, rid).json()
    kept = flying["metrics"]["n_samples"]
    # the ground's 1000 samples, and the few the logged throttle (CTUN, slower) takes to rise after them
    assert total - 1000 - 25 <= kept <= total - 1000, kept
    note = next(w for w in flying["warnings"] if w.startswith("the flying part is fitted: "))
    assert note.startswith(f"the flying part is fitted: {kept} of {total} samples, the throttle at or above 0.10 "), (
        note
    )
    assert note.endswith("(to fit every sample: window=all)")
    every = _calibrate(client, rid, window="all").json()
    assert every["metrics"]["n_samples"] == total and not any("flying part" in w for w in every["warnings"])
    cut = _calibrate(client, rid, window="all", from_s=60.0, to_s=120.0).json()
    assert cut["metrics"]["n_samples"] == 60 * 25 + 1
    narrow = _calibrate(client, rid, from_s=10.0, to_s=11.0)
    assert narrow.status_code == 422 and "widen from_s and to_s" in narrow.json()["detail"], narrow.text
    backwards = _calibrate(client, rid, from_s=20.0, to_s=10.0)
    assert backwards.status_code == 422 and "`to_s` must come after `from_s`" in backwards.text


def test_a_three_compass_log_says_which_compass_is_lying(client, log171):
    """log171.bin's three compasses side by side in the answer of any one: each its heading error before and after,
    orientation, the current's pull and one action; MAG3, never calibrated, fails ArduPilot's pre-arm consistency
    check against MAG (its horizontal field 52.9 µT away, the limit 200 mG), so it is the one to calibrate or stop
    using; MAG2 agrees with MAG (15.7° between their horizontal fields)."""
    body = _calibrate(client, log171, mag_instance=1).json()
    rows = {row["instance"]: row for row in body["flight"]["compasses"]}
    assert sorted(rows) == [0, 1, 2] and rows[1]["after_deg"] == body["metrics"]["heading_error_after_deg"]
    assert [rows[k]["before_deg"] for k in range(3)] == pytest.approx([9.38, 23.84, 38.97], abs=0.01)
    assert all(rows[k]["measures"] and rows[k]["orientation"] == "NONE" for k in range(3))
    assert all(rows[k]["pull"]["unit"] == "µT/A" and rows[k]["pull"]["determined"] is False for k in range(3))
    (one, two) = body["flight"]["consistency"]
    assert one["pair"] == [0, 1] and one["consistent"] and one["xy_angle_deg"] == pytest.approx(15.70, abs=0.01)
    assert (
        two["pair"] == [0, 2] and not two["consistent"] and two["xy_length_diff_ut"] == pytest.approx(52.87, abs=0.01)
    )
    assert rows[2]["action"].startswith("calibrate it or stop its use (COMPASS_USE3 = 0)")
    assert (
        rows[0]["action"]
        == rows[1]["action"]
        == "fly turns through every heading (a slow full yaw turn, or circles), banked as well as level"
    )
    assert rows[0]["reason"].startswith("the flight held one heading for most of it")


def test_the_attitude_judged_by_is_chosen_among_the_logs_estimates(client, log171):
    """MAGFit's control: the compass judged by another estimator's attitude. On log171.bin ATT (the EKF flown by)
    and EKF1 agree; the DCM backup AHR2 gives other figures (MAG's before 8.7° against 9.4°); an estimate the log
    lacks is refused naming those it has, and a PX4 log takes its vehicle_attitude only."""
    by = {}
    for attitude in (None, "AHR2", "EKF1"):
        body = _calibrate(client, log171, mag_instance=0, **({"attitude": attitude} if attitude else {})).json()
        assert body["flight"]["attitude_source"] == f"{attitude or 'ATT'} Roll, Pitch, Yaw (deg)"
        by[attitude] = [round(row["before_deg"], 1) for row in body["flight"]["compasses"]]
    assert by[None] == by["EKF1"] == [9.4, 23.8, 39.0] and by["AHR2"] == [8.7, 26.7, 27.8]
    refused = _calibrate(client, log171, attitude="XKF1")
    assert refused.status_code == 422 and refused.json()["detail"].endswith(
        "has no XKF1 messages: choose attitude among those it logs (ATT, AHR2, EKF1)"
    )
    px4 = _upload(client, LOG171.parent / "px4_1.9_esc_status_log.ulg")
    refused = _calibrate(client, px4, attitude="ATT")
    assert refused.status_code == 422 and "a PX4 log's attitude is vehicle_attitude" in refused.json()["detail"]


def test_a_flight_log_s_implausible_fit_never_asks_for_the_unit_the_log_states(client):
    """The PX4 1.6 log of tests/data/real/flight, parked one way (1 of 8 sectors), with the place given (it has no
    GPS): its undetermined scale (−8.6) is refused by the flight's own gates, never with a unit to give (the upload
    of a flight log refuses mag_unit)."""
    rid = _upload(client, LOG171.parent / "sample_appended_multiple.ulg")
    body = _calibrate(client, rid, latitude_deg=47.4, longitude_deg=8.5, date="2017-01-01").json()
    assert body["ok"] is False and body["reasons"][0].startswith("only 439 samples"), body["reasons"]
    assert not any("mag_unit" in r or "MEMS" in r for r in body["reasons"] + body["warnings"]), body["reasons"]
    assert any(r.startswith("the soft-iron matrix scales the field by -8.62") for r in body["reasons"])


def test_real_arduplane_logs_without_imu_are_read_for_their_compass(client):
    """Two real ArduPlane 4.2.3 logs of minimal logging (ATT, MAG, GPS; no IMU message; PyFlightCoach/FlightData),
    the plane on the ground in MANUAL: each is read for its compass alone. The first's GPS fix has no GPS time, so
    the compass from the flight is listed but asks for `date` (not run by itself), and with it answers; the
    second's runs at once. Neither is ok: the plane hardly turned (the orientation unresolved, 46° and 28° from
    every rotation)."""
    center = client.post(
        "/api/v1/recordings",
        files={"file": ("center.bin", (LOG171.parent / "arduplane_4.2_center_0003.bin").read_bytes())},
    ).json()
    (support,) = [s for s in center["supports"] if s["method"] == "compass_flight"]
    assert support["ready"] is False and support["asks"] == ["date"]
    assert support["why"].endswith("at its GPS fix (51.64°, -2.53°; the log has no GPS time: give `date`)")
    assert center["channels"] == ["mag"] and center["flight"]["fix"]["date"] is None
    body = _calibrate(client, center["id"], date="2025-01-03").json()
    assert body["ok"] is False and body["metrics"]["n_samples"] == 464
    assert any(
        r.startswith("the compass's orientation is unresolved: the rotation the data show is 46°")
        for r in body["reasons"]
    )
    pilot = _upload(client, LOG171.parent / "arduplane_4.2_pilot_0004.bin")
    body = _calibrate(client, pilot).json()
    assert body["ok"] is False and body["reasons"][0].startswith(
        "the compass's orientation is unresolved: the rotation the data show is 28° from every firmware rotation"
    )
    assert body["metrics"]["heading_error_before_deg"] == pytest.approx(24.91, abs=0.01)


def _level(tmp_path, seed: int):
    """A seeded flight kept within 2° of level (a yaw turn a minute, 2.5 min at 10 Hz, no soft iron), written as
    an ArduPilot log with the firmware's stale offsets stored."""
    flight = seeded_flight(seed, orientation=0, tilt_deg=2.0, soft_iron=0.0, duration_s=150.0, rate_hz=10.0)
    return flight, write_flight_compass_logs(tmp_path, flight, stem=f"level{seed}")[0]


def test_a_level_flight_whose_numbers_are_bounded_is_ok(client, tmp_path):
    """Level flights reach a tenth of the directions, yet where every number's interval is within the gates the fit
    stands: the offsets within 0.1 µT of the truth, the heading error 30.1° → 1.02°."""
    flight, log = _level(tmp_path, 22)
    body = _calibrate(client, _upload(client, log)).json()
    assert body["ok"] is True and body["flight"]["updated"] is None, body["reasons"]
    assert body["metrics"]["coverage"] == pytest.approx(0.10)
    np.testing.assert_allclose(body["model"]["b"], flight["truth"]["b"], atol=0.1)
    assert (
        round(body["metrics"]["heading_error_before_deg"], 1),
        round(body["metrics"]["heading_error_after_deg"], 2),
    ) == (
        30.1,
        1.02,
    )


def test_what_the_flight_does_not_determine_is_kept_and_the_file_says_so(client, tmp_path):
    """A level flight that leaves the vertical offset open: it is held at the firmware's stored value, and with it
    the motor term on that axis (which would take up a stale held offset), the horizontal offsets and the motor
    term's horizontal parts updated (11.7° → 1.15° on segments left out, beyond the interval of that drop); the
    answer and the parameter file say which are new. The intervals assume the held values right: here the z offset
    is 8.5 µT off; the horizontal offsets land within 0.07 µT of the truth and the motor term's within 0.006 µT/A,
    inside their intervals."""
    flight, log = _level(tmp_path, 24)
    body = _calibrate(client, _upload(client, log)).json()
    assert body["ok"] is True, body["reasons"]
    assert body["flight"]["updated"] == {"b": [True, True, False], "M": False, "k": [True, True, False]}
    held = next(w for w in body["warnings"] if w.startswith("the flight does not determine the z offset"))
    assert "the motor term on z" in held and held.endswith("(their intervals assume the held values are right)"), held
    assert body["uncertainty"]["b"][2] == pytest.approx(0.0, abs=1e-9) and body["uncertainty"]["k"][2] == 0.0
    off = np.asarray(body["model"]["b"]) - flight["truth"]["b"]
    assert list(np.round(off, 2)) == [-0.07, -0.02, 8.52] and np.all(np.abs(off[:2]) < body["uncertainty"]["b"][:2])
    k_off = np.asarray(body["model"]["k"]) - flight["truth"]["k"]
    assert np.all(np.abs(k_off[:2]) < body["uncertainty"]["k"][:2]) and body["model"]["k"][2] == 0.0  # none stored
    stored_b = -np.asarray(body["flight"]["stored"]["offsets_ut"])  # ArduPilot adds COMPASS_OFS: b = −O
    assert body["model"]["b"][2] == pytest.approx(stored_b[2])
    assert (
        round(body["metrics"]["heading_error_before_deg"], 1),
        round(body["metrics"]["heading_error_after_deg"], 2),
    ) == (
        11.7,
        1.15,
    )
    text = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "ardupilot"}).text
    assert "# new from this flight: the x offset, the y offset, the motor term on x, the motor term on y\n" in text
    kept = "the z offset, the soft iron, the motor term on z"
    assert f"# kept at the values stored before (the flight does not determine them): {kept}\n" in text


def test_a_copter_3_5_landing_says_which_compass_the_current_pulls(client):
    """A real ArduCopter 3.5 log (tests/data/real/flight: spark404/dataflashlog's test log, an RTL descent and
    landing of 51 s, two compasses, COMPASS_MOTCT 0): both compasses are listed and ready with the log's fix
    (Netherlands, 2017-09-10); neither fit is ok (484 samples, 95 % of them in one sector of heading), but the
    table of compasses says what the flight does show: the external one is good as it is, the internal one is
    pulled 9° by the current (a pull the flight determines), so COMPASS_MOT2 is what to set. The internal one's own
    fit leaves its x and z offsets open: held at COMPASS_OFS2, with the motor term on those axes."""
    path = LOG171.parent / "arducopter_3.5_rtl_landing_dataflashlog.bin"
    r = client.post("/api/v1/recordings", files={"file": (path.name, path.read_bytes())})
    assert r.status_code == 201, r.text
    rec = r.json()
    assert [i["instance"] for i in rec["flight"]["instances"] if i["sensor"] == "mag"] == [0, 1]
    body = _calibrate(client, rec["id"], mag_instance=1).json()
    assert body["ok"] is False and body["reasons"][0].startswith("only 484 samples"), body["reasons"]
    assert (
        round(body["metrics"]["heading_error_before_deg"], 1),
        round(body["metrics"]["heading_error_after_deg"], 1),
    ) == (4.4, 3.4)
    assert body["flight"]["updated"] == {"b": [False, True, False], "M": True, "k": [False, True, False]}
    rows = {row["instance"]: row for row in body["flight"]["compasses"]}
    assert rows[0]["action"] == "keep it as it is"
    assert rows[1]["action"] == "set COMPASS_MOT2_X/Y/Z (COMPASS_MOTCT = 2) from this flight (the current pulls it 9°)"
    assert [c["consistent"] for c in body["flight"]["consistency"]] == [True]


def test_a_long_log_is_thinned_evenly_and_says_so(client, flight, tmp_path, monkeypatch):
    """A log of more compass samples than the fit takes (60 000, 40 min at 25 Hz; here the limit lowered to 1 500
    for a 3 min flight of 4 500) is fitted on every k-th sample: the answer says so, and it is the full log's
    within a few hundredths of a degree and a few tenths of a µT, inside the intervals."""
    import app.calibration.magnetometer.flight as core

    log = write_flight_compass_logs(tmp_path, flight)[0]
    full = _calibrate(client, _upload(client, log)).json()
    monkeypatch.setattr(core, "MAX_FIT_SAMPLES", 1500)
    thin = _calibrate(client, _upload(client, log)).json()
    assert full["ok"] and thin["ok"], thin["reasons"]
    n = len(flight["time_s"])
    said = f"a long log: one in 3 of its {n} compass samples fitted (at most 1500;"
    assert any(line.startswith(said) for line in thin["warnings"]), thin["warnings"]
    assert abs(thin["metrics"]["heading_error_after_deg"] - full["metrics"]["heading_error_after_deg"]) < 0.05
    diff = np.abs(np.asarray(thin["model"]["b"]) - np.asarray(full["model"]["b"]))
    assert np.all(diff < np.asarray(thin["uncertainty"]["b"])), (diff, thin["uncertainty"]["b"])


def test_an_ardusub_dive_without_gps_asks_for_the_place_and_says_what_it_lacks(client):
    """A real ArduSub 4.1 dive (tests/data/real/flight: clydemcqueen/ardusub_log_tools' small.BIN; two compasses whose
    field, as the firmware corrects it, reads 91 and 105 µT against the model's 53 µT; no GPS): the compass from the
    flight asks for the place and day; given them, neither compass is ok, for the samples and the one heading the
    dive holds first, and the second compass's fitted z offset of −720 µT is named as no iron's."""
    path = LOG171.parent / "ardusub_4.1_small.bin"
    rec = client.post("/api/v1/recordings", files={"file": (path.name, path.read_bytes())}).json()
    flight = next(s for s in rec["supports"] if s["method"] == "compass_flight")
    assert not flight["ready"] and "latitude_deg" in flight["asks"], flight
    place = {"latitude_deg": 48.386, "longitude_deg": -124.631, "date": "2023-05-04"}
    body = _calibrate(client, rec["id"], mag_instance=1, **place).json()
    assert body["ok"] is False and body["reasons"][0].startswith("only 86 samples"), body["reasons"]
    assert any(r.startswith("the flight turned through too few headings (1 of 8 sectors") for r in body["reasons"])
    assert any(r.startswith("the z offset -720 µT is beyond 300 µT") for r in body["reasons"]), body["reasons"]
    assert [row["action"] for row in body["flight"]["compasses"]] == [
        "fly at least a minute (600 samples) with turns through every heading"
    ] * 2


@pytest.mark.parametrize(
    ("name", "samples"),
    [
        ("px4_1.12_roboto_test.ulg", 10),
        ("sample_log_small.ulg", 6),
        ("sample_px4_events.ulg", 31),
        ("arducopter_4.6_backend_log_80k.bin", 4),
    ],
)
def test_a_real_log_whose_compass_logged_too_few_samples_is_not_ready_for_the_compass(client, name, samples):
    # These logs' compasses logged a few samples each (a bench test, a log cut at 80 kB): the compass from the
    # flight was listed as ready, and the page ran it into a refusal ("N usable compass samples … at least 60").
    path = LOG171.parent / name
    rec = client.post("/api/v1/recordings", files={"file": (path.name, path.read_bytes())}).json()
    support = next(s for s in rec["supports"] if s["method"] == "compass_flight")
    assert support["ready"] is False and support["asks"] == [], support
    assert support["why"] == (
        f"its compass 0 logged {samples} samples: a calibration from a flight needs at least 60, and a minute of "
        "flight with turns"
    )
    refused = _calibrate(client, rec["id"], latitude_deg=47.4, longitude_deg=8.5, date="2020-01-01")
    assert refused.status_code == 422, refused.text  # the support says what the calibration would refuse
