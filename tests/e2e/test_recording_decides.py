"""The recording decides the journey, through the page in Chromium (issue 42): real recordings of the corpus and
the flight logs, uploaded on the start page as a person would, each say what they hold and support, run the first
calibration ready (the one the person asked for) and show no failure of one nobody asked for."""

from __future__ import annotations

import pytest

from tests.conftest import DATA

REAL = DATA / "real"
CORPUS = REAL / "corpus"

CASES = {
    # name: (files, the upload's sampling rate or None, the calibration run first or None, what the page shows)
    "a phone resting on a table": ([CORPUS / "hyperimu_lsm6ds3_phone_still" / "imu.csv"], None, "noise", "#result"),
    "a compass turned in the hand": (
        [CORPUS / "qmc5883l_turn_headerless" / "qmc5883l_turn.csv"],
        None,
        "magnetometer",
        "#result",
    ),
    "an ArduCopter flight with GPS": ([REAL / "flight" / "log171.bin"], None, "compass_flight", "#result"),
    # A 10 s log on a bench: its compass asks for the place (no GPS), and its 6 s rest is the noise's, run first.
    "a PX4 log without GPS": ([REAL / "flight" / "sample_appended_multiple.ulg"], None, "noise", "#compass-place"),
    "an accelerometer turned without rests": (
        [CORPUS / "mpu6050_session1_turns_headerless" / "example_data_calibration_rows3001_8000.csv"],
        "100",
        None,
        "#supports",
    ),
    "an iPhone's three files, one per sensor, lying still for 10 s": (
        [
            CORPUS / "iphone_heading_per_sensor_files" / f
            for f in ("accelerometer.csv", "gyroscope.csv", "magnetometer.csv")
        ],
        None,
        "noise",
        "#result",
    ),
    "a Betaflight compass tumble's JSON": (
        [CORPUS / "betaflight_compass_tumble_samples" / "calibration_samples_2026-06-11T03-08-04-544Z.json"],
        None,
        "magnetometer",
        "#result",
    ),
}


@pytest.mark.parametrize("name", list(CASES))
def test_a_real_recording_runs_what_it_supports_first_and_nothing_else(page, server, name):
    files, rate, first, shown = CASES[name]
    page.goto(server.url + "/")
    page.set_input_files("#log-file", [str(f) for f in files])
    if rate:
        page.click("#options-summary")
        page.fill("#log-rate", rate)
    with page.expect_response(lambda r: r.url.endswith("/api/v1/recordings")) as answer:
        page.click("#upload-form button[type=submit]")
    rec = answer.value.json()
    page.wait_for_selector("#supports:not([hidden])")
    lines = page.locator("#supports-list li")
    methods = [lines.nth(i).get_attribute("data-method") for i in range(lines.count())]
    assert methods == [s["method"] for s in rec["supports"]]  # the page lists what the recording supports, in order
    ready = [s["method"] for s in rec["supports"] if s["ready"]]
    assert (ready[0] if ready else None) == first, rec["supports"]
    page.wait_for_selector(f"{shown}:not([hidden])", timeout=60_000)
    if first is not None:
        page.wait_for_selector("#verdict-words:not(:empty)", timeout=60_000)
        assert page.text_content("#supports-holds").endswith(".") and "Running " in page.text_content("#supports-holds")
    else:  # nothing ready: nothing runs, and what each lacks is said as a fact, never in red
        assert page.locator("#result").is_hidden()
        assert "Nothing this recording supports is ready yet" in page.text_content("#segments-msg")
    assert page.locator("#segments-msg.bad, #upload-msg.bad").count() == 0  # no failure nobody asked for
    if name == "an ArduCopter flight with GPS":  # the log's fix gives the place: no Where and when card
        assert page.locator("#compass-place").is_hidden()
    # The page fetches every export of a result; one that does not apply (Kalibr without a random walk, a firmware
    # file of counts) answers 422 and is shown as such: the browser logs it, nothing else may fail.
    assert [e for e in page.errors if "status of 422" not in e] == []
