"""A flight controller's log on the start page in real Chromium: its sensor instances, the IMU and compass read
chosen and read again, the temperature over the log, and the temperature calibration where its range allows."""

from __future__ import annotations

import re

import numpy as np
from playwright.sync_api import expect

from tests.e2e.conftest import shot
from tests.flight_logs import px4_file, still_board


def warming_px4_log(path, *, rise_c: float = 20.0):
    """Two IMU instances resting flat while the board warms from 25 °C by ``rise_c`` (a cold start)."""
    imus = still_board(3, rate_hz=200.0, duration_s=30.0)
    for k, imu in enumerate(imus):
        n = len(imu["time_us"])
        imu["temperature"] = 25.0 + k + rise_c * (1 - np.exp(-5 * np.arange(n) / n))
    return px4_file(path, imus)


def test_a_flight_log_shows_its_sensors_and_reads_the_imu_chosen(page, server, tmp_path):
    log = warming_px4_log(tmp_path / "warm_up.ulg")
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(log))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#flight:not([hidden])")
    # Every instance of the log, a row each, with its source, rate and temperature range.
    rows = page.eval_on_selector_all(
        "#flight-table tbody tr", "rs => rs.map(r => [...r.cells].map(c => c.textContent))"
    )
    assert [(r[0], r[1], r[2]) for r in rows] == [
        ("accelerometer", "0", "sensor_accel"),
        ("accelerometer", "1", "sensor_accel"),
        ("gyroscope", "0", "sensor_gyro"),
        ("gyroscope", "1", "sensor_gyro"),
    ], rows
    assert all(r[4] == "200" for r in rows), rows
    assert rows[0][5] == "25.0–44.9" and rows[1][5] == "26.0–45.9", rows
    # The units menus of text logs are not offered: the format states its units.
    assert page.is_hidden("#units") and page.is_hidden("#flight-mag-label")
    caption = page.text_content("#flight-temp")
    assert (
        caption.startswith("The IMU read went from 25.0 to 44.9 °C")
        and "enough for a temperature calibration" in caption
    )
    assert (
        page.get_attribute("#flight-temp-plot svg", "aria-label")
        == "The sensor's temperature over the log, 25.2 to 44.9 °C"
    )  # the bins' means
    assert page.is_visible("#temperature-recording")
    assert page.is_hidden("#options")  # the format states its rate, units and columns
    shot(page, "flight_log_sensors")
    # The second IMU, read again: the upload sends its instance, and the recording reads it.
    page.select_option("#flight-imu", "1")
    with page.expect_response(lambda r: r.url.endswith("/api/v1/recordings")) as answer:
        page.click("#flight-go")
    rec = answer.value.json()
    assert rec["read_with"]["instance"] == 1 and rec["flight"]["imu"]["instance"] == 1, rec["read_with"]
    expect(page.locator("#flight-temp")).to_contain_text("went from 26.0 to 45.9 °C")
    assert page.input_value("#flight-imu") == "1"
    # a still board has no poses: only what it supports runs, and nothing fails
    assert page.locator("#segments-msg.bad").count() == 0
    assert [e for e in page.errors if "status of 422" not in e] == []


def test_a_log_too_short_a_warm_up_says_what_the_temperature_calibration_needs(page, server, tmp_path):
    log = warming_px4_log(tmp_path / "short.ulg", rise_c=4.0)
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(log))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#flight:not([hidden])")
    caption = page.text_content("#flight-temp")
    assert "a temperature calibration needs 10 °C or more" in caption and "cold start" in caption, caption
    line = page.locator("#supports-list li[data-method=temperature]")
    assert line.get_attribute("data-ready") == "false" and "spans 4.0 °C" in line.text_content()
    # The still 30 s are ready for the noise: that runs, and the temperature calibration, not ready, is not tried.
    assert page.get_attribute("#supports-list li[data-method=noise]", "data-ready") == "true"
    page.wait_for_selector("#verdict-words:not(:empty)", timeout=60_000)
    assert "Running " in page.text_content("#supports-holds")
    assert page.locator("#segments-msg.bad, #upload-msg.bad").count() == 0  # no failure nobody asked for
    assert [e for e in page.errors if "status of 422" not in e] == []


