"""A calibration a person can keep and find again, in real Chromium against a real server: the upload
moves to the calibration's own page /c/{id} (the address changes, a reload keeps the result), the
history lists the calibrations (device, method, verdict, date) and filters by device, a device's latest
calibration is one link, and a wizard session's calibration opens with the token this browser kept.
Each page is measured at 390 and 1280 px (no sideways scrolling, axe, 44 px targets)."""

from __future__ import annotations

import re

import httpx
import numpy as np
import pytest
from playwright.sync_api import expect

from app.calibration import CANONICAL_SIX
from app.reach.tls import lan_addresses
from tests.conftest import DATA
from tests.e2e.axe import axe_context
from tests.e2e.conftest import shot
from tests.e2e.test_layout import layout_problems
from tests.phone_poses import pose_samples

CAL_PATH = re.compile(r"/c/(cal_[0-9a-f]{32})$")


def upload(page, url: str, device: str) -> str:
    """Upload the six-pose log of tests/data as `device`; the id of the calibration it made."""
    page.goto(url + "/")
    page.set_input_files("#log-file", str(DATA / "six_orientations_150hz.csv"))
    page.fill("#log-device", device)
    page.click("#options-summary")
    page.fill("#log-rate", "150")
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#downloads[data-ready=true]", state="attached")
    page.wait_for_function("/^\\/c\\/cal_/.test(location.pathname)")
    return CAL_PATH.search(page.url).group(1)


def session_calibration(url: str) -> tuple[str, str]:
    """A phone's six-pose session calibrated through the API: (calibration id, session token)."""
    with httpx.Client(base_url=url, timeout=60) as http:
        s = http.post("/api/v1/sessions", json={"protocol": "six"}).json()
        auth = {"Authorization": f"Bearer {s['token']}"}
        rng = np.random.default_rng(24)
        for label in CANONICAL_SIX:
            r = http.post(f"/api/v1/sessions/{s['id']}/captures", json=pose_samples(label, rng), headers=auth)
            assert r.status_code == 201, r.text
        r = http.post(f"/api/v1/sessions/{s['id']}/solve", headers=auth)
        assert r.status_code == 201, r.text
        return r.json()["id"], s["token"]


