"""Responses are gzip-compressed for clients that accept it (issue 14, item 6), over real HTTP."""

from __future__ import annotations

import gzip

import httpx
import pytest

from tests.live_server import live_server

SIX = {
    "-x": [-9.7, 0.1, 0.2],
    "+x": [9.9, 0.1, 0.2],
    "-y": [0.1, -9.7, 0.2],
    "+y": [0.1, 9.9, 0.2],
    "-z": [0.1, 0.1, -9.6],
    "+z": [0.1, 0.1, 10.0],
}


def _raw_get(url: str, encoding: str | None) -> httpx.Response:
    """A GET whose body is left as it came over the wire (httpx would decode it)."""
    headers = {"Accept-Encoding": encoding} if encoding else {"Accept-Encoding": "identity"}
    with httpx.stream("GET", url, headers=headers, timeout=10) as r:
        r.wire = b"".join(r.iter_raw())
        return r


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """One server for the module's tests (each stores its own calibration): a start costs seconds."""
    tmp_path = tmp_path_factory.mktemp("compression")
    with live_server({"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 't.db'}"}) as s:
        yield s


def test_pages_scripts_and_calibrations_come_compressed_when_asked(server):
    s = server
    cal = httpx.post(
        f"{s.url}/api/v1/calibrations",
        json={"method": "six_position", "readings": [{"up": k, "mean": v} for k, v in SIX.items()]},
    )
    assert cal.status_code == 201, cal.text
    for path in (
        "/",
        "/wizard?protocol=compass",
        "/static/js/wizard.js",
        f"/api/v1/calibrations/{cal.json()['id']}",
        f"/api/v1/calibrations/{cal.json()['id']}/export?format=json",
    ):
        plain = _raw_get(s.url + path, None)
        packed = _raw_get(s.url + path, "gzip")
        assert plain.status_code == packed.status_code == 200, path
        assert "content-encoding" not in plain.headers, path
        assert packed.headers["content-encoding"] == "gzip", path
        assert gzip.decompress(packed.wire) == plain.wire, path
        assert len(packed.wire) < 0.6 * len(plain.wire), (path, len(packed.wire), len(plain.wire))
        # the security headers survive the compression
        assert packed.headers.get("x-content-type-options") == plain.headers.get("x-content-type-options")


def test_an_answer_under_1_kib_comes_as_it_is_and_a_larger_one_whole(server):
    """GZipMiddleware's minimum size holds for the API's answers too: /healthz is sent plain, a calibration
    compressed in one piece with its length (neither streamed in chunks), each with the security headers."""
    s = server
    cal = httpx.post(
        f"{s.url}/api/v1/calibrations",
        json={"method": "six_position", "readings": [{"up": k, "mean": v} for k, v in SIX.items()]},
    )
    assert cal.status_code == 201, cal.text
    small = _raw_get(s.url + "/healthz", "gzip")
    assert small.status_code == 200 and "content-encoding" not in small.headers
    assert int(small.headers["content-length"]) == len(small.wire) < 1024
    large = _raw_get(f"{s.url}/api/v1/calibrations/{cal.json()['id']}", "gzip")
    assert large.headers["content-encoding"] == "gzip" and "transfer-encoding" not in large.headers
    assert int(large.headers["content-length"]) == len(large.wire)
    for r in (small, large):
        assert r.headers["x-frame-options"] == "DENY"
        assert r.headers["content-security-policy"].startswith("default-src 'self'")
