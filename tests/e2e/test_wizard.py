"""The guided wizard in real headless Chromium, with the phone's motion fed through the DevTools
protocol's sensor overrides (Chromium derives DeviceMotionEvent from them and rounds to 0.1 m/s²),
against a real trical server."""

from __future__ import annotations

import json
import re
import time
from pathlib import Path

import numpy as np
import pytest
from playwright.sync_api import expect

from app.calibration import fit_six_position
from tests.e2e.axe import axe_context
from tests.e2e.conftest import ARTIFACTS, CHROMIUM, CHROMIUM_ARGS, LAUNCH_TIMEOUT_MS, shot, tab_to, watched_page
from tests.e2e.journey import Journey
from tests.e2e.source_words import assert_only_its_words
from tests.e2e.test_layout import layout_problems, looked_at
from tests.live_server import LiveServer

G = 9.80665  # the session's default gravity
POSES = ["-x", "+x", "-y", "+y", "-z", "+z"]
IPHONE_UA = (
    "Mozilla/5.0 (iPhone; CPU iPhone OS 17_5 like Mac OS X) AppleWebKit/605.1.15 "
    "(KHTML, like Gecko) Version/17.5 Mobile/15E148 Safari/604.1"
)
# A phone's accelerometer as the test knows it: m = X a + y, X off the identity, y off zero.
X_TRUE = np.array([[1.012, 0.011, -0.018], [-0.014, 0.991, 0.023], [0.016, -0.021, 1.006]])
Y_TRUE = np.array([0.137, -0.211, 0.284])
CAPTURED = '#poses li[data-pose="{}"][data-state="done"]'


def up(label: str) -> np.ndarray:
    v = np.zeros(3)
    v["xyz".index(label[1])] = 1.0 if label[0] == "+" else -1.0
    return v


def chromium_round(v) -> np.ndarray:
    """What Chromium hands the page: each component rounded to a multiple of 0.1 m/s²."""
    return np.round(np.asarray(v, dtype=float) / 0.1) * 0.1


def reading(label: str) -> np.ndarray:
    return X_TRUE @ (G * up(label)) + Y_TRUE


class Motion:
    """The device's sensors, overridden through the DevTools protocol."""

    def __init__(self, page):
        self.cdp = page.context.new_cdp_session(page)
        for sensor in ("accelerometer", "linear-acceleration", "gyroscope"):
            self.cdp.send("Emulation.setSensorOverrideEnabled", {"enabled": True, "type": sensor})
            self.send(sensor, (0.0, 0.0, 0.0))

    def send(self, sensor, xyz):
        x, y, z = (float(v) for v in xyz)
        self.cdp.send(
            "Emulation.setSensorOverrideReadings", {"type": sensor, "reading": {"xyz": {"x": x, "y": y, "z": z}}}
        )

    def acc(self, xyz):
        self.send("accelerometer", xyz)

    def orientation(self, beta, gamma):
        self.cdp.send("DeviceOrientation.setDeviceOrientationOverride", {"alpha": 0, "beta": beta, "gamma": gamma})


def captures_sent(page) -> list[dict]:
    """The capture requests the page really sends (observed, not altered)."""
    sent: list[dict] = []
    page.on("request", lambda r: sent.append(r.post_data_json) if r.url.endswith("/captures") else None)
    return sent


def stored_session(page, server) -> dict:
    saved = json.loads(page.evaluate("localStorage.getItem('trical.wizard.six')"))
    r = page.request.get(
        f"{server.url}/api/v1/sessions/{saved['id']}", headers={"Authorization": f"Bearer {saved['token']}"}
    )
    assert r.status == 200, r.text()
    return r.json()


def wait_captured(page, label, timeout=20_000):
    # attached: after the last pose the list hides behind the result
    page.wait_for_selector(CAPTURED.format(label), state="attached", timeout=timeout)


def repeat_the_first_pose(page, motion, url):
    """Open the six flow, capture +z, then pick the phone up and put it down screen up again: the
    repeat is refused (the page's longest instruction)."""
    page.goto(url + "/wizard?capture_s=1")
    motion.acc(reading("+z"))
    page.click("#start-btn")
    wait_captured(page, "+z")
    motion.acc((3.0, 3.0, 8.8))  # picked up and tilted...
    expect(page.locator("#still-text")).to_have_text("Moving")
    motion.acc(reading("+z"))  # ...and put down screen up again
    expect(page.locator("#instruction")).to_contain_text("Flat, screen up is already captured", timeout=10_000)


