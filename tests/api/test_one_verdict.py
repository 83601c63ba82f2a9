"""One verdict, from the final result (issue 42, deliverable 3): ``ok``, the reasons, the headline and the verdict
of a calibration are computed once, from the result as it is answered and stored (app.workflows.calibration);
nothing changes ``ok`` or ``reasons`` after them. And a noise characterisation whose filter figures are
incomplete says what is missing instead of "use these figures"."""

from __future__ import annotations

import copy
from pathlib import Path

from app import methods
from app.io.readers import read_log
from app.io.readers.read_options import ReadOptions
from app.verdict import verdict
from app.workflows.recordings import RecordingSource, describe_log
from tests.real_corpus import cases

DATA = Path(__file__).resolve().parents[1] / "data"
SIX = DATA / "six_orientations_150hz.csv"


def disagreement(body: dict) -> str:
    """How an answered calibration's verdict disagrees with its own ``ok`` and reasons ("" when it agrees):
    the verdict read again from the body as stored must be the verdict it carries, and a calibration that is
    not ok is never offered to a device."""
    if body["verdict"] != verdict({k: v for k, v in body.items() if k != "verdict"}):
        return f"the stored verdict {body['verdict']['words']!r} is not the body's own ({verdict(body)['words']!r})"
    if not body["ok"] and body["verdict"]["apply"]:
        return f"ok is false ({body['reasons'][:1]}) but the verdict says {body['verdict']['words']!r}"
    return ""


def _six_position_body(meta_questions=()) -> dict:
    log = read_log(SIX, ReadOptions(), name=SIX.name)
    meta = describe_log(log)
    meta["questions"] = [dict(q) for q in meta_questions]
    request = methods.parse_calibration_request({"method": "six_position", "recording_id": SIX.name})
    return methods.calibrate(request, RecordingSource(meta=meta, path=SIX, log=log)).body()


def test_a_good_calibration_agrees_with_its_verdict():
    body = _six_position_body()
    assert body["ok"] and body["verdict"]["kind"] == "apply", body["verdict"]
    assert disagreement(body) == ""


def test_a_question_the_reading_left_open_is_a_reason_before_the_verdict_is_said():
    # The recording's open question about the accelerometer, whose figures the calibration stands on: not ok, and
    # the verdict, computed once from the final result, says so with that reason first.
    question = {"sensor": "acc", "detail": "the accelerometer's unit is not evident from its data: give acc_unit"}
    body = _six_position_body([question])
    assert body["ok"] is False and body["reasons"][0] == question["detail"]
    assert body["verdict"]["apply"] is False and body["verdict"]["kind"] == "failed", body["verdict"]
    assert body["verdict"]["why"].startswith("The accelerometer's unit is not evident")
    assert disagreement(body) == ""


def test_a_question_about_a_sensor_the_calibration_does_not_use_changes_nothing():
    body = _six_position_body([{"sensor": "gyr", "detail": "the gyroscope's unit is not evident"}])
    assert body["ok"] and body["verdict"]["kind"] == "apply"


def test_a_step_that_changes_ok_after_the_verdict_is_caught():
    # Planted: what the old path did (the recording's question set ``ok`` and the reasons on the plain body after
    # its verdict was computed). The check the answers are held to catches it.
    body = copy.deepcopy(_six_position_body())
    body["ok"] = False
    body["reasons"] = ["the gyroscope's unit is not evident from its data: give gyr_unit"]
    assert "ok is false" in disagreement(body) or "not the body's own" in disagreement(body)


def test_a_short_real_rest_says_what_a_filter_lacks_and_how_long_to_record(client):
    # A real phone (LSM6DS3) flat on a table for 13.7 s, uploaded as the page sends it: its white noise shows, its
    # random walk cannot. Kalibr's, OpenVINS's and VINS-Fusion's files need both, so the verdict does not say
    # "use these figures in your filter": it says what is missing and how long to record.
    case = next(c for c in cases() if c.name == "hyperimu_lsm6ds3_phone_still")
    rec = client.post("/api/v1/recordings", files=case.upload_parts(), data=case.form).json()
    r = client.post("/api/v1/calibrations", json={"method": "noise", "recording_id": rec["id"]})
    body = r.json()
    v = body["verdict"]
    assert r.status_code == 201 and body["ok"] and v["kind"] == "figures" and v["apply"] is True, v
    assert v["words"].startswith("Not enough for a filter yet: "), v["words"]
    assert "random walk did not show in this rest — record the device still for " in v["words"], v["words"]
    assert "JSON and CSV files and the Allan plot" in v["why"]
    for sensor in ("acc", "gyr"):
        assert body["metrics"][sensor]["record_for_s"]["random_walk"] > body["duration_s"], body["metrics"][sensor]
    assert disagreement(body) == ""
    # What is offered works: the JSON and the CSV; Kalibr says why not.
    assert client.get(f"/api/v1/calibrations/{body['id']}/export?format=json").status_code == 200
    assert client.get(f"/api/v1/calibrations/{body['id']}/export?format=kalibr").status_code == 422