@pytest.mark.parametrize("width", [390, 1280])
def test_an_upload_moves_to_its_page_which_a_reload_keeps_and_the_history_finds(browser, server, width):
    context = axe_context(browser, viewport={"width": width, "height": 844}, device_scale_factor=1)
    try:
        page = context.new_page()
        errors: list[str] = []
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        cal_id = upload(page, server.url, f"bench-imu-{width}")
        words = page.text_content("#verdict-words")
        assert words and page.is_visible("#use")
        page.reload()  # the address keeps the result: the calibration's own page reads it back
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")
        assert page.text_content("#verdict-words") == words
        assert f"Device bench-imu-{width}" in page.text_content("#cal-meta") and cal_id in page.text_content(
            "#cal-meta"
        )
        assert page.get_attribute("#use-file", "download").endswith(".json") or page.is_visible("#use-file")
        assert page.locator("#downloads a").count() >= 4  # every format, fetched
        assert (
            page.is_visible("#result-norms") and page.locator("#norm-chart svg circle").count() == 12
        )  # as the wizard draws it
        page.click("#result-details summary")
        # One naming: the correction the person applies, M = X⁻¹ and o = y, then the model as fitted.
        page.wait_for_selector("#correction-acc-M td")
        body = httpx.get(f"{server.url}/api/v1/calibrations/{cal_id}", timeout=60).json()
        shown_m = np.array([float(v) for v in page.locator("#correction-acc-M td").all_text_contents()]).reshape(3, 3)
        np.testing.assert_allclose(shown_m, np.linalg.inv(body["model"]["X"]), atol=5e-7)
        shown_o = [float(v) for v in page.locator("#correction-acc-o td").all_text_contents()]
        np.testing.assert_allclose(shown_o, body["model"]["y"], atol=5e-7)
        assert "X = M⁻¹ and y = o" in page.text_content("#result-fitted-note")
        # Every figure named in words with its unit and a line on what it is; no stored key on the page.
        names = page.locator("#result-metrics th").all_text_contents()
        assert names and not [n for n in names if re.search(r"\b[a-z]+_[a-z_]+\b", n)], names
        assert page.locator("#result-metrics th .meaning").count() == len(names)
        assert page.text_content("#result-metrics tr[data-key=error_after_mg] td").endswith(" mg")
        assert "Readings to spare" in page.text_content("#result-metrics tr[data-key=dof] th")
        visible = page.text_content("#result")
        for key in ("fit_error_max", "cv_error_mg", "norm_error_max_raw", "six_position"):
            assert key not in visible, key
        problems = layout_problems(page, "calibration_page", width)

        # A second device, read again with the units shown (Read again with these units): the later reading
        # supersedes the earlier one of the same upload, method and device.
        other = upload(page, server.url, f"other-board-{width}")
        page.click("#units-go")
        page.wait_for_function(f"/^\\/c\\/cal_/.test(location.pathname) && !location.pathname.endsWith('{other}')")
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")
        again = CAL_PATH.search(page.url).group(1)
        # The history: one row per recording and method, newest first; the earlier reading one tap away.
        page.goto(server.url + "/history")
        page.wait_for_selector("#history-table:not([hidden])")
        ids = page.eval_on_selector_all("#history-table tbody tr", "(rows) => rows.map((r) => r.dataset.id)")
        assert ids.index(again) < ids.index(cal_id) and other not in ids
        toggle = page.locator(f"#history-table tr[data-id='{again}'] .earlier-toggle")
        assert toggle.text_content() == "1 earlier" and toggle.get_attribute("aria-expanded") == "false"
        toggle.click()
        page.wait_for_selector(f"#history-table tr.earlier[data-id='{other}'][data-earlier-than='{again}']")
        assert page.get_attribute(f"#history-table tr[data-id='{again}'] .earlier-toggle", "aria-expanded") == "true"
        problems += layout_problems(page, "history_earlier", width)
        shot(page, f"history_earlier_{width}")
        page.click(f"#history-table tr[data-id='{other}'] th a")  # the earlier reading still opens by id
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")
        assert page.url.endswith(f"/c/{other}")
        # ... and its page leads to the newer reading, whose page says it superseded one.
        assert "A newer reading of the same upload superseded this one" in page.text_content("#cal-readings")
        page.click("#cal-readings a")
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")
        assert page.url.endswith(f"/c/{again}")
        expect(page.locator("#cal-readings")).to_contain_text("superseded 1 earlier reading of the same upload")
        page.goto(server.url + "/history")
        page.wait_for_selector("#history-table:not([hidden])")
        row = page.locator(f"#history-table tr[data-id='{cal_id}']")
        cells = row.locator("td").all_text_contents()
        assert cells[0] == f"bench-imu-{width}" and "accelerometer" in cells[1] and cells[2] == words
        assert re.fullmatch(r"\d{4}-\d\d-\d\d \d\d:\d\d", row.locator("th a").text_content())
        page.select_option("#history-device", f"bench-imu-{width}")
        page.wait_for_function("document.querySelectorAll('#history-table tbody tr').length === 1")
        assert page.url.endswith(f"/history?device=bench-imu-{width}")
        problems += layout_problems(page, "history", width)
        page.click("#history-latest-link")
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")
        assert page.url.endswith(f"/c/latest?device=bench-imu-{width}") and cal_id in page.text_content("#cal-meta")
        page.go_back()  # the history as it was left: filtered by that device
        page.wait_for_selector("#history-table:not([hidden])")
        assert page.input_value("#history-device") == f"bench-imu-{width}"
        page.select_option("#history-device", "")
        page.click(f"#history-table tr[data-id='{again}'] th a")
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")
        assert page.url.endswith(f"/c/{again}")
        assert not problems, "\n".join(problems)
        assert errors == []
    finally:
        context.close()


def test_a_session_s_calibration_opens_with_the_token_this_browser_kept_and_nowhere_else(browser, server):
    cal_id, token = session_calibration(server.url)
    context = axe_context(browser, viewport={"width": 390, "height": 844}, device_scale_factor=1)
    try:
        page = context.new_page()
        page.goto(f"{server.url}/c/{cal_id}")  # a browser that does not keep the token: the API's 404
        page.wait_for_selector("#cal-access:not([hidden])")
        assert "opens only in the browser that made it" in page.text_content("#cal-access-why")
        assert page.is_hidden("#result")
        problems = layout_problems(page, "calibration_not_readable", 390)
        # The wizard keeps each calibration's session token (static/js/tokens.js): the same page opens it.
        page.evaluate(
            "([id, t]) => localStorage.setItem('trical.calibrations', JSON.stringify({[id]: t}))", [cal_id, token]
        )
        page.reload()
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")
        assert page.is_hidden("#cal-access") and "six positions" in page.text_content("#cal-meta")
        assert page.locator("#result-X td").count() == 9  # the model of the session, read with its token
        page.goto(server.url + "/history")
        page.wait_for_selector(f"#history-table tr[data-id='{cal_id}']")
        assert not problems, "\n".join(problems)
    finally:
        context.close()


