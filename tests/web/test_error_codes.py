"""The error JSON carries a stable `code` the page decides on (never the message text): the codes
the wizard reads, from real requests."""

from __future__ import annotations

import numpy as np
from fastapi.testclient import TestClient

from app.main import create_app
from tests.conftest import make_settings
from tests.phone_poses import pose_samples


def test_the_wizard_s_codes(client):
    s = client.post("/api/v1/sessions", json={"protocol": "six", "capture_s": 5}).json()
    h = {"Authorization": f"Bearer {s['token']}"}
    url = f"/api/v1/sessions/{s['id']}"
    capture = pose_samples("+z", np.random.default_rng(1))
    assert client.post(f"{url}/captures", json=capture, headers=h).status_code == 201
    again = client.post(f"{url}/captures", json=capture, headers=h)
    assert again.status_code == 409 and again.json()["code"] == "already_captured"
    assert "already captured" in again.json()["detail"]
    missing = client.post(f"{url}/solve", headers=h)
    assert missing.status_code == 422 and missing.json()["code"] == "insufficient_data"
    turning = dict(pose_samples("-z", np.random.default_rng(2)), gyr=[[20.0, 0.0, 0.0]] * 300)
    refused = client.post(f"{url}/captures", json=turning, headers=h)
    assert refused.status_code == 422 and refused.json()["code"] == "not_still"
    bad = client.post(f"{url}/captures", json={"acc": "nope"}, headers=h)
    assert bad.status_code == 422 and bad.json()["code"] == "invalid_request"
    stale = client.get(url, headers={"Authorization": "Bearer tks_not-this-one"})  # a reload with a stale token
    assert stale.status_code == 401 and stale.json()["code"] == "unauthorized"
    forgotten = client.get("/api/v1/sessions/ses_gone", headers=h)  # a session the server no longer has
    assert forgotten.status_code == 404 and forgotten.json()["code"] == "not_found"
    gone = client.get("/api/v1/calibrations/cal_nothing-here")
    assert gone.status_code == 404 and gone.json()["code"] == "not_found"
    assert client.get("/api/v1/no-such-route").json()["code"] == "http_error"


def test_a_server_with_api_keys_answers_unauthorized(tmp_path):
    with TestClient(create_app(make_settings(tmp_path, api_keys=("k-123",)))) as c:
        r = c.post("/api/v1/sessions", json={"protocol": "six"})
    assert r.status_code == 401 and r.json()["code"] == "unauthorized"
    assert r.headers["www-authenticate"] == "Bearer"


BROWSER = {"Accept": "text/html,application/xhtml+xml,application/xml;q=0.9,*/*;q=0.8"}
"""What a browser's navigation sends."""


def test_an_unknown_address_is_a_page_for_a_browser_and_json_for_the_api(client):
    page = client.get("/nope", headers=BROWSER)
    assert page.status_code == 404 and page.headers["content-type"].startswith("text/html")
    assert "<h1>No page at this address</h1>" in page.text and "“/nope” is not a page of trical" in page.text
    assert (
        '<a id="not-found-start" href="/">' in page.text and '<a id="not-found-history" href="/history">' in page.text
    )
    program = client.get("/nope", headers={"Accept": "application/json"})  # a program asking outside the API
    assert program.status_code == 404 and program.json()["code"] == "http_error"
    api = client.get("/api/v1/nope", headers=BROWSER)  # the API answers JSON, whoever asks
    assert api.status_code == 404 and api.json()["code"] == "http_error"
    method = client.post("/history", headers=BROWSER)  # not a 404: its own status, in JSON
    assert method.status_code == 405 and method.json()["code"] == "http_error"
