"""Short links (issue 24): a session's calibration sent from the phone to a computer. The link reads
that one calibration as its owner until it expires, and nothing else."""

from __future__ import annotations

import time

import numpy as np
from fastapi.testclient import TestClient

from app.calibration import CANONICAL_SIX
from app.main import create_app
from tests.api.conftest import make_settings
from tests.api.test_sessions import auth, start
from tests.phone_poses import pose_samples


def solved(client) -> tuple[dict, str]:
    s = start(client)
    rng = np.random.default_rng(3)
    for label in CANONICAL_SIX:
        assert client.post(f"/api/v1/sessions/{s['id']}/captures", json=pose_samples(label, rng),
                           headers=auth(s["token"])).status_code == 201
    r = client.post(f"/api/v1/sessions/{s['id']}/solve", headers=auth(s["token"]))
    assert r.status_code == 201, r.text
    return r.json(), s["token"]


def test_a_link_reads_its_one_calibration_until_it_expires(tmp_path):
    with TestClient(create_app(make_settings(tmp_path, link_ttl_min=0.01))) as client:  # 0.6 s
        cal, token = solved(client)
        other, other_token = solved(client)
        assert client.post(f"/api/v1/calibrations/{cal['id']}/links").status_code == 404  # not the session's
        r = client.post(f"/api/v1/calibrations/{cal['id']}/links", headers=auth(token))
        assert r.status_code == 201, r.text
        link = r.json()
        assert link["url"] == f"http://testserver/s/{link['code']}" and link["qr"].startswith("data:image/svg+xml")
        opened = client.get(f"/api/v1/links/{link['code'].lower()}").json()
        assert opened["calibration_id"] == cal["id"] and opened["token"] == "lnk_" + link["code"]
        as_link = auth(opened["token"])
        assert client.get(f"/api/v1/calibrations/{cal['id']}", headers=as_link).json()["id"] == cal["id"]
        assert client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": "c"}, headers=as_link).status_code == 200
        assert client.get(f"/api/v1/calibrations/{cal['id']}/use", headers=as_link).status_code == 200
        for path in (f"/api/v1/calibrations/{other['id']}", "/api/v1/calibrations"):
            r = client.get(path, headers=as_link)
            assert r.status_code == 401 and "its own calibration only" in r.json()["detail"], path
        r = client.post(f"/api/v1/calibrations/{cal['id']}/links", headers=as_link)
        assert r.status_code == 401 and "cannot make another link" in r.json()["detail"]
        time.sleep(0.8)
        r = client.get(f"/api/v1/links/{link['code']}")
        assert r.status_code == 404 and "expired at" in r.json()["detail"] and "send it again" in r.json()["detail"]
        r = client.get(f"/api/v1/calibrations/{cal['id']}", headers=as_link)
        assert r.status_code == 401 and "expired" in r.json()["detail"]
        assert client.get(f"/api/v1/calibrations/{cal['id']}", headers=auth(token)).status_code == 200  # the phone still


def test_the_link_page_and_a_code_that_is_no_code(client):
    r = client.get("/s/ABCDEFGHJK")
    assert r.status_code == 200 and 'data-link="ABCDEFGHJK"' in r.text
    assert client.get("/s/abc").status_code == 404