def hold(page, motion, label, name):
    motion.acc(reading(label))
    wait_captured(page, label)
    shot(page, name)


def grant_on_tap(page):
    """Stand-in for iOS's DeviceMotionEvent.requestPermission, which Chromium lacks: records whether
    it was called during a user activation (a tap) and grants."""
    page.add_init_script("""
      window.__permissionCalls = [];
      DeviceMotionEvent.requestPermission = () => {
        window.__permissionCalls.push(navigator.userActivation.isActive);
        return Promise.resolve('granted');
      };""")


def test_six_poses_hands_free_match_the_closed_form(browser, server):
    """The phone's journey (issue 45): the computer's start page, the phone scanning its code into the phone's door
    (HTTPS, the certificate's warning passed as a person does), Start, six poses hands-free, and the file for a
    phone app; the result is the closed form on what the browser handed the page."""
    journey = Journey("phone")
    desktop = axe_context(browser, viewport={"width": 1280, "height": 900}, device_scale_factor=1)
    start = watched_page(desktop)
    start.goto(server.url + "/")
    code = start.text_content("#phone-url")
    with journey.looking():  # the start page's layout and axe at every width are test_layout.py's
        shot(start, "journey_phone_first_1280")
    problems: list[str] = []
    phone = axe_context(
        browser,
        viewport={"width": 390, "height": 844},
        device_scale_factor=1,
        is_mobile=True,
        has_touch=True,
        ignore_https_errors=True,  # the person's "proceed" past the self-signed certificate's warning
    )
    page = watched_page(phone)
    grant_on_tap(page)
    sent = captures_sent(page)
    motion = Motion(page)
    gyro_deg_s = np.array([0.3, -0.2, 0.1])  # a gyroscope bias at rest, multiples of Chromium's 0.1 °/s rounding
    motion.send("gyroscope", np.radians(gyro_deg_s))  # the sensor in rad/s, rotationRate in °/s
    journey.act("scan the code")
    page.goto(code)
    door = code.partition("/phone?")[0]
    assert door.startswith("https://") and page.url == door + "/"  # in, on the phone's start page
    expect(page.locator("#phone-start")).to_be_visible()
    with journey.looking():
        problems += looked_at(page, "journey_phone_start", widths=(390,))
    journey.click(page, "#phone-start a[href='/wizard?protocol=six']", "Start: six positions")
    page.wait_for_url("**/wizard?protocol=six")
    page.goto(page.url + "&capture_s=1")  # the test's one shortcut: 1 s captures (the person's are 5 s)
    shot(page, "wizard_start")
    assert_only_its_words(page, "phone")
    assert "flat, steady table" in page.text_content("#start")
    order = ["+z", "-y", "+x", "-z", "-x", "+y"]  # shuffled
    motion.acc(reading(order[0]))
    page.fill("#device-name", "bench phone")  # named before Start: the session, and so its calibration, carry it
    journey.act("type the phone's name")
    t0 = time.monotonic()
    journey.click(page, "#start-btn", "Start")
    assert page.evaluate("window.__permissionCalls") == [True]  # asked once, from the tap
    expect(page.locator("#device-name")).to_be_hidden()
    for k, label in enumerate(order):
        if k:
            motion.acc(reading(label))
        if k == 0:
            page.wait_for_selector("#progress:not([value='0'])", timeout=10_000)
            shot(page, "wizard_capturing_first_pose")
            assert_only_its_words(page, "phone")
        wait_captured(page, label)
        shot(page, f"wizard_captured_{k + 1}_{label}")
        assert_only_its_words(page, "phone")
    page.wait_for_selector("#downloads[data-ready=true]", timeout=20_000)
    elapsed = time.monotonic() - t0
    shot(page, "wizard_result")
    assert_only_its_words(page, "phone")

    # The closed form of Georgieva et al. section 3.3.1 on what Chromium handed the page.
    fed = np.array([chromium_round(reading(label)) for label in POSES])
    expected = fit_six_position(fed, POSES, gravity=G)
    assert page.input_value("#use-with") == "app"  # a phone's calibration: the file for a phone app
    with page.expect_download() as info:
        journey.click(page, "#use-file", "download the JSON")
    download = info.value
    journey.report("the phone app's JSON", 6 * (5 - 1) + 6 * 8, "5 s captures, and 8 s to turn the phone to each pose")
    with journey.looking():
        problems += looked_at(page, "journey_phone_last")
    assert not problems, "\n".join(problems)
    doc = json.loads(Path(download.path()).read_text())
    np.testing.assert_allclose(np.array(doc["model"]["X"]), expected.X, rtol=1e-9, atol=0)
    np.testing.assert_allclose(np.array(doc["model"]["y"]), expected.y, rtol=1e-9, atol=0)
    assert download.suggested_filename == f"{doc['id']}.json"
    assert doc["device_id"] == "bench phone"
    links = page.eval_on_selector_all("#downloads a", "as => as.map(a => [a.textContent, a.href, a.download])")
    assert [name for name, _, _ in links] == [
        "JSON",
        "C header",
        "ArduPilot",
        "PX4",
        "Betaflight",
        "INAV",
        "YAML",
        "CSV",
    ]
    assert all(href.startswith("blob:") and filename for _, href, filename in links)

    # What the page showed: X with intervals, the server's warnings, the norm chart per pose.
    assert "passed its checks" in page.text_content("#result-ok")
    first = page.text_content("#result-X tr:first-child td:first-child")
    assert first.startswith(f"{expected.X[0, 0]:.6f} ± ")
    warnings = page.text_content("#result-warnings")
    assert "rounds its sensor values to 0.1 m/s²" in warnings and "may already calibrate" in warnings
    rows = page.eval_on_selector_all("#norm-table tbody tr", "rs => rs.map(r => [...r.cells].map(c => c.textContent))")
    assert [r[0] for r in rows] == POSES
    for (_label, raw, calibrated), m in zip(rows, fed):
        assert float(raw) == pytest.approx(np.linalg.norm(m), abs=1e-4)
        assert float(calibrated) == pytest.approx(np.linalg.norm(expected.apply(m[None])[0]), abs=1e-4)
    assert page.locator("#norm-chart svg circle").count() == 12
    # The gyroscope's bias over the still captures (app.calibration.still.gyro_bias), and its export.
    assert page.text_content("#result-gyro") == (
        "Gyroscope bias: 0.300, -0.200, 0.100 °/s ± 0.000, 0.000, 0.000 °/s (95 %, 6 still captures)"
    )
    np.testing.assert_allclose(doc["gyroscope"]["bias"], np.radians(gyro_deg_s), rtol=1e-6)

    # What the page sent: raw samples in order, W3C by default off Apple devices, the gyroscope too.
    assert [c["position"] for c in sent] == order
    for c in sent:
        assert c["sign"] == {"convention": "w3c", "detected_from": "default"}
        assert c["redo"] is False and c["unit"] == "m/s^2" and c["gyr_unit"] == "deg/s"
        assert len(c["acc"]) >= 10 and np.all(np.diff(c["t_ms"]) > 0) and len(c["gyr"]) == len(c["acc"])
        assert c["t_ms"][-1] - c["t_ms"][0] >= 1000
    assert page.errors == []
    # The device's latest calibration, read in this browser (with the session's token it keeps), is this one.
    page.goto(door + "/c/latest?device=bench%20phone")
    expect(page.locator("#cal-meta")).to_contain_text(doc["id"])

    per_pose = elapsed / 6
    estimate = elapsed + 6 * (5 - 1)  # each pose captures 4 s longer with capture_s=5
    note = (
        f"six-pose wizard, capture_s=1: {elapsed:.1f} s from the Start tap to the downloads "
        f"({per_pose:.1f} s a pose, the phone moved instantly); capture_s=5: {estimate:.1f} s of "
        f"waiting, {estimate + 6 * 8:.0f} s with 8 s for a person to turn the phone each time"
    )
    print("\n" + note)
    ARTIFACTS.mkdir(exist_ok=True)
    (ARTIFACTS / "wizard_timing.txt").write_text(note + "\n")
    assert estimate + 6 * 8 < 120


