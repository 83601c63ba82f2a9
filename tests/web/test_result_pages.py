"""A stored calibration's page /c/{id}, a device's latest /c/latest?device=…, and the history /history."""

from __future__ import annotations


def test_a_calibration_page_renders_the_result_view_and_its_script(client):
    r = client.get("/c/cal_" + "0123456789abcdef" * 2)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    for needle in (
        'data-id="cal_0123456789abcdef0123456789abcdef"',
        'id="result"',
        'id="verdict"',
        'id="use"',
        'id="result-details"',
        'src="/static/js/calibration_page.js"',
        'href="/history"',
        'id="trical-tables"',
    ):
        assert needle in r.text, needle
    for path in (
        "/static/js/calibration_page.js",
        "/static/js/result_view.js",
        "/static/js/tokens.js",
        "/static/js/history.js",
    ):
        assert client.get(path).status_code == 200, path


def test_a_device_s_latest_calibration_is_one_address(client):
    r = client.get("/c/latest", params={"device": "drone imu"})
    assert r.status_code == 200
    assert 'data-device="drone imu"' in r.text and "The latest calibration of drone imu" in r.text


def test_an_address_that_names_no_calibration_is_a_404_saying_what_an_id_is(client):
    r = client.get("/c/not-an-id")
    assert r.status_code == 404 and "cal_ and 32 hexadecimal digits" in r.text
    assert "calibration_page.js" not in r.text
    r = client.get("/c/latest")
    assert r.status_code == 404 and "/c/latest?device=NAME" in r.text


def test_the_history_page_renders_its_filter_and_script(client):
    r = client.get("/history", params={"device": "bench-board"})
    assert r.status_code == 200
    for needle in (
        'id="history-device"',
        'data-device="bench-board"',
        'src="/static/js/history.js"',
        'id="history-table"',
    ):
        assert needle in r.text, needle
