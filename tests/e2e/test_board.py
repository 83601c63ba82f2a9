"""A board as the wizard's sensor, in real headless Chromium against a real trical server: real board
recordings (tests/data/real) played as the lines a sketch prints, through a stand-in for the Web Serial
API (board_shim.js) that the page's own timer drives in real time, into the same flows as the phone's.
"""

from __future__ import annotations

import json
import re
import time
from pathlib import Path

import numpy as np
import pytest
from playwright.sync_api import expect

from app.calibration import fit_six_position
from app.io.board.formats import RATE_WINDOW_S
from app.io.exports.motioncal_packet import decode
from simulations.magnetometer import simulate_session
from tests.conftest import DATA
from tests.e2e.axe import axe_context
from tests.e2e.conftest import ARTIFACTS, shot, watched_page
from tests.e2e.journey import Journey
from tests.e2e.source_words import other_source_words

SHIM = (Path(__file__).parent / "board_shim.js").read_text()
POSE_FILES = DATA / "real" / "mpu6050_pose_files"
FILES = {
    "+x": "x_axis_pos.csv",
    "-x": "x_axis_neg.csv",
    "+y": "y_axis_pos.csv",
    "-y": "y_axis_neg.csv",
    "+z": "z_axis_pos.csv",
    "-z": "z_axis_neg.csv",
}
ORDER = ["+z", "-y", "+x", "-z", "-x", "+y"]
BOOT = ["", "ets Jun  8 2016 00:22:57", "MPU6050 Found!"]  # what a sketch prints before its readings
CAPTURED = '#poses li[data-pose="{}"][data-state="done"]'
G = 9.80665
NOISE_S = 10  # the shortest still recording the noise page offers
DEVICE = "bench-imu"  # the board's name, as the person types it
RATE_WAIT_MS = int((RATE_WINDOW_S + 4) * 1000)  # a rate is decided once the arrivals fill the window, at the latest


def pose_rows(label: str) -> tuple[str, list[list[str]]]:
    """The header and the rows of one pose file, as the board printed them (numbers kept as text)."""
    lines = (POSE_FILES / FILES[label]).read_text().splitlines()
    return lines[0], [line.split(",") for line in lines[1:]]


def six_lines() -> tuple[list[str], dict[str, list[list[float]]]]:
    """The six files as one board's output: its boot text, the header once, then the poses in ORDER,
    the board's millis() going on from file to file (each file restarts at 410 ms: the files were
    recorded one by one). The first pose is printed twice (the board rests in it while the person
    connects). Returns the lines and, per pose, the accelerometer rows printed."""
    header, _ = pose_rows("+z")
    lines = BOOT + [header]
    printed: dict[str, list[list[float]]] = {}
    t_end = 0
    for label in [ORDER[0]] + ORDER:
        _, rows = pose_rows(label)
        t0 = int(rows[0][0])
        shift = t_end + 16 - t0
        for row in rows:
            t = int(row[0]) + shift
            lines.append(",".join([str(t)] + row[1:]))
            printed.setdefault(label, []).append([float(v) for v in row[1:4]])
        t_end = int(rows[-1][0]) + shift
    return lines, printed


@pytest.fixture
def desk(browser, request):
    """A computer's browser with the board stand-in, the CSP bypassed for axe (tests/e2e/axe.py) unless the
    test's name has `csp` in it (then the page's script runs under the page's own policy)."""
    options = {"viewport": {"width": 1280, "height": 900}, "device_scale_factor": 1}
    axe = "csp" not in request.node.name
    context = axe_context(browser, **options) if axe else browser.new_context(**options)
    page = watched_page(context)
    page.add_init_script(SHIM)
    yield page
    context.close()


def board_state(page, flow: str, state: str, widths=(390, 1280)) -> list[str]:
    """A board's page as it stands: none of a phone's words, and at each width (the one page resized in
    place) no sideways scrolling, no axe violation, no target under 44 px, a screenshot
    test-artifacts/board_<flow>_<state>_<width>.png. Returns the problems found."""
    from tests.e2e.test_layout import looked_at

    problems = [f"board_{flow}_{state}: a phone's word {w}" for w in other_source_words(page, "board")]
    return problems + looked_at(page, f"board_{flow}_{state}", widths)


