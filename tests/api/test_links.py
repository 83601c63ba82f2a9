"""Short links (issue 24): a session's calibration sent from the phone to a computer. The link reads
that one calibration as its owner until it expires, and nothing else."""

from __future__ import annotations

import sys
import time
from datetime import UTC, datetime

import httpx
import numpy as np
from fastapi.testclient import TestClient

from app.calibration import CANONICAL_SIX
from app.main import create_app
from app.reach.tls import lan_addresses
from tests.api.test_sessions import auth, start
from tests.conftest import make_settings
from tests.live_server import free_port, live_server
from tests.phone_poses import pose_samples


def solved(client) -> tuple[dict, str]:
    s = start(client)
    rng = np.random.default_rng(3)
    for label in CANONICAL_SIX:
        assert (
            client.post(
                f"/api/v1/sessions/{s['id']}/captures", json=pose_samples(label, rng), headers=auth(s["token"])
            ).status_code
            == 201
        )
    r = client.post(f"/api/v1/sessions/{s['id']}/solve", headers=auth(s["token"]))
    assert r.status_code == 201, r.text
    return r.json(), s["token"]


def test_a_link_reads_its_one_calibration_until_it_expires(tmp_path):
    with TestClient(create_app(make_settings(tmp_path, link_ttl_min=0.01))) as client:  # 0.6 s
        cal, token = solved(client)
        other, _other_token = solved(client)
        assert client.post(f"/api/v1/calibrations/{cal['id']}/links").status_code == 404  # not the session's
        r = client.post(f"/api/v1/calibrations/{cal['id']}/links", headers=auth(token))
        assert r.status_code == 201, r.text
        link = r.json()
        assert link["url"] == f"http://testserver/s/{link['code']}" and link["qr"].startswith("data:image/svg+xml")
        opened = client.get(f"/api/v1/links/{link['code'].lower()}").json()
        assert opened["calibration_id"] == cal["id"] and opened["token"] == "lnk_" + link["code"]
        as_link = auth(opened["token"])
        assert client.get(f"/api/v1/calibrations/{cal['id']}", headers=as_link).json()["id"] == cal["id"]
        assert (
            client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": "c"}, headers=as_link).status_code
            == 200
        )
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
        assert (
            client.get(f"/api/v1/calibrations/{cal['id']}", headers=auth(token)).status_code == 200
        )  # the phone still


def test_the_link_page_and_a_code_that_is_no_code(client):
    r = client.get("/s/ABCDEFGHJK")
    assert r.status_code == 200 and 'data-link="ABCDEFGHJK"' in r.text
    assert client.get("/s/abc").status_code == 404


def test_the_link_is_at_the_address_the_phone_reached_and_a_loopback_one_becomes_the_lan_address(tmp_path):
    """A real server on every interface (as `trical serve --host 0.0.0.0`): a phone on the LAN reaches it at
    the LAN address and its link is there; a request on this machine (loopback) gets the same LAN address (the
    start page's QR code finds it so); another name the request used (its Host) is kept; the link page opens
    at the LAN address; the expiry is ISO 8601 with its offset."""
    lan = lan_addresses()[0]
    assert lan != "127.0.0.1", "this test needs a LAN address"
    with _everywhere(tmp_path) as server:
        at_lan = f"http://{lan}:{server.port}"
        with httpx.Client(base_url=at_lan, timeout=30) as phone:
            cal, token = solved(phone)
            link = phone.post(f"/api/v1/calibrations/{cal['id']}/links", headers=auth(token)).json()
            assert link["url"] == f"{at_lan}/s/{link['code']}"
            expires = datetime.fromisoformat(link["expires_at"])
            assert expires.utcoffset() is not None and expires > datetime.now(UTC)
            assert phone.get(link["url"]).status_code == 200  # the other machine opens it there
        with httpx.Client(base_url=f"http://127.0.0.1:{server.port}", timeout=30) as here:
            loop = here.post(f"/api/v1/calibrations/{cal['id']}/links", headers=auth(token)).json()
            assert loop["url"] == f"{at_lan}/s/{loop['code']}"
            named = here.post(
                f"/api/v1/calibrations/{cal['id']}/links", headers={**auth(token), "Host": "trical.lan:8765"}
            )
            assert named.json()["url"] == f"http://trical.lan:8765/s/{named.json()['code']}"


def _everywhere(tmp_path):
    """`trical serve --host 0.0.0.0` over HTTP: reachable at loopback and at the LAN address."""
    port = free_port()
    return live_server(
        {"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}"},
        port=port,
        command=[sys.executable, "-m", "app.cli", "serve", "--host", "0.0.0.0", "--port", str(port)],
    )
