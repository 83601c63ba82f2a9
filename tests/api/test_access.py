"""TRICAL_API_KEYS: every API call needs a key; each key sees only what it created."""

from __future__ import annotations

import pytest
from fastapi.testclient import TestClient

from app.main import create_app
from tests.api.test_calibrations import CANONICAL, six_request
from tests.api.test_recordings import LOG
from tests.conftest import make_settings, seed_table


@pytest.fixture
def keyed(tmp_path):
    with TestClient(create_app(make_settings(tmp_path, api_keys=("key-a", "key-b")))) as c:
        yield c


def auth(key):
    return {"Authorization": f"Bearer {key}"}


def test_two_keys_never_see_each_other(keyed):
    a = keyed.post(
        "/api/v1/calibrations", json=six_request(seed_table(1), CANONICAL, device_id="d"), headers=auth("key-a")
    )
    b = keyed.post(
        "/api/v1/calibrations", json=six_request(seed_table(1), CANONICAL, device_id="d"), headers=auth("key-b")
    )
    assert a.status_code == b.status_code == 201
    ida, idb = a.json()["id"], b.json()["id"]
    assert keyed.get(f"/api/v1/calibrations/{ida}", headers=auth("key-a")).status_code == 200
    assert keyed.get(f"/api/v1/calibrations/{ida}", headers=auth("key-b")).status_code == 404
    assert keyed.get(f"/api/v1/calibrations/{idb}/export", headers=auth("key-a")).status_code == 404
    assert (
        keyed.post(
            f"/api/v1/calibrations/{idb}/apply", json={"samples": [[1, 2, 3]]}, headers=auth("key-a")
        ).status_code
        == 404
    )
    assert [
        c["id"]
        for c in keyed.get("/api/v1/calibrations", params={"device_id": "d"}, headers=auth("key-a")).json()["items"]
    ] == [ida]
    rec = keyed.post(
        "/api/v1/recordings",
        files={"file": ("log.csv", LOG.read_bytes(), "text/csv")},
        data={"sampling_rate_hz": "150"},
        headers=auth("key-a"),
    )
    assert rec.status_code == 201
    other = keyed.post(
        "/api/v1/calibrations", json={"method": "six_position", "recording_id": rec.json()["id"]}, headers=auth("key-b")
    )
    assert other.status_code == 404


@pytest.mark.parametrize(
    "headers", [{}, auth("wrong"), {"Authorization": "Basic a2V5LWE="}, {"Authorization": "Bearer "}]
)
def test_missing_or_wrong_key_is_401(keyed, headers):
    r = keyed.get("/api/v1/calibrations", headers=headers)
    assert r.status_code == 401 and r.headers["www-authenticate"] == "Bearer"
    assert "API key" in r.json()["detail"]
    assert (
        keyed.post("/api/v1/calibrations", json=six_request(seed_table(1), CANONICAL), headers=headers).status_code
        == 401
    )


def test_health_and_pages_need_no_key(keyed):
    assert keyed.get("/healthz").status_code == 200
    assert keyed.get("/").status_code == 200


def test_rate_limit_per_client(tmp_path):
    with TestClient(create_app(make_settings(tmp_path, rate_limit_per_minute=5))) as c:
        codes = [c.get("/api/v1/calibrations").status_code for _ in range(7)]
        assert codes[:5] == [200] * 5 and codes[5:] == [429, 429]
        r = c.get("/api/v1/calibrations")
        assert int(r.headers["retry-after"]) >= 1 and "TRICAL_RATE_LIMIT_PER_MINUTE" in r.json()["detail"]
        assert c.get("/healthz").status_code == 200  # not an API call


def test_token_bucket_refills():
    from app.api.ratelimit import RateLimiter

    limiter = RateLimiter(60)  # one a second
    assert all(limiter.acquire("a", now=0.0) == 0 for _ in range(60))
    assert limiter.acquire("a", now=0.0) == pytest.approx(1.0)
    assert limiter.acquire("b", now=0.0) == 0  # another client has its own bucket
    assert limiter.acquire("a", now=1.0) == 0