def test_a_repeated_pose_is_refused_and_redo_replaces_it(page, server):
    sent = captures_sent(page)
    motion = Motion(page)
    page.goto(server.url + "/wizard?capture_s=1")
    motion.acc(reading("+z"))
    page.click("#start-btn")
    wait_captured(page, "+z")
    first = stored_session(page, server)["captures"][0]
    motion.acc((3.0, 3.0, 8.8))  # picked up and tilted...
    expect(page.locator("#still-text")).to_have_text("Moving")
    motion.acc(reading("+z"))  # ...and put down screen up again
    expect(page.locator("#instruction")).to_contain_text("Flat, screen up is already captured", timeout=10_000)
    text = page.text_content("#instruction")
    # The next pose in words; the axis codes only in the grey note under it.
    assert "Next: put the phone flat, screen down" in text and "Redo" in text and not re.search(r"[+-][xyz]\b", text)
    assert "Still to do: -x, +x, -y, +y, -z" in page.text_content("#instruction-code")
    assert "Flat, screen up is already captured" in page.text_content("#status")  # announced
    shot(page, "wizard_repeat_refused")
    page.wait_for_timeout(2500)  # longer than hold + capture: nothing is sent for a done pose
    assert len(sent) == 1

    page.click('#poses button[data-redo="+z"]')
    expect(page.locator('#poses li[data-pose="+z"]')).to_have_attribute("data-state", "redo")
    shot(page, "wizard_redo_pressed")
    wait_captured(page, "+z")
    assert [c["redo"] for c in sent] == [False, True]
    session = stored_session(page, server)
    assert len(session["captures"]) == 1 and session["captures"][0]["created_at"] != first["created_at"]
    assert session["remaining"] == ["-x", "+x", "-y", "+y", "-z"]
    assert page.errors == []


