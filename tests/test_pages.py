"""The start page renders and links its module scripts."""

from tests.api.conftest import client, settings  # noqa: F401  (fixtures)


def test_start_page(client):
    r = client.get("/")
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    html = r.text
    for needle in ('id="upload-form"', 'id="readings-form"', 'type="module" src="/static/js/index.js"',
                   'aria-live="polite"', "C header"):
        assert needle in html
    for label in ("-x", "+x", "-y", "+y", "-z", "+z"):
        assert f'data-up="{label}"' in html
    for path in ("/static/js/index.js", "/static/js/api.js", "/static/js/readings.js", "/static/css/trical.css"):
        assert client.get(path).status_code == 200, path


def test_security_headers_and_no_cors(client):
    r = client.get("/", headers={"Origin": "https://evil.example"})
    assert r.headers["x-content-type-options"] == "nosniff"
    assert r.headers["x-frame-options"] == "DENY"
    assert "script-src 'self'" in r.headers["content-security-policy"]
    assert "access-control-allow-origin" not in r.headers
    pre = client.options("/api/v1/calibrations", headers={"Origin": "https://evil.example",
                                                           "Access-Control-Request-Method": "POST"})
    assert "access-control-allow-origin" not in pre.headers