def test_with_api_keys_the_page_asks_for_the_key_and_reads_with_it(browser, tmp_path):
    from tests.live_server import LiveServer

    key = "k-result-page-24"
    s = LiveServer({"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'keys.db'}", "TRICAL_API_KEYS": key}).start()
    context = axe_context(browser, viewport={"width": 390, "height": 844}, device_scale_factor=1)
    try:
        readings = [
            {"up": up, "mean": [9.80665 * v for v in vec]}
            for up, vec in zip(CANONICAL_SIX, ([-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1]))
        ]
        r = httpx.post(
            s.url + "/api/v1/calibrations",
            json={"method": "six_position", "readings": readings},
            headers={"Authorization": f"Bearer {key}"},
            timeout=60,
        )
        assert r.status_code == 201, r.text
        page = context.new_page()
        page.goto(f"{s.url}/c/{r.json()['id']}")
        page.wait_for_selector("#cal-access:not([hidden])")
        assert "needs an API key" in page.text_content("#cal-access-why")  # the server's words
        page.fill("#cal-key", "not-the-key")
        page.click("#cal-key-form button")
        page.wait_for_function("document.querySelector('#cal-access-why').textContent.includes('not valid')")
        page.fill("#cal-key", key)
        page.click("#cal-key-form button")
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")
        assert page.is_hidden("#cal-access")
        page.goto(s.url + "/history")
        page.wait_for_selector(f"#history-table tr[data-id='{r.json()['id']}']")  # the key, kept
    finally:
        context.close()
        s.stop()


def test_the_firmware_use_shows_the_lines_to_paste_which_gcc_builds_and_runs(browser, server, tmp_path):
    """The page's snippet under the C header, as a person copies it, compiled over the header the page
    downloads and run on its reading: the same numbers as the API's apply."""
    import shutil

    from tests.io.test_snippets import C_FLAGS, counts_log, example_reading
    from tests.processes import run_ok

    rec = httpx.post(
        server.url + "/api/v1/recordings",
        files={"file": ("board.csv", counts_log(8192, 7), "text/csv")},
        data={"chip": "mpu6050-4g"},
        timeout=60,
    ).json()
    cal = httpx.post(
        server.url + "/api/v1/calibrations",
        json={"method": "six_position", "recording_id": rec["id"], "device_id": "bench-board"},
        timeout=60,
    ).json()
    context = axe_context(browser, viewport={"width": 390, "height": 844}, device_scale_factor=1)
    try:
        page = context.new_page()
        page.goto(f"{server.url}/c/{cal['id']}")
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")
        page.select_option("#use-with", "firmware")
        page.wait_for_selector("#use-snippet-box:not([hidden])")
        snippet = page.text_content("#use-snippet code")
        assert "trical_acc_apply(m, f);" in snippet and "raw[0] / 8192.0f" in snippet and "±4 g" in snippet
        assert page.is_hidden("#use-snippet-note")  # the part was named: nothing to check
        with page.expect_download() as download:
            page.click("#use-file")
        header = tmp_path / download.value.suggested_filename
        download.value.save_as(header)
        # The lines go at file scope as pasted (their #include first), then a main of ours calls their function.
        assert f'#include "{header.name}"' in snippet.splitlines()[:2]
        raw = [int(v) for v in example_reading(snippet)]
        (tmp_path / "paste.c").write_text(
            "\n".join(
                [
                    "#include <stdio.h>",
                    snippet,
                    "int main(void) {",
                    f"    int16_t raw[3] = {{{', '.join(map(str, raw))}}};",
                    "    float f[3];",
                    "    trical_acc_calibrate(raw, f);",
                    '    printf("%.9g %.9g %.9g\\n", f[0], f[1], f[2]);',
                    "    return 0;",
                    "}",
                    "",
                ]
            )
        )
        run_ok(
            [
                shutil.which("gcc"),
                *C_FLAGS,
                "-I",
                str(tmp_path),
                "-o",
                str(tmp_path / "paste"),
                str(tmp_path / "paste.c"),
            ],
            timeout_s=60,
        )
        f = [float(v) for v in run_ok([str(tmp_path / "paste")], timeout_s=10).stdout.split()]
        want = httpx.post(
            f"{server.url}/api/v1/calibrations/{cal['id']}/apply",
            json={"samples": [[v / 8192 for v in raw]]},
            timeout=60,
        ).json()["samples"][0]
        np.testing.assert_allclose(f, want, atol=2e-6)
        page.select_option("#use-with", "python")
        page.wait_for_function("document.querySelector('#use-snippet code').textContent.includes('np.array')")
        problems = layout_problems(page, "calibration_snippet", 390)
        page.set_viewport_size({"width": 1280, "height": 900})
        problems += layout_problems(page, "calibration_snippet", 1280)
        assert not problems, "\n".join(problems)
    finally:
        context.close()


