"""The start page renders and links its module scripts."""


def test_start_page(client):
    r = client.get("/")
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    html = r.text
    for needle in (
        'id="upload-form"',
        'id="readings-form"',
        'type="module" src="/static/js/index.js"',
        'aria-live="polite"',
        "C header",
    ):
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
    pre = client.options(
        "/api/v1/calibrations", headers={"Origin": "https://evil.example", "Access-Control-Request-Method": "POST"}
    )
    assert "access-control-allow-origin" not in pre.headers


def test_start_page_shows_the_phone_address_as_a_qr_code(tmp_path):
    from html import escape

    from fastapi.testclient import TestClient

    from app.main import create_app
    from app.reach.qr import qr_svg_data_uri
    from tests.conftest import make_settings

    url = "https://192.168.1.23:8443/wizard?protocol=six"
    with TestClient(create_app(make_settings(tmp_path, public_url=url))) as c:
        html = c.get("/").text
    assert f'<img id="phone-qr" src="{escape(qr_svg_data_uri(url))}" alt="QR code of {escape(url)}">' in html
    assert f'<a id="phone-url" href="{escape(url)}">{escape(url)}</a>' in html
    assert 'id="phone-https"' not in html  # an https address needs no word on HTTPS


def test_start_page_without_a_public_address_shows_the_address_it_was_opened_at(client):
    # The test client's host is "testserver": that address, as the QR code too; no operator commands, but
    # what a phone needs at an http:// address: HTTPS, without which its browser gives no motion data.
    html = client.get("/").text
    assert 'id="phone-qr"' in html and 'alt="QR code of http://testserver/"' in html
    assert "trical serve --https" not in html
    assert "gives a page its motion\n    sensors only over HTTPS" in html


def test_start_page_links_the_wizard(client):
    html = client.get("/").text
    assert '<a class="cta" href="/wizard?protocol=six">Start: six positions on a table' in html


def test_wizard_page(client):
    r = client.get("/wizard")
    assert r.status_code == 200
    html = r.text
    for needle in (
        'data-protocol="six"',
        'data-capture-s="5.0"',
        'type="module" src="/static/js/wizard.js"',
        'id="start-btn"',
        "flat, steady table",
        "about 2 minutes",
        '"C header"',
        'aria-label="Redo +z (flat, screen up)"',
        'aria-label="Capture progress"',
    ):
        assert needle in html, needle
    for label in ("-x", "+x", "-y", "+y", "-z", "+z"):
        assert f'data-pose="{label}"' in html
    assert 'data-capture-s="1.5"' in client.get("/wizard?protocol=six&capture_s=1.5").text
    for path in ("/static/js/wizard.js", "/static/js/motion.js", "/static/js/poses.js", "/static/js/result.js"):
        assert client.get(path).status_code == 200, path


def test_wizard_refuses_an_unknown_protocol_or_capture_time_with_links(client):
    r = client.get("/wizard?protocol=cube12")
    assert r.status_code == 400
    assert "The protocol “cube12” is unknown" in r.text
    assert 'href="/wizard?protocol=six&amp;source=phone"' in r.text and 'href="/"' in r.text
    assert 'href="/wizard?protocol=cube24&amp;source=board"' in r.text
    assert "wizard.js" not in r.text
    # The source: phone (the default) or board; another is refused naming both, as a flow the source
    # cannot do (a phone's noise: the noise page records a board).
    r = client.get("/wizard?protocol=six&source=tablet")
    assert r.status_code == 400 and "The source “tablet” is unknown: source is phone or board" in r.text
    r = client.get("/wizard?protocol=noise&source=phone")
    assert r.status_code == 400 and "A phone cannot do “the noise: a still recording of a chosen length”" in r.text
    assert client.get("/wizard?protocol=noise").status_code == 200  # a board's, with no source named
    for bad in ("0.1", "31", "nan", "five"):
        r = client.get(f"/wizard?capture_s={bad}")
        assert r.status_code == 400 and f"capture_s={bad} is not a number of seconds between 0.5 and 30" in r.text


def test_the_compass_page_checks_a_calibration_named_by_its_id_and_refuses_anything_else(client):
    cal = "cal_" + "0" * 32
    r = client.get(f"/wizard?protocol=compass&check={cal}")
    assert r.status_code == 200 and f'data-check="{cal}"' in r.text
    assert "<h1>Check this phone&#39;s compass</h1>" in r.text
    assert "compass-where" not in r.text  # the check takes the calibration's own field
    board = client.get(f"/wizard?protocol=compass&source=board&check={cal}")
    assert board.status_code == 200 and "<h1>Check this board&#39;s compass</h1>" in board.text
    assert 'checks <a href="/c/' + cal + "\">the board's calibration</a>" in board.text
    for query in ("protocol=compass&check=cal_nope", f"protocol=six&check={cal}"):
        r = client.get(f"/wizard?{query}")
        assert r.status_code == 400 and "is not a compass calibration&#39;s id to check" in r.text, query


def test_cube24_wizard_page(client):
    r = client.get("/wizard?protocol=cube24&capture_s=2")
    assert r.status_code == 200
    html = " ".join(r.text.split())
    for needle in (
        'data-protocol="cube24"',
        'data-capture-s="2.0"',
        'type="module" src="/static/js/wizard.js"',
        "in a fixed order",
        "a jig",
        "about 4 minutes",
        'id="turn-alert" class="problem" role="alert"',
        'id="redo-last"',
        "Position 1 of 24",
        'aria-label="Positions captured"',
    ):
        assert needle in html, needle
    assert "coming" not in html and 'id="poses"' not in html  # no upload-instead notice, no six-pose list
    assert "can still be uploaded through the API" in html and "POST /api/v1/recordings" in html
    assert client.get("/static/js/cube.js").status_code == 200
