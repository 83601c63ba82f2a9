"""GET /api/v1/calibrations/{id}/export of a compass calibrated from a flight (method compass_flight), stored
as its calibration body: the ArduPilot and PX4 files and the JSON over HTTP, and a 422 export_refused in words
for a format that does not fit (the formulas themselves: tests/io/test_export_flight_compass.py)."""

from __future__ import annotations

import numpy as np

from tests.io.test_export_flight_compass import YAW_90, flight_body, parse_ardupilot, parse_px4


def _stored(client, body: dict) -> str:
    return client.app.state.store.add_calibration(body, owner=None)["id"]


def test_flight_compass_exports_over_http(client):
    cal = _stored(client, flight_body(Q=YAW_90, orientation=8, params={"COMPASS_EXTERNAL": 1}))
    r = client.get(f"/api/v1/calibrations/{cal}/export", params={"format": "ardupilot"})
    assert r.status_code == 200, r.text
    assert r.headers["content-type"].startswith("text/plain")
    assert f'filename="trical_{cal}_ardupilot.parm"' in r.headers["content-disposition"]
    params = parse_ardupilot(r.text)
    assert params["COMPASS_ORIENT"] == 10 and params["COMPASS_MOTCT"] == 2
    doc = client.get(f"/api/v1/calibrations/{cal}/export", params={"format": "json"}).json()
    assert doc["id"] == cal and doc["firmware_parameters"] == params


def test_px4_flight_compass_over_http(client):
    cal = _stored(client, flight_body("px4", params={"CAL_MAG1_ID": 396825, "CAL_MAG1_ROT": 0}))
    r = client.get(f"/api/v1/calibrations/{cal}/export", params={"format": "px4"})
    assert r.status_code == 200, r.text
    params = parse_px4(r.text)
    assert np.allclose([params[f"CAL_MAG1_{a}OFF"] for a in "XYZ"], [0.12, -0.20, 0.31])


def test_a_format_that_does_not_fit_is_refused_in_words(client):
    cal = _stored(client, flight_body())
    r = client.get(f"/api/v1/calibrations/{cal}/export", params={"format": "px4"})
    assert r.status_code == 422 and r.json()["code"] == "export_refused"
    assert "ArduPilot log" in r.json()["detail"] and "ArduPilot or JSON file" in r.json()["detail"]
    r = client.get(f"/api/v1/calibrations/{cal}/export", params={"format": "c"})
    assert r.status_code == 422 and "json, ardupilot, px4" in r.json()["detail"]
