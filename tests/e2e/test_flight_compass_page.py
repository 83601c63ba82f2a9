"""A flight's compass on the page in real Chromium: a drone builder's log uploaded, *Calibrate the compass from
this flight*, then the verdict in degrees, the flight seen by its compass (expected against measured field, |B|
beside the current, the heading error before and after), the orientation found, and the firmware's file."""

from __future__ import annotations

from pathlib import Path

import pytest
from playwright.sync_api import expect

from tests.e2e.conftest import ARTIFACTS, shot
from tests.e2e.journey import Journey
from tests.flight_compass_logs import seeded_flight, write_flight_compass_logs
from tests.io.test_export_flight_compass import parse_ardupilot


def test_a_flights_compass_is_calibrated_from_the_page(axe_page, server, tmp_path):
    from tests.e2e.test_layout import looked_at

    page = axe_page
    # The drone builder's journey (issue 45): from the start page's drone door to the file for ArduPilot. No real
    # log of the corpus flew enough headings for an "apply" (each says why, tests/api/test_compass_flight.py):
    # this flight is seeded, written as ArduPilot writes its logs.
    log, _ = write_flight_compass_logs(tmp_path, seeded_flight(3, rate_hz=10.0))  # mounted yaw 90°, stored 0
    journey = Journey("drone log")
    page.goto(server.url + "/")
    with journey.looking():  # the start page's layout and axe at every width are test_layout.py's
        shot(page, "journey_drone_first_390")
    problems: list[str] = []
    with page.expect_file_chooser() as chooser:
        journey.click(page, "#drone-log", "A drone's flight log")
    chooser.value.set_files(str(log))
    journey.act("choose the log")
    journey.click(page, "#upload-form button[type=submit]", "Upload and calibrate")
    page.wait_for_selector("#flight:not([hidden])")
    expect(page.locator("#flight-compass")).to_be_visible()
    with journey.looking():
        shot(page, "flight_compass_start_390")
    journey.click(page, "#flight-compass", "Calibrate the compass from this flight")
    page.wait_for_selector("#downloads[data-ready=true]", timeout=60_000)
    words = page.text_content("#verdict-words")
    assert words.startswith("Apply it: heading error on flight segments left out"), words
    assert "°" in words
    expect(page.locator("#result-flight")).to_be_visible()
    loaded = page.evaluate(
        "() => new Promise((done) => { const img = document.querySelector('#result-flight img');"
        " if (img.complete) done(img.naturalWidth); else img.onload = () => done(img.naturalWidth); })"
    )
    assert loaded > 0
    caption = page.text_content("#result-flight figcaption")
    assert caption.startswith("Orientation: the compass sits as ") and "COMPASS_ORIENT 2" in caption, caption
    assert "Directions covered:" in caption and "of the log (ArduPilot" in caption, caption
    # the numbers are in ArduPilot's frames: its file, or the JSON
    assert list(page.eval_on_selector_all("#use-with option", "os => os.map(o => o.value)")) == [
        "ardupilot",
        "filter",
    ]
    links = page.eval_on_selector_all("#downloads a", "as => as.map(a => a.dataset.format)")
    assert "ardupilot" in links and "flight_svg" in links, links
    assert page.input_value("#use-with") == "ardupilot"
    with page.expect_download() as info:
        journey.click(page, "#use-file", "download the ArduPilot parameters")
    params = parse_ardupilot(Path(info.value.path()).read_text())  # as Mission Planner's Load from file reads it
    assert {"COMPASS_OFS_X", "COMPASS_OFS_Y", "COMPASS_OFS_Z"} <= params.keys() and params["COMPASS_ORIENT"] == 2
    journey.report("the ArduPilot parameter file")
    problems += looked_at(page, "journey_drone_last", (320, 390, 1280))  # one screenshot a width
    assert not problems, "\n".join(problems)
    assert [e for e in page.errors if "status of 422" not in e] == []


def test_a_px4_log_without_gps_asks_for_the_place_in_the_pages_words(page, server, tmp_path):
    _, log = write_flight_compass_logs(tmp_path, seeded_flight(3, rate_hz=10.0), gps=False)
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(log))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#flight:not([hidden])")
    expect(page.locator("#compass-place")).to_be_visible()  # for the flight's compass, the log having no GPS
    page.click("#flight-compass")
    expect(page.locator("#flight-compass-msg")).to_contain_text("the Latitude and the Longitude")
    said = page.text_content("#flight-compass-msg")
    assert "latitude_deg" not in said and "Compass calibration refused" in said, said
    shot(page, "flight_compass_no_gps")
    page.fill("#place-lat", "47.4")
    page.fill("#place-lon", "8.5")
    page.fill("#place-date", "2025-06-01")
    page.click("#flight-compass")
    page.wait_for_selector("#downloads[data-ready=true]", timeout=60_000)
    assert page.text_content("#verdict-words").startswith("Apply it: heading error on flight segments left out")
    assert list(page.eval_on_selector_all("#use-with option", "os => os.map(o => o.value)")) == ["px4", "filter"]
    assert page.get_attribute("#use-file", "data-format") == "px4" and "CAL_MAG_COMP_TYP" in page.text_content(
        "#use-how"
    )
    assert [e for e in page.errors if "status of 422" not in e] == []