def compass_log(tmp_path):
    """A phyphox magnetometer log of a slow turn (tests/e2e/test_wizard_compass.py's spiral), in µT."""
    from tests.e2e.test_wizard_compass import turn

    readings, _ = turn(24, 48.0, n=400)
    t = np.arange(len(readings)) / 10.0
    path = tmp_path / "Raw Data.csv"
    header = '"Time (s)","Magnetic field x (µT)","Magnetic field y (µT)","Magnetic field z (µT)"'
    path.write_text(
        header + "\n" + "\n".join(",".join(f"{v:.6f}" for v in row) for row in np.column_stack([t, readings])) + "\n",
        encoding="utf-8",
    )
    return path


def test_the_compass_upload_takes_its_place_and_date_and_they_reach_the_model_s_field(browser, server, tmp_path):
    """Use my location (the Geolocation API, here Chromium's override of Helsinki) and a date fill the
    request's latitude_deg, longitude_deg and date; the calibrated strength is IGRF's there and then. A
    strength typed instead is the field the model takes; half a place is named, not sent."""
    from app.geomag import reference_field

    context = axe_context(
        browser,
        viewport={"width": 390, "height": 844},
        device_scale_factor=1,
        geolocation={"latitude": 60.1699, "longitude": 24.9384},
        permissions=["geolocation"],
    )
    try:
        page = context.new_page()
        sent = []
        page.on(
            "request",
            lambda r: (
                sent.append(r.post_data_json) if r.url.endswith("/api/v1/calibrations") and r.method == "POST" else None
            ),
        )
        page.goto(server.url + "/")
        page.set_input_files("#log-file", str(compass_log(tmp_path)))
        page.click("#upload-form button[type=submit]")
        page.wait_for_selector("#compass-place:not([hidden])")
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")  # the estimated field, at once
        notes = page.text_content("#result-warnings")
        assert (
            "give the Date of the turn, the Latitude and the Longitude (or the field's strength (µT))" in notes
            and "_deg" not in notes
        ), notes
        page.click("#place-here")
        page.wait_for_function("document.querySelector('#place-lat').value !== ''")
        assert (page.input_value("#place-lat"), page.input_value("#place-lon")) == ("60.1699", "24.9384")
        page.fill("#place-date", "2025-06-01")
        problems = layout_problems(page, "compass_place", 390)
        page.set_viewport_size({"width": 1280, "height": 900})
        problems += layout_problems(page, "compass_place", 1280)
        assert not problems, "\n".join(problems)
        page.click("#compass-recording")
        page.wait_for_function(
            "document.querySelector('#result-metrics tr[data-key=field_source] td')"
            " && document.querySelector('#result-metrics tr[data-key=field_source] td').textContent === 'model'"
        )
        body = sent[-1]
        assert (body["latitude_deg"], body["longitude_deg"], body["date"]) == (60.1699, 24.9384, "2025-06-01")
        cal_id = CAL_PATH.search(page.url).group(1)
        stored = httpx.get(f"{server.url}/api/v1/calibrations/{cal_id}", timeout=60).json()
        want = reference_field("2025-06-01", 60.1699, 24.9384).field_ut
        assert stored["metrics"]["field_ut"] == pytest.approx(want, rel=1e-9)
        assert stored["metrics"]["field_date"] == "2025-06-01"

        # A strength instead of a place: the field the model takes, as given.
        page.fill("#place-lat", "")
        page.fill("#place-lon", "")
        page.fill("#place-field", "51.25")
        page.click("#compass-recording")
        page.wait_for_function(
            "document.querySelector('#result-metrics tr[data-key=field_source] td').textContent === 'given'"
        )
        assert "latitude_deg" not in sent[-1] and sent[-1]["field_ut"] == 51.25
        cal_id = CAL_PATH.search(page.url).group(1)
        assert (
            httpx.get(f"{server.url}/api/v1/calibrations/{cal_id}", timeout=60).json()["metrics"]["field_ut"] == 51.25
        )
        # Half a place is named and nothing is sent.
        n = len(sent)
        page.fill("#place-field", "")
        page.fill("#place-lat", "45")
        page.click("#compass-recording")
        page.wait_for_selector("#place-msg.bad")
        assert "both the latitude and the longitude" in page.text_content("#place-msg") and len(sent) == n
    finally:
        context.close()