def test_a_reload_resumes_with_the_done_poses(page, server):
    motion = Motion(page)
    page.goto(server.url + "/wizard?capture_s=1")
    motion.acc(reading("-x"))
    page.click("#start-btn")
    wait_captured(page, "-x")
    hold(page, motion, "+y", "wizard_before_reload")
    page.reload()
    page.wait_for_selector("#resume:not([hidden])")
    shot(page, "wizard_resumed")
    states = page.eval_on_selector_all("#poses li", "ls => ls.map(l => [l.dataset.pose, l.dataset.state])")
    assert dict(states) == {"-x": "done", "+x": "todo", "-y": "todo", "+y": "done", "-z": "todo", "+z": "todo"}
    assert "2 of 6 positions captured (right edge down, standing)" in page.text_content("#resume")
    assert page.text_content("#start-btn") == "Continue"
    page.click("#start-btn")
    for label in ["-z", "+x", "+z", "-y"]:
        hold(page, motion, label, f"wizard_resumed_{label}")
    page.wait_for_selector("#downloads[data-ready=true]", timeout=20_000)
    assert "passed its checks" in page.text_content("#result-ok")
    # The result has its own address, /c/{id}: a reload reads it back with the session's token kept for it.
    cal_path = page.evaluate("location.pathname")
    assert re.fullmatch(r"/c/cal_[0-9a-f]{32}", cal_path)
    page.reload()
    page.wait_for_selector("#downloads[data-ready=true]", state="attached")
    assert page.evaluate("location.pathname") == cal_path and cal_path[3:] in page.text_content("#cal-meta")
    page.goto(server.url + "/wizard?capture_s=1")  # the wizard itself resumes into its result
    page.wait_for_selector("#downloads[data-ready=true]")
    page.click("#start-over")
    page.click("#start-over-yes")  # the second step: discard the session; the calibration stays findable
    page.wait_for_selector("#start-btn")
    assert (
        page.text_content("#start-btn") == "Start"
        and page.evaluate("localStorage.getItem('trical.wizard.six')") is None
    )
    assert page.evaluate("Object.keys(JSON.parse(localStorage.getItem('trical.calibrations')))") == [cal_path[3:]]
    assert page.errors == []


def test_start_waits_for_the_flow_a_loaded_machine_is_slow_to_bring(page, server):
    """The page loads its flow's modules after the page itself (a loaded machine, a slow link): Start is
    disabled until they are there, so a tap is never lost, and the first tap once it is enabled reads the
    sensors. CI saw the lost tap: the page stayed at "Waiting for motion data…" with Start on screen."""
    held: list = []
    page.route("**/static/js/flow_six*.js", lambda route: held.append(route))
    motion = Motion(page)
    page.goto(server.url + "/wizard?capture_s=1")
    expect(page.locator("#start-btn")).to_be_disabled()
    page.wait_for_timeout(300)
    expect(page.locator("#start-btn")).to_be_disabled()  # still held: no tap can be lost
    assert len(held) == 2  # the flow and its view
    for route in held:
        route.continue_()
    expect(page.locator("#start-btn")).to_be_enabled()
    motion.acc(reading("+z"))
    page.click("#start-btn")
    wait_captured(page, "+z")
    assert page.errors == []


