"""The rate limit counts per verified caller: made-up bearer tokens share their address's bucket."""

from __future__ import annotations

import secrets

import pytest
from fastapi.testclient import TestClient

from app.main import create_app
from tests.conftest import make_settings

LIMIT = 10


def auth(token: str) -> dict:
    return {"Authorization": f"Bearer {token}"}


def made_up(n: int, prefix: str = "") -> list[str]:
    return [prefix + secrets.token_urlsafe(16) for _ in range(n)]


def assert_limited(responses) -> None:
    passed = [r for r in responses if r.status_code != 429]
    refused = [r for r in responses if r.status_code == 429]
    # A bucket of LIMIT, refilled at LIMIT a minute: one more may trickle in on a slow machine.
    assert LIMIT <= len(passed) <= LIMIT + 1, [r.status_code for r in responses]
    for r in refused:
        assert int(r.headers["retry-after"]) >= 1
        assert "TRICAL_RATE_LIMIT_PER_MINUTE" in r.json()["detail"]


@pytest.mark.parametrize("prefix", ["", "tks_"], ids=["key-like", "session-like"])
def test_made_up_tokens_share_the_address_bucket(tmp_path, prefix):
    with TestClient(create_app(make_settings(tmp_path, rate_limit_per_minute=LIMIT))) as c:
        responses = [c.get("/api/v1/calibrations", headers=auth(t)) for t in made_up(50, prefix)]
        assert_limited(responses)
        # The address's own calls, without a token, are in the same (now empty) bucket.
        assert c.get("/api/v1/calibrations").status_code == 429


def test_with_keys_a_valid_key_has_its_own_bucket(tmp_path):
    settings = make_settings(tmp_path, rate_limit_per_minute=LIMIT, api_keys=("key-a", "key-b"))
    with TestClient(create_app(settings)) as c:
        responses = [c.get("/api/v1/calibrations", headers=auth(t)) for t in made_up(50)]
        assert_limited(responses)
        assert {r.status_code for r in responses} == {401, 429}
        for key in ("key-a", "key-b"):
            codes = [c.get("/api/v1/calibrations", headers=auth(key)).status_code for _ in range(LIMIT)]
            assert codes == [200] * LIMIT, key
            refused = c.get("/api/v1/calibrations", headers=auth(key))
            assert refused.status_code == 429 and int(refused.headers["retry-after"]) >= 1


def test_a_wizard_session_token_has_its_own_bucket(tmp_path):
    with TestClient(create_app(make_settings(tmp_path, rate_limit_per_minute=LIMIT))) as c:
        created = c.post("/api/v1/sessions", json={"protocol": "six"})
        assert created.status_code == 201, created.text
        session = created.json()
        # Spend the address's bucket with made-up tokens; the session's token is unaffected.
        [c.get("/api/v1/calibrations", headers=auth(t)) for t in made_up(LIMIT)]
        assert c.get("/api/v1/calibrations").status_code == 429
        codes = [
            c.get(f"/api/v1/sessions/{session['id']}", headers=auth(session["token"])).status_code for _ in range(LIMIT)
        ]
        assert codes == [200] * LIMIT
        assert c.get(f"/api/v1/sessions/{session['id']}", headers=auth(session["token"])).status_code == 429