def decode_qr(png: bytes) -> str:
    """The text of the one QR code in a screenshot (zxing-cpp)."""
    import io

    import zxingcpp
    from PIL import Image

    found = zxingcpp.read_barcodes(Image.open(io.BytesIO(png)).convert("L"))
    assert len(found) == 1, f"{len(found)} codes found"
    return found[0].text


@pytest.mark.parametrize("width", [390, 1280])
def test_send_to_my_computer_without_web_share_shows_a_qr_of_a_short_link_the_computer_opens(browser, server, width):
    """The phone (no Web Share API) shows a QR code and a short link; the QR decodes to the link, which a
    second browser (the computer, keeping nothing) opens into the calibration's page with its files."""
    cal_id, token = session_calibration(server.url)
    phone = axe_context(
        browser, viewport={"width": width, "height": 844}, device_scale_factor=1, timezone_id="Europe/Berlin"
    )
    computer = axe_context(browser, viewport={"width": 1280, "height": 900}, device_scale_factor=1)
    try:
        page = phone.new_page()
        page.add_init_script("delete Navigator.prototype.share; delete Navigator.prototype.canShare;")
        page.goto(server.url + "/")
        page.evaluate(
            "([id, t]) => localStorage.setItem('trical.calibrations', JSON.stringify({[id]: t}))", [cal_id, token]
        )
        page.goto(f"{server.url}/c/{cal_id}")
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")
        page.click("#send-btn")
        page.wait_for_selector("#send-box:not([hidden])")
        page.wait_for_function(
            "document.querySelector('#send-qr').complete && document.querySelector('#send-qr').naturalWidth > 0"
        )
        url = page.text_content("#send-url")
        # A server on loopback: the link is at this machine's LAN address, which the computer can open.
        lan_url = f"http://{lan_addresses()[0]}:{server.port}"
        assert re.fullmatch(re.escape(lan_url) + r"/s/[2-9A-HJKMNP-Z]{10}", url), url
        assert decode_qr(page.locator("#send-qr").screenshot()) == url  # the QR read back is the link
        expires = page.text_content("#send-expires")  # a date, a time and the phone's zone (Berlin: CET)
        assert re.fullmatch(
            r"\(it opens this calibration until \d{1,2} [A-Z][a-z]+ 20\d\d, \d\d:\d\d CET\)\.", expires
        ), expires
        problems = layout_problems(page, "send_fallback", width)
        assert not problems, "\n".join(problems)

        other = computer.new_page()
        other.goto(url.replace(lan_url, server.url))  # the test's server listens on loopback only
        other.wait_for_selector("#downloads[data-ready=true]", state="attached")
        assert other.url == f"{server.url}/c/{cal_id}"  # the calibration's own address, the link's token kept for it
        assert other.locator("#downloads a").count() >= 4 and cal_id in other.text_content("#cal-meta")
        other.reload()
        other.wait_for_selector("#downloads[data-ready=true]", state="attached")
        other.goto(server.url + "/history")  # the computer's history lists it while the link holds
        other.wait_for_selector(f"#history-table tr[data-id='{cal_id}']")
    finally:
        phone.close()
        computer.close()


def test_send_to_my_computer_hands_the_link_to_the_web_share_api(browser, server):
    cal_id, token = session_calibration(server.url)
    context = axe_context(browser, viewport={"width": 390, "height": 844}, device_scale_factor=1)
    try:
        page = context.new_page()
        # A phone's share sheet, as the page calls it (navigator.share resolves once the person picked a target).
        page.add_init_script(
            "navigator.share = async (data) => { window.__shared = data; };navigator.canShare = () => true;"
        )
        page.goto(server.url + "/")
        page.evaluate(
            "([id, t]) => localStorage.setItem('trical.calibrations', JSON.stringify({[id]: t}))", [cal_id, token]
        )
        page.goto(f"{server.url}/c/{cal_id}")
        page.wait_for_selector("#downloads[data-ready=true]", state="attached")
        page.click("#send-btn")
        page.wait_for_function("window.__shared !== undefined")
        shared = page.evaluate("window.__shared")
        assert re.fullmatch(
            rf"http://{re.escape(lan_addresses()[0])}:{server.port}/s/[2-9A-HJKMNP-Z]{{10}}", shared["url"]
        )
        assert shared["text"] == page.text_content("#verdict-words")
        assert page.is_hidden("#send-box") and "Sent: the link opens it until" in page.text_content("#send-msg")
    finally:
        context.close()