def test_denied_permission_shows_how_to_allow_it(page, server):
    page.add_init_script("DeviceMotionEvent.requestPermission = () => Promise.resolve('denied');")
    page.goto(server.url + "/wizard")
    page.click("#start-btn")
    problem = page.locator("#problem")
    expect(problem).to_be_visible()
    text = problem.text_content()
    assert "Motion access was not allowed (denied)" in text
    assert "reload this page" in text and "Settings › Safari" in text
    assert page.get_attribute("#problem a", "href") == "/"
    assert "not allowed" in page.text_content("#status")
    assert page.evaluate("localStorage.length") == 0  # no session was started
    shot(page, "wizard_permission_denied")
    assert_only_its_words(page, "phone")


def test_no_motion_events_suggest_an_upload(page, server):
    # Headless Chromium without overrides fires one devicemotion event whose values are all null.
    page.goto(server.url + "/wizard")
    page.click("#start-btn")
    problem = page.locator("#problem")
    expect(problem).to_contain_text("This browser sends no motion data", timeout=5000)
    assert "upload a log instead" in problem.text_content()
    assert page.get_attribute("#problem a", "href") == "/"
    assert page.evaluate("localStorage.length") == 0
    shot(page, "wizard_no_motion")
    assert_only_its_words(page, "phone")


@pytest.mark.parametrize(
    "user_agent, orientation, negate, sign",
    [
        (IPHONE_UA, None, True, {"convention": "ios", "detected_from": "platform"}),
        (None, (0.0, 0.0), True, {"convention": "ios", "detected_from": "orientation"}),
        (IPHONE_UA, (0.0, 0.0), False, {"convention": "w3c", "detected_from": "orientation"}),
    ],
    ids=["iphone-platform", "orientation-says-ios", "orientation-beats-platform"],
)
def test_ios_sign_convention(browser, server, user_agent, orientation, negate, sign):
    context = browser.new_context(viewport={"width": 360, "height": 640}, user_agent=user_agent)
    try:
        page = context.new_page()
        sent = captures_sent(page)
        motion = Motion(page)
        if orientation:
            motion.orientation(*orientation)  # flat, screen up: beta = gamma = 0
        page.goto(server.url + "/wizard?capture_s=1")
        m = reading("+z")
        motion.acc(-m if negate else m)  # iOS Safari: the up axis reads −g
        page.click("#start-btn")
        wait_captured(page, "+z")
        shot(page, f"wizard_sign_{sign['convention']}_{sign['detected_from']}")
        assert sent[0]["sign"] == sign and sent[0]["position"] == "+z"
        np.testing.assert_allclose(np.mean(sent[0]["acc"], axis=0), chromium_round(m), atol=1e-9)
        capture = stored_session(page, server)["captures"][0]
        assert capture["position"] == "+z" and capture["mean"][2] == pytest.approx(chromium_round(m)[2])
    finally:
        context.close()


def test_keyboard_reaches_start_and_redo_with_names(page, server):
    motion = Motion(page)
    page.goto(server.url + "/wizard?capture_s=1")

    tab_to(page, "#start-btn")
    expect(page.locator("#start-btn")).to_have_accessible_name("Start")
    motion.acc(reading("-y"))
    page.keyboard.press("Enter")
    wait_captured(page, "-y")
    tab_to(page, '#poses button[data-redo="-y"]')
    redo = page.locator('#poses button[data-redo="-y"]')
    expect(redo).to_have_accessible_name("Redo -y (upside down on its top edge (the earpiece))")
    shot(page, "wizard_keyboard_redo_focused")
    page.keyboard.press("Enter")
    expect(page.locator('#poses li[data-pose="-y"]')).to_have_attribute("data-state", "redo")
    for button in page.locator("button:visible").all():  # every visible control has a name
        assert button.evaluate("b => b.textContent.trim() || b.getAttribute('aria-label')")
    tab_to(page, "#start-over")
    expect(page.locator("#start-over")).to_have_accessible_name("Start over")
    assert page.evaluate("document.documentElement.scrollWidth") <= 360  # no sideways scrolling on a phone