def test_a_warm_up_is_calibrated_for_temperature_from_the_page(axe_page, server, tmp_path):
    """A PX4 log whose IMU 1 warms from 15 °C (the seeded warm-up of the temperature tests, a known cubic and a
    real MPU-6050's noise): IMU 1 chosen, *Calibrate the temperature drift*, then the verdict, the plot of offset
    against temperature, and the firmware's file under *Use this calibration*."""
    from tests.api.test_flight_log_temperature import warm_instances
    from tests.e2e.test_layout import layout_problems

    page = axe_page
    log = px4_file(tmp_path / "warm_up.ulg", warm_instances(44))
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(log))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#flight:not([hidden])")
    if page.input_value("#flight-imu") != "1":  # the default IMU rests at 40 °C: nothing to calibrate on it
        assert page.get_attribute("#supports-list li[data-method=temperature]", "data-ready") == "false"
        page.select_option("#flight-imu", "1")
        page.click("#flight-go")
    expect(page.locator("#temperature-recording")).to_be_visible()
    page.click("#temperature-recording")
    # The still IMU's noise may have run first (it is ready on its own): wait for the temperature's answer itself.
    expect(page.locator("#verdict-words")).to_have_text(re.compile(r"^Apply it: offset drift over 15"), timeout=60_000)
    page.wait_for_selector("#downloads[data-ready=true]", timeout=60_000)
    assert page.url.endswith("/c/" + page.text_content("#result-ok").split(" ")[1])
    expect(page.locator("#result-temperature")).to_be_visible()
    loaded = page.evaluate(
        "() => new Promise((done) => { const img = document.querySelector('#result-temperature img');"
        " if (img.complete) done(img.naturalWidth); else img.onload = () => done(img.naturalWidth); })"
    )
    assert loaded > 0
    assert list(page.eval_on_selector_all("#use-with option", "os => os.map(o => o.value)")) == [
        "px4",
        "ardupilot",
        "filter",
    ]
    assert page.get_attribute("#use-file", "data-format") == "px4" and "TC_A0_ID" in page.text_content("#use-how")
    links = page.eval_on_selector_all("#downloads a", "as => as.map(a => a.dataset.format)")
    assert links == ["px4", "ardupilot", "json", "temperature_svg"], links
    shot(page, "flight_log_temperature_result")
    problems = []
    for width in (390, 1280):
        page.set_viewport_size({"width": width, "height": 900})
        problems += layout_problems(page, "flight_log_temperature_result", width)
    assert not problems, "\n".join(problems)
    assert [e for e in page.errors if "status of 422" not in e] == []


CUT_HEADERS = """() => {
  const cut = (c) => c.scrollWidth > c.clientWidth + 1;  // its words wider than the cell shows
  const box = document.querySelector("#flight .scroll");
  const table = document.querySelector("#flight-table");
  return {
    cells: [...table.querySelectorAll("th, td")].filter(cut).map((c) => c.textContent),
    widths: [...table.querySelectorAll("thead th")].map((c) => [c.textContent, c.clientWidth, c.scrollWidth]),
    scroller: [box.scrollWidth, box.clientWidth], table: [table.scrollWidth, table.clientWidth],
    page: [document.documentElement.scrollWidth, document.documentElement.clientWidth],
  };
}"""


def test_a_real_flight_log_s_table_of_sensors_is_never_cut_from_320_to_1280_px(page, server, tmp_path):
    """pyulog's real sample log (tests/data/flight_logs): at 320, 390 and 1280 px no header or cell of the table of
    sensors is cut ("Temperature (°C)" once read "Te"); a table wider than a phone scrolls in its own box, never
    the page. The same walk checks the wording of the page's counts and spans, and a browser's 404 page."""
    from tests.conftest import DATA

    page.set_viewport_size({"width": 1280, "height": 900})
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(DATA / "flight_logs" / "sample_log_small.ulg"))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#flight:not([hidden])")
    heads = page.eval_on_selector_all("#flight-table thead th", "hs => hs.map(h => h.textContent)")
    assert "Temperature (°C)" in heads and "Device" in heads
    for width in (1280, 1024, 768, 640, 390, 320):
        page.set_viewport_size({"width": width, "height": 900})
        page.evaluate("() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")
        found = page.evaluate(CUT_HEADERS)
        assert found["cells"] == [], (width, found)
        assert found["page"][0] <= found["page"][1], (width, found)  # the page itself never scrolls sideways
        assert found["scroller"][0] <= found["scroller"][1] + 1, (width, found)  # the whole table in view, unscrolled
        if width in (1280, 390, 320):
            shot(page, f"flight_log_table_{width}")
    # A small span of temperature with the digits that show it (44.44 → 44.46 °C is 0.02 °C, not "0.0 °C").
    assert page.evaluate("""() => import("/static/js/flight_log.js").then((m) =>
        [0.02, 0.1, 0.05, 0.004, 3.2, 0].map(m.spanDecimals))""") == [2, 1, 2, 3, 1, 1]
    assert page.evaluate("""() => import("/static/js/dom.js").then((m) =>
        [m.counted(1, "still reading"), m.counted(6, "still reading")])""") == ["1 still reading", "6 still readings"]
    # An ArduPilot log's six poses: the verdict tells its figure as a level's tilt, and the use offered first is
    # that firmware's parameters (app/web/uses.py DEFAULT_USES), not a phone app.
    from tests.flight_logs import ardupilot_file, imu_instances

    page.set_viewport_size({"width": 1280, "height": 900})
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(ardupilot_file(tmp_path / "six.bin", imu_instances(3))))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#downloads[data-ready=true]")
    assert re.search(r"\(a level off by [\d.]+° → [\d.<]+°\)\.$", page.text_content("#verdict-words"))
    assert (
        page.input_value("#use-with") == "ardupilot" and page.get_attribute("#use-file", "data-format") == "ardupilot"
    )
    shot(page, "flight_log_six_verdict_ardupilot_1280")
    # An address that names nothing: a page, with the way back.
    answer = page.goto(server.url + "/nope")
    assert answer.status == 404 and page.text_content("h1") == "No page at this address"
    shot(page, "not_found_1280")
    page.click("#not-found-history")
    page.wait_for_url(server.url + "/history")
