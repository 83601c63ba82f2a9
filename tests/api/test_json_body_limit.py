"""JSON bodies above TRICAL_MAX_JSON_MB are refused with 413 before they are parsed (app.api.body_limit).

The large cases run against a real server in a subprocess over real HTTP: its answer must come
within a second, and its memory must not grow with the body (read from /proc/<pid>/status).
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import httpx
import numpy as np
import pytest
from fastapi.testclient import TestClient

from app.config import Settings, SettingsError
from app.main import create_app
from tests.conftest import make_settings
from tests.live_server import live_server

DATA = Path(__file__).resolve().parent.parent / "data"
HUGE_BYTES = 200 << 20
DEFAULT_LIMIT = Settings().max_json_bytes
SIX = {
    "-x": [-9.7, 0.1, 0.2],
    "+x": [9.9, 0.1, 0.2],
    "-y": [0.1, -9.7, 0.2],
    "+y": [0.1, 9.9, 0.2],
    "-z": [0.1, 0.1, -9.6],
    "+z": [0.1, 0.1, 10.0],
}


def six_body(**extra) -> dict:
    return {"method": "six_position", "readings": [{"up": k, "mean": v} for k, v in SIX.items()], **extra}


def padded(body: dict, size: int) -> bytes:
    """``body`` as JSON followed by spaces (still valid JSON) up to exactly ``size`` bytes."""
    raw = json.dumps(body).encode()
    assert len(raw) <= size
    return raw + b" " * (size - len(raw))


def rss_bytes(pid: int) -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
    raise AssertionError(f"no VmRSS in /proc/{pid}/status")


def chunks(total: int, size: int = 1 << 20):
    sent = 0
    while sent < total:
        piece = min(size, total - sent)
        sent += piece
        yield b" " * piece


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    db = tmp_path_factory.mktemp("json-limit") / "trical.db"
    with live_server({"TRICAL_DATABASE_URL": f"sqlite:///{db}"}) as s:
        yield s


def assert_refused(response: httpx.Response) -> None:
    assert response.status_code == 413, response.text
    body = response.json()
    assert body["code"] == "payload_too_large"
    assert "TRICAL_MAX_JSON_MB" in body["detail"] and f"{DEFAULT_LIMIT / 2**20:g} MiB" in body["detail"]


@pytest.mark.parametrize("declared", [False, True], ids=["chunked", "content-length"])
def test_a_200_mb_body_is_refused_at_once_without_growing_the_server(server, declared):
    pid = server.process.pid
    before = rss_bytes(pid)
    headers = {"content-type": "application/json"}
    if declared:
        headers["content-length"] = str(HUGE_BYTES)
    start = time.monotonic()
    response = httpx.post(f"{server.url}/api/v1/calibrations", content=chunks(HUGE_BYTES), headers=headers, timeout=30)
    elapsed = time.monotonic() - start
    grown = rss_bytes(pid) - before
    assert_refused(response)
    assert elapsed < 1.0, f"the 413 took {elapsed:.2f} s"
    assert grown < 50e6, f"the server grew by {grown / 1e6:.0f} MB"
    assert server.process.poll() is None
    assert httpx.get(f"{server.url}/healthz").status_code == 200


@pytest.mark.parametrize("declared", [False, True], ids=["chunked", "content-length"])
def test_a_body_of_exactly_the_limit_is_served_and_one_byte_more_is_not(server, declared):
    def post(raw: bytes) -> httpx.Response:
        headers = {"content-type": "application/json"}
        content = raw if declared else chunks_of(raw)
        return httpx.post(f"{server.url}/api/v1/calibrations", content=content, headers=headers, timeout=60)

    at_limit = padded(six_body(), DEFAULT_LIMIT)
    ok = post(at_limit)
    assert ok.status_code == 201, ok.text
    assert ok.json()["method"] == "six_position"
    assert_refused(post(at_limit + b" "))


def chunks_of(raw: bytes, size: int = 1 << 20):
    for i in range(0, len(raw), size):
        yield raw[i : i + size]


def test_a_holdout_of_100_000_readings_fits_the_default(server):
    # The schema's largest holdout, at full double precision as a browser writes it (about 5.6 MiB).
    holdout = (np.random.default_rng(1).normal(0, 1, (100_000, 3)) * 9.81).tolist()
    raw = json.dumps(six_body(holdout=holdout)).encode()
    assert len(raw) < DEFAULT_LIMIT / 2
    r = httpx.post(
        f"{server.url}/api/v1/calibrations", content=raw, headers={"content-type": "application/json"}, timeout=60
    )
    assert r.status_code == 201, r.text


def test_the_cap_follows_the_setting_and_spares_uploads(tmp_path):
    settings = make_settings(tmp_path, max_json_mb=0.01)  # 10 KiB, far below the CSV below
    with TestClient(create_app(settings), raise_server_exceptions=False) as client:
        r = client.post(
            "/api/v1/calibrations", content=padded(six_body(), 20_000), headers={"content-type": "application/json"}
        )
        assert r.status_code == 413 and r.json()["code"] == "payload_too_large"
        assert "0.01 MiB" in r.json()["detail"]
        small = client.post("/api/v1/calibrations", json=six_body())
        assert small.status_code == 201, small.text
        log = DATA / "six_orientations_150hz.csv"
        assert log.stat().st_size > 20 * settings.max_json_bytes
        with open(log, "rb") as f:
            up = client.post(
                "/api/v1/recordings", files={"file": (log.name, f, "text/csv")}, data={"sampling_rate_hz": "150"}
            )
        assert up.status_code == 201, up.text
        # Outside /api/ nothing is capped by it (the pages take no bodies; a 405 is not a 413).
        assert client.post("/healthz", content=b" " * 20_000).status_code != 413


@pytest.mark.parametrize("value", ["abc", "0", "-1", "inf", "nan"])
def test_the_setting_is_validated(value):
    with pytest.raises(SettingsError, match="TRICAL_MAX_JSON_MB"):
        Settings.from_env({"TRICAL_MAX_JSON_MB": value})


def test_the_setting_is_read():
    assert Settings.from_env({"TRICAL_MAX_JSON_MB": "2.5"}).max_json_bytes == int(2.5 * 2**20)