def test_the_firmware_file_is_offered_with_the_figure_it_reaches_and_only_where_it_beats_raw(page, server):
    """The MPU-6050's six pose files (tests/data/real/README.md): ArduPilot's file, with what its offsets and
    scales reach beside raw and trical's; a sensor whose only error is its axes' angles: no ArduPilot file."""
    from app.calibration.still.firmware_model import DIRECTIONS
    from tests.api.test_pose_files import ORDER, pose_bytes

    rec = httpx.post(
        server.url + "/api/v1/recordings",
        data={"acc_unit": "m/s^2"},
        timeout=60,
        files=[("file", (f"{s}.csv", pose_bytes(s), "text/csv")) for s in ORDER],
    ).json()
    boards = httpx.post(
        server.url + "/api/v1/calibrations", json={"method": "auto", "recording_id": rec["id"]}, timeout=60
    ).json()
    e = np.sin(np.radians(1.0))  # every pair of axes 2° from orthogonal, nothing else
    sheared = 9.80665 * DIRECTIONS @ np.linalg.inv([[1, e, e], [e, 1, e], [e, e, 1.0]]).T
    shear = httpx.post(
        server.url + "/api/v1/calibrations", json={"method": "nonorthogonal", "means": sheared.tolist()}, timeout=60
    ).json()
    assert boards["verdict"]["apply"] and shear["verdict"]["apply"]
    page.goto(f"{server.url}/c/{boards['id']}")
    page.wait_for_selector("#downloads[data-ready=true]", state="attached")
    page.select_option("#use-with", "ardupilot")
    assert page.is_visible("#use-file") and page.get_attribute("#use-file", "data-format") == "ardupilot"
    assert page.text_content("#use-firmware") == (
        "With these offsets and scales ArduPilot reaches at most 0.00 mg on the 6 still readings (6 numbers fit 6 "
        "readings exactly) and 3.68 mg in any direction; raw 65.1 mg, trical's full model 0.96 mg. trical's model "
        "also turns the axes 2.8° (the table's tilt or the board's mounting), which no offset or scale holds: "
        "ArduPilot's level calibration takes the tilt (AHRS_TRIM_X and AHRS_TRIM_Y)."
    )
    shot(page, "use_ardupilot_pose_files")
    page.goto(f"{server.url}/c/{shear['id']}")
    page.wait_for_selector("#downloads[data-ready=true]", state="attached")
    page.select_option("#use-with", "px4")
    assert page.is_hidden("#use-file") and page.is_hidden("#use-firmware")
    assert page.text_content("#use-problem") == (
        "PX4: PX4's offsets and scales would leave 34.7 mg on the 14 still readings, no better than raw (33.7 mg): "
        "use the full correction (M and o) instead. Pick another use, or a format below."
    )
    assert page.locator("#downloads a[data-format=px4]").count() == 1  # still listed among every format
    shot(page, "use_px4_not_offered")
    assert page.errors == []


def test_the_history_names_each_compass_of_a_flight_log(page, server):
    """The real log171.bin's compass 0 and compass 1 calibrated from the flight: two rows of the drone's history,
    each naming its compass and whether the firmware takes it for external."""
    log = DATA / "real" / "flight" / "log171.bin"
    with httpx.Client(base_url=server.url, timeout=120) as http:
        rec = http.post("/api/v1/recordings", files={"file": (log.name, log.read_bytes())}).json()
        for instance in (0, 1):
            r = http.post(
                "/api/v1/calibrations",
                json={
                    "method": "compass_flight",
                    "recording_id": rec["id"],
                    "mag_instance": instance,
                    "device_id": "log171-quad",
                },
            )
            assert r.status_code == 201, r.text
    page.goto(server.url + "/history?device=log171-quad")
    page.wait_for_selector("#history-table:not([hidden])")
    methods = page.eval_on_selector_all(
        "#history-table tbody td[data-label='Method']", "(c) => c.map((x) => x.textContent)"
    )
    assert [m.split(", ", 1)[1] for m in methods] == ["compass 1 (internal)", "compass 0 (external)"], methods