def test_insecure_context_asks_for_https(browser, server):
    # A name other than localhost over plain HTTP is not a secure context: a phone on the LAN sees
    # http://<computer>:8000 that way. A second Chromium resolves trical.test to the test server.
    b = browser.browser_type.launch(
        executable_path=CHROMIUM,
        args=CHROMIUM_ARGS + ["--host-resolver-rules=MAP trical.test 127.0.0.1"],
        timeout=LAUNCH_TIMEOUT_MS,
    )
    try:
        page = b.new_page(viewport={"width": 360, "height": 640})
        page.goto(f"http://trical.test:{server.port}/wizard")
        assert page.evaluate("window.isSecureContext") is False
        problem = page.locator("#problem")
        expect(problem).to_contain_text(
            "Motion sensors need HTTPS: on the computer that runs trical, scan the QR code of its start page"
        )
        assert page.get_attribute("#problem a", "href") == "/"
        assert page.locator("#start-btn").is_hidden()
        shot(page, "wizard_insecure_context")
    finally:
        b.close()


def test_api_key_is_asked_for(browser, tmp_path):
    server = LiveServer(
        {"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}", "TRICAL_API_KEYS": "k-123"}
    ).start()
    context = browser.new_context(viewport={"width": 360, "height": 640})
    try:
        page = context.new_page()
        motion = Motion(page)
        page.goto(server.url + "/wizard?capture_s=1")
        motion.acc(reading("+x"))
        page.click("#start-btn")
        page.wait_for_selector("#key-box:not([hidden])")
        shot(page, "wizard_api_key")
        assert "API key" in page.text_content("#status")
        page.fill("#api-key", "k-123")
        page.click("#key-submit")
        wait_captured(page, "+x")
    finally:
        context.close()
        server.stop()


def test_the_next_pose_is_named_in_words_with_its_large_picture_before_the_phone_turns(browser, server):
    """At a phone's width: before the phone is placed, the instruction names the next pose in words and the
    large picture shows it (the axis codes only in the grey note); once a pose is captured, the next one
    is named and pictured while the phone is moving; the six thumbnails are two rows of three, each
    named in words and no two alike."""

    context = axe_context(browser, viewport={"width": 390, "height": 844}, device_scale_factor=1)
    try:
        page = context.new_page()
        motion = Motion(page)
        page.goto(server.url + "/wizard?capture_s=1")
        motion.acc((3.0, 3.0, 8.8))  # in the hand, tilted: no pose yet
        page.click("#start-btn")
        # Held tilted: the instruction says so in words, and the large picture shows the pose to put it in.
        expect(page.locator("#instruction")).to_contain_text("away from flat, screen up: rest it flat on that side")
        expect(page.locator("#live-pose")).to_have_attribute("data-pose", "next +z")
        assert page.text_content("#live-pose-words") == "Next: flat, screen up"
        assert page.locator("#live-pose svg").bounding_box()["width"] >= 170  # the large picture, not a thumbnail
        note = page.text_content("#instruction-code")
        assert note == "+z up. Still to do: -x, +x, -y, +y, -z, +z (the axis pointing up)."
        assert page.evaluate("getComputedStyle(document.querySelector('#instruction-code')).color") == "rgb(85, 85, 85)"
        shot(page, "wizard_next_pose_before_the_move_390")
        # Thumbnails: words under each, a grey code, two rows of three, pictures that differ.
        words = page.locator("#poses .pose-words").all_text_contents()
        assert words == ["right edge down", "left edge down", "upside down", "standing", "screen down", "screen up"]
        boxes = [page.locator(f"#poses li[data-pose='{p}'] .pic svg").bounding_box() for p in ("-x", "+x", "-y")]
        assert all(b["width"] >= 90 for b in boxes) and len({round(b["y"]) for b in boxes}) == 1
        assert page.locator("#poses li[data-pose='-z']").bounding_box()["y"] > boxes[0]["y"] + 50  # the second row
        pics = page.eval_on_selector_all("#poses .pic", "(ps) => ps.map((p) => p.innerHTML)")
        assert len(set(pics)) == 6
        motion.acc(reading("+z"))
        wait_captured(page, "+z")
        expect(page.locator("#instruction")).to_contain_text(
            "Flat, screen up: captured. Next: put the phone flat, screen down (or on any side still to do)."
        )
        motion.acc((3.0, 3.0, 8.8))  # picked up: the next pose is pictured before it is turned
        expect(page.locator("#live-pose")).to_have_attribute("data-pose", "next -z")
        assert page.text_content("#live-pose-words") == "Next: flat, screen down"
        assert not re.search(r"[+-][xyz]\b", page.text_content("#instruction"))
        problems = layout_problems(page, "wizard_next_pose", 390)
        assert not problems, "\n".join(problems)
    finally:
        context.close()