def test_a_minimal_log_without_imu_runs_its_compass_from_the_flight_at_once(axe_page, server, tmp_path):
    """ArduPilot's minimal logging (attitude, compass, GPS, current; no IMU message): the page offers no IMU to
    choose, says the log holds none, and runs the compass from the flight, the first thing it supports."""
    from tests.e2e.test_layout import layout_problems

    page = axe_page
    log, _ = write_flight_compass_logs(tmp_path, seeded_flight(3, rate_hz=10.0), imu=False)
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(log))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#flight:not([hidden])")
    expect(page.locator("#flight-imu-label")).to_be_hidden()
    expect(page.locator("#compass-place")).to_be_hidden()  # the place and date come from the log's GPS
    expect(page.locator("#flight-temp")).to_have_text(
        "The log holds no IMU samples: its compass is read alone (log the IMU for the other calibrations)."
    )
    expect(page.locator("#verdict-words")).to_contain_text(
        "Apply it: heading error on flight segments left out", timeout=60_000
    )
    assert page.locator("#segments-msg.bad, #upload-msg.bad").count() == 0  # no failure nobody asked for
    # the part of the log fitted: every sample, from 10 s to 150 s
    page.select_option("#flight-window", "all")
    page.fill("#flight-from", "10")
    page.fill("#flight-to", "150")
    with page.expect_response(lambda r: r.url.endswith("/api/v1/calibrations") and r.request.method == "POST") as sent:
        page.click("#flight-compass")
    asked = sent.value.request.post_data_json
    assert (asked["window"], asked["from_s"], asked["to_s"]) == ("all", 10, 150), asked
    assert sent.value.status == 201 and sent.value.json()["metrics"]["n_samples"] == 1401
    problems = []
    for width in (320, 390, 1280):
        page.set_viewport_size({"width": width, "height": 900})
        shot(page, f"flight_compass_minimal_log_{width}")
        problems += layout_problems(page, "flight_compass_minimal_log", width)
    assert not problems, "\n".join(problems)
    assert [e for e in page.errors if "status of 422" not in e] == []


def test_a_three_compass_log_shows_which_compass_to_trust(axe_page, server):
    """The real ArduCopter 3.3 log of tests/data/real/flight: its compass from the flight runs at once (a GPS fix),
    and the result lists its three compasses side by side, MAG3 the one inconsistent with the first."""
    from tests.conftest import DATA
    from tests.e2e.test_layout import layout_problems

    page = axe_page
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(DATA / "real" / "flight" / "log171.bin"))
    page.click("#upload-form button[type=submit]")
    expect(page.locator("#result-compasses")).to_be_visible(timeout=60_000)
    rows = page.locator("#result-compasses-table tbody tr")
    expect(rows).to_have_count(3)
    assert rows.nth(0).locator("td").nth(0).text_content() == "0 (this result)"
    assert rows.nth(2).locator("td").nth(4).text_content() == "no: inconsistent"
    assert rows.nth(2).locator("td").nth(5).text_content().startswith("calibrate it or stop its use (COMPASS_USE3 = 0)")
    assert "Compass 2 against 0: 67° apart" in page.text_content("#result-compasses-checks")
    problems = []
    for width in (320, 390, 1280):
        page.set_viewport_size({"width": width, "height": 900})
        page.locator("#result-compasses").scroll_into_view_if_needed()
        shot(page, f"flight_compasses_{width}")
        page.locator("#result-compasses").screenshot(path=str(ARTIFACTS / f"flight_compasses_table_{width}.png"))
        problems += layout_problems(page, "flight_compasses", width)
    assert not problems, "\n".join(problems)
    assert [e for e in page.errors if "status of 422" not in e] == []


def test_a_log_whose_fix_has_no_gps_time_asks_the_day_and_takes_it(page, server):
    """A real ArduPlane 4.2.3 log (no IMU, a fix without a GPS week): the compass from the flight waits for the day
    (Where and when shows, nothing runs by itself), then runs with the day typed and the log's own place."""
    from tests.conftest import DATA

    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(DATA / "real" / "flight" / "arduplane_4.2_center_0003.bin"))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#flight:not([hidden])")
    line = page.locator("#supports-list li[data-method=compass_flight]")
    assert line.get_attribute("data-ready") == "false" and "the log has no GPS time" in line.text_content()
    expect(page.locator("#compass-place")).to_be_visible()
    assert page.locator("#verdict-words:not(:empty)").count() == 0  # nothing ran by itself
    page.fill("#place-date", "2025-01-03")
    with page.expect_response(lambda r: r.url.endswith("/api/v1/calibrations") and r.request.method == "POST") as sent:
        page.click("#flight-compass")
    asked = sent.value.request.post_data_json
    assert asked["date"] == "2025-01-03" and "latitude_deg" not in asked, asked
    assert sent.value.status == 201 and sent.value.json()["flight"]["place"]["latitude_deg"] == pytest.approx(
        51.6416, abs=1e-4
    )
    expect(page.locator("#verdict-words")).to_contain_text("Don't apply it", timeout=60_000)
    assert [e for e in page.errors if "status of 422" not in e] == []