def play(page, lines: list[str], hz: float, eol: str = "\r\n", chunk_ms: float = 16) -> None:
    page.evaluate("([lines, hz, eol, ms]) => window.__board.play(lines, hz, eol, ms)", [lines, hz, eol, chunk_ms])


def test_six_poses_from_a_board_over_web_serial_and_the_result_s_layout(desk, server):
    page = desk
    sent: list[dict] = []
    page.on("request", lambda r: sent.append(r.post_data_json) if r.url.endswith("/captures") else None)
    # The same board's compass was calibrated before (its turn simulated, in µT: a board's compass
    # in counts has no MotionCal packet): Send will offer to keep it on the board.
    turn, _, _ = simulate_session(33, n=300, hard_iron_ut=60.0)
    r = page.request.post(
        f"{server.url}/api/v1/calibrations",
        data={"method": "magnetometer", "mag": turn.tolist(), "field_ut": 48.0, "device_id": DEVICE},
    )
    assert r.status == 201, r.text()
    compass = r.json()
    # The maker's journey (issue 45): from the start page's board door to the packet on the board.
    journey = Journey("board, six poses")
    page.goto(server.url + "/")
    with journey.looking():
        shot(page, "journey_board_first_1280")
    journey.click(page, "#board-flows .cta", "Connect a board: six positions")
    page.wait_for_url("**/wizard?protocol=six&source=board")
    page.goto(page.url + "&capture_s=0.5")  # the test's one shortcut: half-second captures (the person's are 5 s)
    expect(page.locator("#board")).to_be_visible()
    # A board's page from the first screen: its title, the board's card first, no Start, a board pictured.
    assert page.title() == "Calibrate this board — trical" and page.text_content("h1") == "Calibrate this board"
    assert page.evaluate("document.querySelector('main .card:not([hidden])').id") == "board"
    assert page.locator("#start-btn").count() == 0
    with journey.looking():
        problems = board_state(page, "six", "before_start", widths=(320, 390, 1280))
    assert page.input_value("#board-baud") == "115200"
    page.fill("#device-name", DEVICE)
    journey.act("type the board's name")
    lines, printed = six_lines()
    # Lines without the board's time (the Timestamp column dropped), reaching the page 1 s at a time (a
    # USB-serial bridge's buffer, a loaded computer): the rate is counted over the arrivals.
    lines = BOOT + [line.split(",", 1)[1] for line in lines[len(BOOT) :]]
    play(page, lines, 62.5, "\r\n", 1000)
    t0 = time.monotonic()
    journey.click(page, "#board-usb", "Connect over USB")
    journey.act("pick the board's port in the browser's chooser")
    assert page.evaluate("window.__board.requests") == [True]  # the chooser, from the click
    assert page.evaluate("window.__board.opened") == [115200]
    expect(page.locator("#board-live")).to_have_attribute("data-format", "csv", timeout=5_000)
    expect(page.locator("#board-live")).to_have_attribute("data-acc-unit", "m/s^2", timeout=RATE_WAIT_MS)
    checks = time.monotonic()
    with journey.looking():
        problems += board_state(page, "six", "connected")
    what = page.text_content("#board-what")
    assert "CSV with a header line" in what and "accelerometer in m/s² (from its reading at rest)" in what
    assert "gyroscope in °/s (assumed)" in what
    # The pictures and words are a board's.
    assert page.text_content("h1") == "Calibrate this board"
    assert (
        page.get_attribute("#poses li[data-pose='+x'] svg", "aria-label")
        == "Board on an edge, its X arrow pointing up (+x up)"
    )
    for k, label in enumerate(ORDER):
        page.wait_for_selector(CAPTURED.format(label), state="attached", timeout=15_000)
        if k == 1:
            with journey.looking():
                problems += board_state(page, "six", "capture_done", widths=(320, 390, 1280))
            checks = time.monotonic() - checks  # the seconds the checks above held the page (left out below)
    page.wait_for_selector("#downloads[data-ready=true]", timeout=20_000)
    elapsed = time.monotonic() - t0 - checks
    with journey.looking():
        page.click("#result-details summary")  # the details open too
        problems += board_state(page, "six", "result")

    # The captures are the board's rows, verbatim and in order, on the board's clock (its counted rate).
    assert [c["position"] for c in sent] == ORDER
    for c in sent:
        rows = np.array(printed[c["position"]])
        acc = np.array(c["acc"])
        start = next(
            i
            for i in range(len(rows))
            if np.array_equal(rows[i], acc[0]) and np.array_equal(rows[i : i + len(acc)], acc)
        )
        assert np.array_equal(rows[start : start + len(acc)], acc)
        assert np.allclose(np.diff(c["t_ms"]), 16.0, rtol=0.02) and c["t_ms"][-1] - c["t_ms"][0] >= 500
        assert c["sign"] == {"convention": "w3c", "detected_from": "default"} and c["unit"] == "m/s^2"
    # The result is the closed form of Georgieva et al. on the means of what the board printed.
    means = np.array([np.mean(c["acc"], axis=0) for c in sent])
    expected = fit_six_position(means, [c["position"] for c in sent], gravity=G)
    saved = json.loads(page.evaluate("localStorage.getItem('trical.wizard.six.board')"))
    cal_id = page.evaluate("document.querySelector('#result-ok').textContent.split(' ')[1]")
    r = page.request.get(
        f"{server.url}/api/v1/calibrations/{cal_id}", headers={"Authorization": f"Bearer {saved['token']}"}
    )
    assert r.status == 200, r.text()
    model = r.json()["model"]
    np.testing.assert_allclose(np.array(model["X"]), expected.X, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(np.array(model["y"]), expected.y, rtol=1e-9, atol=1e-12)

    assert page.input_value("#use-with") == "firmware"  # a board's calibration: the C header first
    # Send to the board: the bytes written to the port are the API's MotionCal packet
    # (GET …/export?format=motioncal); the note says what the packet cannot carry.
    expect(page.locator("#board-send-box")).to_be_visible()
    note = page.text_content("#board-send-box")
    assert "cannot carry the accelerometer's scales and cross terms" in note and "C header" in note
    api = page.request.get(
        f"{server.url}/api/v1/calibrations/{cal_id}/export?format=motioncal",
        headers={"Authorization": f"Bearer {saved['token']}"},
    )
    assert api.ok and len(api.body()) == 68 and api.body()[:2] == bytes([117, 84]), api.text()
    # What it replaces, and the same device's compass calibration from the history, included by default.
    box = page.locator("#board-send-box")
    expect(box).to_have_attribute("data-compass", compass["id"])
    assert (
        "replaces all the board has stored: the accelerometer's offsets, the gyroscope's offsets, and the "
        "compass's hard iron, soft iron and field strength" in page.inner_text("#board-send-replaces")
    )
    assert page.is_checked("#board-send-compass")
    assert f"Include the compass calibration of {DEVICE} from " in page.text_content("#board-send-compass-box")
    assert "From the compass calibration of" in page.text_content("#board-send-parts")
    journey.click(page, "#board-send", "Send to the board")  # asks first: what the packet replaces
    expect(page.locator("#board-send-confirm")).to_be_visible()
    assert bytes(page.evaluate("window.__board.written")) == b""
    with journey.looking():
        box.screenshot(path=str(ARTIFACTS / "board_send_confirm_1280.png"))
    journey.click(page, "#board-send-go", "Replace the board's calibration")
    expect(page.locator("#board-send-msg")).to_have_attribute("data-sent", "68")
    journey.report(
        "the packet written to the board", 6 * (5 - 0.5) + 6 * 8, "5 s captures, and 8 s to turn the board each time"
    )
    assert page.get_attribute("#board-send-msg", "data-compass") == compass["id"]
    # the board's reply, or that none came within 2 s (the shim, as Adafruit's sketch, prints none)
    expect(page.locator("#board-send-msg")).to_have_attribute("data-ack", "none", timeout=10_000)
    assert "The board printed no reply within 2 s" in page.text_content("#board-send-msg")
    written = bytes(page.evaluate("window.__board.written"))
    sent_cal, ours = decode(written), decode(api.body())  # decode checks the signature and the CRC
    theirs = decode(
        page.request.get(f"{server.url}/api/v1/calibrations/{compass['id']}/export?format=motioncal").body()
    )
    assert np.array_equal(sent_cal.accel_zerog, ours.accel_zerog) and np.array_equal(
        sent_cal.gyro_zerorate, ours.gyro_zerorate
    )
    assert np.array_equal(sent_cal.mag_hardiron, theirs.mag_hardiron) and sent_cal.mag_field == theirs.mag_field
    assert np.array_equal(sent_cal.mag_softiron, theirs.mag_softiron)
    # the stored compass calibration's own numbers (float32 on the way)
    np.testing.assert_allclose(sent_cal.mag_hardiron, compass["model"]["b"], rtol=1e-6)
    np.testing.assert_allclose(sent_cal.mag_softiron, compass["model"]["M"], rtol=1e-6, atol=1e-7)
    assert sent_cal.mag_field == pytest.approx(compass["metrics"]["field_ut"], rel=1e-6)
    shot(page, "journey_board_last_1280")
    box.screenshot(path=str(ARTIFACTS / "board_send_compass_1280.png"))
    # Left out: the page says the board's compass calibration is reset, and the packet is the server's own.
    page.uncheck("#board-send-compass")
    assert (
        "The board's compass calibration will be reset: no hard iron, an identity soft iron and 50 µT"
        in page.text_content("#board-send-parts")
    )
    page.click("#board-send")
    page.click("#board-send-go")
    page.wait_for_function("window.__board.written.length === 136")
    assert bytes(page.evaluate("window.__board.written"))[68:] == api.body()
    page.check("#board-send-compass")
    problems += board_state(page, "six", "sent", widths=(320, 390, 1280))
    assert not problems, "\n".join(problems)

    # The live view: the boot lines skipped and counted, the board's rate counted over 1 s bursts.
    page.wait_for_function("window.__board.pending() === 0", timeout=30_000)
    page.wait_for_timeout(600)  # the live view's last redraw
    live = page.locator("#board-live")
    assert live.get_attribute("data-skipped") == "2"  # the two boot lines (a blank line is no line)
    n = int(live.get_attribute("data-readings"))
    assert n == len(lines) - len(BOOT) - 1
    rate = float(live.get_attribute("data-rate"))
    assert rate == pytest.approx(62.5, rel=0.01)
    assert page.errors == []
    # From Connect to the verdict with 5 s a pose: each capture 4.5 s longer, and 8 s for a person to
    # turn the board each time (the played lines turn it at once).
    estimate = elapsed + 6 * (5 - 0.5) + 6 * 8
    print(
        f"\nboard six flow, lines in 1 s bursts, capture_s=0.5: {elapsed:.1f} s from Connect to the downloads; "
        f"with 5 s a pose and "
        f"8 s a turn: {estimate:.0f} s"
    )


def test_nothing_arrives_then_lines_that_are_not_readings(desk, server):
    page = desk
    page.goto(server.url + "/wizard?protocol=six&source=board")
    page.click("#board-usb")  # a board that prints nothing
    msg = page.locator("#board-msg")
    expect(msg).to_have_text(
        "Nothing arrives at 115200 baud: check the rate and that the board prints readings.", timeout=6_000
    )
    problems = board_state(page, "six", "silent")
    page.click("#board-close")
    expect(page.locator("#board-live")).to_be_hidden()
    # The same board printing Uni: lines at 115200, opened at 9600: scrambled bytes, no reading.
    page.select_option("#board-baud", "9600")
    play(page, ["Uni:0.12,-0.05,9.79,0.001,-0.002,0.000,21.5,-3.2,40.1"] * 400, 100)
    page.click("#board-usb")
    expect(msg).to_contain_text("The lines arriving are not readings: the last one is “", timeout=6_000)
    assert page.evaluate("window.__board.opened") == [115200, 9600]
    problems += board_state(page, "six", "unreadable")
    assert not problems, "\n".join(problems)
    assert page.errors == []


def test_the_chooser_closed_says_so_under_the_csp(desk, server):
    page = desk
    page.goto(server.url + "/wizard?protocol=six&source=board")
    page.evaluate("window.__board.refuse = true")
    page.click("#board-usb")
    expect(page.locator("#board-msg")).to_have_text(
        "No board was chosen: connect it, then choose it in the browser's list."
    )
    assert page.evaluate("window.__board.opened") == []


def test_compass_from_a_board_turned_by_hand(desk, server):
    """The QMC5883L turned by hand (raw counts, every tenth row of a 50 Hz log), its lines after the
    60 s at rest played at 100 lines a second: the sphere fills, the page calibrates by itself, and the
    offset lands within a few counts of the maker's own fit."""
    page = desk
    sent: list[dict] = []
    page.on(
        "request",
        lambda r: sent.append(r.post_data_json) if r.url.endswith("/calibrations") and r.method == "POST" else None,
    )
    refused: list[str] = []
    page.on("response", lambda r: refused.append(r.url.split("?")[-1]) if r.status == 422 else None)
    text = (DATA / "real" / "magnetometer" / "tomisuarez2_qmc5883l_turn_every10.csv").read_text().splitlines()
    header_at = next(i for i, line in enumerate(text) if line.startswith("mx"))
    rows = text[header_at + 1 :][300:]  # after the 60 s at rest (5 rows a second here)
    # The maker's journey to the compass (issue 45): from the start page's board door to the C header.
    journey = Journey("board, compass")
    page.goto(server.url + "/")
    journey.click(page, "#board-flows a[href='/wizard?protocol=compass&source=board']", "The compass: turn the board")
    page.wait_for_url("**/wizard?protocol=compass&source=board")
    assert (
        page.text_content("h1") == "Calibrate this board's compass" and page.locator("#compass-start-btn").count() == 0
    )
    with journey.looking():
        problems = board_state(page, "compass", "before_start", widths=(320, 390, 1280))
    play(page, [text[header_at]] + rows, 100, "\n")
    journey.click(page, "#board-usb", "Connect over USB")
    journey.act("pick the board's port in the browser's chooser")
    expect(page.locator("#compass-capture")).to_be_visible()
    assert page.text_content("#compass-capture-h") == "Turn the board slowly through all directions"
    expect(page.locator("#board-live")).to_have_attribute("data-format", "csv")
    expect(page.locator(".board-plot-fig")).to_be_hidden()  # no accelerometer to plot
    with journey.looking():
        problems += board_state(page, "compass", "turning")
    assert "screen" not in page.inner_html("#compass-sphere")
    page.wait_for_selector("#result:not([hidden])", timeout=40_000)
    read = int(page.get_attribute("#board-live", "data-readings"))  # the turn's rows the page read to its result
    page.wait_for_selector("#downloads[data-ready=true]", timeout=20_000)
    assert page.input_value("#use-with") == "firmware"  # a board's: the C header
    with page.expect_download() as info:
        journey.click(page, "#use-file", "download the C header")
    header = Path(info.value.path()).read_text()
    assert re.search(r"static TRICAL_INLINE void \w+_apply\(const float m\[3\], float f\[3\]\)", header), header[:600]
    # The rows were played at 100 a second; the person turned the board at the log's 5 rows a second.
    journey.report("the compass's C header", read / 5 - read / 100, f"the {read} rows turned at the log's pace")
    problems += board_state(page, "compass", "result", widths=(320, 390, 1280))
    assert (
        page.eval_on_selector_all("#result-mag svg text", "ts => ts.map(t => t.textContent)").count("component side")
        == 2
    )
    assert len(sent) == 1
    mag = np.array(sent[0]["mag"])
    played = np.array([[float(v) for v in r.split(",")] for r in rows])
    assert np.array_equal(mag[0], played[0]) and len(mag) >= 50
    assert all(any(np.array_equal(m, p) for p in played[: len(mag) + 50]) for m in mag[:20])
    peer = json.loads((DATA / "real" / "magnetometer" / "tomisuarez2_qmc5883l_peer.json").read_text())
    offset = -np.linalg.solve(np.array(peer["A"]), np.array(peer["B"]))
    cal_id = page.evaluate("document.querySelector('#result-ok').textContent.split(' ')[1]")
    b = np.array(page.request.get(f"{server.url}/api/v1/calibrations/{cal_id}").json()["model"]["b"])
    # The page fits the part of the turn it took before its coverage was full, which depends on how fast
    # the lines were read (seen 15.1 counts under two busy loops, a few on a quiet machine): within 25
    # counts of the maker's fit on the whole turn (the offset is about 6200 counts).
    assert np.max(np.abs(b - offset)) < 25, (b, offset)
    # The board prints counts, not µT (the calibration says so: its unit is read from the field its readings
    # show): a flight controller's file is refused, naming the scale to give, and the page says so in the list
    # of formats (the browser logs the refused exports).
    body = page.request.get(f"{server.url}/api/v1/calibrations/{cal_id}").json()
    assert body["output_unit"] == "raw" and body["ok"] is True
    assert sorted(refused) == ["format=ardupilot", "format=px4"], refused
    assert page.text_content("#downloads").count("this calibration maps readings in counts") == 2
    assert len(page.errors) == 2 and all("422" in e for e in page.errors)
    # Its own page, opened later, still speaks of a board: the calibration keeps its source.
    assert body["source"] == "board"
    page.goto(f"{server.url}/c/{cal_id}")
    page.wait_for_selector(".mag-fig svg text", timeout=10_000)
    assert (
        page.eval_on_selector_all(".mag-fig svg text", "ts => ts.map(t => t.textContent)").count("component side") == 2
    )
    problems += [f"/c/ of a board's compass: a phone's word {w}" for w in other_source_words(page, "board")]
    assert not problems, "\n".join(problems)


def test_noise_of_a_still_board(desk, server):
    """The MPU-6050 resting still (100 Hz, raw counts), printed as a sketch prints g (counts / 16384, five
    decimals, no time column): the page times the lines by their arrival, records the length chosen,
    uploads it and characterises its noise; the white noise lands near the maker's own figure from a
    6-hour recording (tests/data/real/README.md)."""
    page = desk
    refused: list[str] = []
    page.on("response", lambda r: refused.append(r.url.split("?")[-1]) if r.status == 422 else None)
    text = (DATA / "real" / "mpu6050_session2_still_30s.csv").read_text().splitlines()
    rows = [line for line in text if line and not line.startswith("#")][1:]
    lines = [",".join(f"{int(v) / 16384:.5f}" for v in row.split(",")) for row in rows]
    page.goto(server.url + "/wizard?protocol=noise&source=board")
    problems = board_state(page, "noise", "before_start", widths=(320, 390, 1280))
    page.select_option("#noise-length", str(NOISE_S))
    page.fill("#device-name", "mpu6050 bench")
    play(page, lines, 100)
    page.click("#board-usb")
    # Record is enabled by the first reading, which comes once the rate of the lines (no time column) is
    # counted: as long as the rule may take (CI once waited more than 5 s on a loaded machine).
    expect(page.locator("#noise-record")).to_be_enabled(timeout=RATE_WAIT_MS)
    expect(page.locator("#board-live")).to_have_attribute("data-acc-unit", "g")
    page.click("#noise-record")
    problems += board_state(page, "noise", "recording")
    page.wait_for_selector("#result:not([hidden])", timeout=(NOISE_S + 30) * 1000)
    page.wait_for_selector("#downloads[data-ready=true]", timeout=20_000)
    problems += board_state(page, "noise", "result")
    cal_id = page.evaluate("document.querySelector('#result-ok').textContent.split(' ')[1]")
    cal = page.request.get(f"{server.url}/api/v1/calibrations/{cal_id}").json()
    assert cal["device_id"] == "mpu6050 bench"
    density = np.array(cal["model"]["acc"]["noise_density"], dtype=float)
    peer = json.loads((DATA / "real" / "mpu6050_noise_peer.json").read_text())
    expected = np.sqrt(np.array(peer["R"]) / peer["sampling_rate_hz"])  # 3.30, 3.05, 4.63 mm/s²/√Hz
    print(f"\nnoise density over {NOISE_S} s from the board's lines: {density} m/s²/√Hz; the maker's: {expected}")
    # Which 10 s the page records depends on when the rate is decided: over every 10 s window of this file
    # trical's density lies −13.4…+9.8 % from the maker's, whose figure lies inside trical's 95 % interval
    # in each (the page's figure is honest about what 10 s can tell).
    interval = np.array(cal["uncertainty"]["acc"]["noise_density"], dtype=float)
    assert np.all((interval[:, 0] <= expected) & (expected <= interval[:, 1])), interval
    assert np.all(np.abs(density / expected - 1) < 0.15)
    # 10 s show no random walk: the filters' formats that need it are refused with the reason, the JSON,
    # the CSV and the plot offered (the browser logs the three refused exports).
    assert sorted(refused) == ["format=kalibr", "format=openvins", "format=vins"]
    assert "random_walk is null on some axes (the recording is too short to see it" in page.text_content("#downloads")
    assert len(page.errors) == 3 and all("422" in e for e in page.errors)
    assert not problems, "\n".join(problems)


def test_a_board_over_bluetooth_prints_raw_lines(desk, server):
    """The +z pose file printed as MotionCal's Raw: lines (its m/s² as counts of 1/8192 g, gyroscope and
    magnetometer zero), over the Nordic UART: the same live view, the pose recognised as a board's."""
    page = desk
    _, rows = pose_rows("+z")
    # The file's 200 rows are 3.2 s at 62.5 Hz: the board rests and prints them over and over (22 s), longer than
    # the page may take to count the rate. Played once, a pause of a loaded page early on left the page no
    # arrivals to decide on after it (CI: no pose after 12 s).
    rows = rows * 7
    lines = ["Raw:" + ",".join(str(round(float(v) / G * 8192)) for v in r[1:4]) + ",0,0,0,0,0,0" for r in rows]
    page.goto(server.url + "/wizard?protocol=six&source=board")
    expect(page.locator("#board-ble")).to_be_visible()
    play(page, lines, 62.5, "\n")
    page.click("#board-ble")
    requests = page.evaluate("window.__board.bleRequests")
    assert requests == [
        {"options": {"filters": [{"services": ["6e400001-b5a3-f393-e0a9-e50e24dcca9e"]}]}, "click": True}
    ]
    live = page.locator("#board-live")
    expect(live).to_have_attribute("data-format", "raw", timeout=5_000)
    expect(page.locator("#live-pose")).to_have_attribute("data-pose", "+z", timeout=RATE_WAIT_MS)
    assert page.text_content("#live-pose-words") == "Now: flat, component side up"
    assert page.text_content("#board-what").startswith(
        "MotionCal Raw: lines (counts at MotionCal's scales); accelerometer in m/s²;"
    )
    row = page.eval_on_selector_all(
        "#board-numbers tbody tr", "rs => rs.map(r => [...r.cells].map(c => c.textContent))"
    )
    assert [r[0] for r in row] == ["acc (m/s²)", "gyr (°/s)", "mag (µT)"]
    shot(page, "board_bluetooth_raw_1280")
    assert page.errors == []


@pytest.mark.parametrize("flow", ["free", "cube24"])
def test_free_poses_and_the_cube_from_a_board_are_a_board_s(desk, server, flow):
    """The free and the cube flows with a board resting component side up (Uni: lines with a gyroscope):
    the page before it connects, the board connected and capturing, its first pose captured."""
    from tests.e2e.test_layout import UNI

    page = desk
    page.goto(server.url + f"/wizard?protocol={flow}&source=board&capture_s=0.5")
    assert page.text_content("h1") == "Calibrate this board" and page.locator("#start-btn").count() == 0
    problems = board_state(page, flow, "before_start", widths=(320, 390, 1280))
    play(page, list(UNI) * 3, 100)
    page.click("#board-usb")
    expect(page.locator("#capture")).to_be_visible()
    expect(page.locator("#board-live")).to_have_attribute("data-acc-unit", "m/s^2", timeout=RATE_WAIT_MS)
    problems += board_state(page, flow, "connected")
    done = "#free-count[data-count='1']" if flow == "free" else "#cube-count[data-captured='1']"
    page.wait_for_selector(done, state="attached", timeout=15_000)
    problems += board_state(page, flow, "capture_done")
    assert not problems, "\n".join(problems)
    assert page.errors == []
