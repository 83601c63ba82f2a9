"""The compass wizard (/wizard?protocol=compass) in real headless Chromium against a real trical server:
without a magnetometer the page says so and points to the upload; with one (the Generic Sensor API's
Magnetometer, enabled by a Chromium flag and fed through the DevTools protocol's sensor overrides) a
slow turn fills the sphere, the page calibrates by itself and the result recovers the simulated
phone; and a phyphox magnetometer export uploaded on the start page shows the sphere before and after."""

from __future__ import annotations

import datetime
import json
from pathlib import Path

import numpy as np
import pytest
from playwright.sync_api import expect

from app.geomag import reference_field
from simulations.magnetometer import random_soft_iron
from tests.e2e.conftest import CHROMIUM, CHROMIUM_ARGS, LAUNCH_TIMEOUT_MS, shot
from tests.e2e.source_words import assert_only_its_words

WIDTHS = (320, 390, 1280)
WIDEST = (
    "() => [...document.querySelectorAll('body *')].filter((e) => e.getBoundingClientRect().right > innerWidth + 0.5)"
    ".slice(-3).map((e) => `${e.tagName}#${e.id}.${e.className} ${e.textContent.slice(0, 40)}`).join(' | ')"
)
MAG_FLAGS = ["--enable-features=GenericSensorExtraClasses", "--enable-generic-sensor-extra-classes"]
HELSINKI = {"latitude": 60.17, "longitude": 24.94}
B_TRUE = np.array([23.5, -41.2, 12.8])
N_TURN = 160


def spiral(n: int, turns: float = 8.0) -> np.ndarray:
    """A slow turn: the field's direction in the device frame spirals from +z to −z in ``turns`` loops,
    consecutive readings about 15° apart."""
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    phi = 2.0 * np.pi * turns * k / n
    r = np.sqrt(1.0 - z * z)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def turn(seed: int, field_ut: float, n: int = N_TURN, noise_ut: float = 0.3):
    """Raw readings m = M⁻¹ h + b + ε of the spiral turn, with the truth (M, b)."""
    rng = np.random.default_rng(seed)
    M = random_soft_iron(rng)
    h = field_ut * spiral(n)
    return h @ np.linalg.inv(M).T + B_TRUE + rng.normal(0.0, noise_ut, (n, 3)), M


def shots(page, name: str) -> None:
    """A screenshot of the state at each width, no sideways scrolling, back at the phone's width after; no
    board's words (a phone's page)."""
    if page.locator("[data-source]").count():  # a wizard page (not the start page's upload)
        assert_only_its_words(page, "phone")
    for width in WIDTHS:
        page.set_viewport_size({"width": width, "height": 720})
        shot(page, f"wizard_compass_{name}_{width}")
        assert page.evaluate("() => document.documentElement.scrollWidth <= innerWidth"), (
            f"{name} scrolls sideways at {width} px: {page.evaluate(WIDEST)}"
        )
    page.set_viewport_size({"width": 390, "height": 720})


@pytest.fixture(scope="module")
def mag_browser(browser):
    """A second Chromium, from the same Playwright, with the Generic Sensor API's extra classes on."""
    b = browser.browser_type.launch(
        executable_path=CHROMIUM, args=[*CHROMIUM_ARGS, *MAG_FLAGS], timeout=LAUNCH_TIMEOUT_MS
    )
    yield b
    b.close()


@pytest.fixture
def mag_page(mag_browser, server):
    context = mag_browser.new_context(viewport={"width": 390, "height": 720}, geolocation=HELSINKI)
    context.grant_permissions(["geolocation", "magnetometer"], origin=server.url)
    pg = context.new_page()
    errors: list[str] = []
    pg.on("pageerror", lambda exc: errors.append(str(exc)))
    pg.errors = errors
    yield pg
    context.close()


def magnetometer(page):
    """Chromium's magnetometer overridden through the DevTools protocol: a function that sets its
    reading (µT)."""
    cdp = page.context.new_cdp_session(page)
    cdp.send("Emulation.setSensorOverrideEnabled", {"enabled": True, "type": "magnetometer"})

    def feed(m):
        x, y, z = (float(v) for v in m)
        cdp.send(
            "Emulation.setSensorOverrideReadings",
            {"type": "magnetometer", "reading": {"xyz": {"x": x, "y": y, "z": z}}},
        )

    return feed


def coverage_of(page) -> float:
    return float(page.get_attribute("#compass-coverage", "data-coverage"))


def test_without_a_magnetometer_the_page_points_to_the_upload(page, server):
    page.goto(server.url + "/wizard?protocol=compass")
    expect(page.locator("#compass-none")).to_be_visible()
    assert page.is_hidden("#compass-start")
    text = page.text_content("#compass-none")
    assert "no magnetometer" in text and "phyphox" in text and "Sensor Logger" in text
    assert "Magnetometer (uncalibrated)" in text
    assert page.get_attribute("#compass-upload-link", "href") == "/"
    shots(page, "no_magnetometer")
    assert page.errors == []


def test_a_full_turn_fills_the_sphere_and_recovers_the_phone(mag_page, server):
    page = mag_page
    today = datetime.datetime.now(datetime.UTC).date()
    field = reference_field(today, HELSINKI["latitude"], HELSINKI["longitude"]).field_ut
    readings, M_true = turn(11, field)
    sent: list[dict] = []
    page.on("request", lambda r: sent.append(r.post_data_json) if r.url.endswith("/api/v1/calibrations") else None)
    feed = magnetometer(page)

    page.goto(server.url + "/wizard?protocol=compass")
    expect(page.locator("#compass-start-btn")).to_be_visible()
    assert page.is_hidden("#compass-none")
    page.click("#compass-where")
    expect(page.locator("#compass-where-text")).to_contain_text("60.17°, 24.94°")
    page.fill("#device-name", "phone compass")
    shots(page, "start")
    feed(readings[0])
    page.click("#compass-start-btn")
    page.wait_for_function("() => document.querySelector('#compass-coverage').dataset.count === '1'")
    seen = []
    for k, m in enumerate(readings[1:], start=2):
        feed(m)
        page.wait_for_function(
            f"() => Number(document.querySelector('#compass-coverage').dataset.count) >= {k}"
            " || !document.querySelector('#result').hidden"
        )
        if k % 20 == 0 and page.is_hidden("#result"):
            page.wait_for_timeout(200)  # the sphere is redrawn at most every 150 ms
            seen.append(coverage_of(page))
        if k == N_TURN // 2:
            assert 0.3 <= coverage_of(page) <= 0.8, coverage_of(page)
            assert "Still missing:" in page.text_content("#compass-missing")
            assert "back" in page.text_content("#compass-missing")  # the spiral has not reached −z yet
            shots(page, "half_covered")
        if not page.is_hidden("#result"):
            break
    assert seen == sorted(seen) and seen[-1] > seen[0], seen  # the coverage climbs
    expect(page.locator("#result")).to_be_visible(timeout=20_000)
    assert len(sent) == 1
    body = sent[0]
    assert body["method"] == "magnetometer" and body["latitude_deg"] == HELSINKI["latitude"]
    assert body["device_id"] == "phone compass"
    assert body["longitude_deg"] == HELSINKI["longitude"] and body["date"] == today.isoformat()
    n = len(body["mag"])
    assert 50 <= n <= N_TURN
    # the readings as Chromium handed them to the page: each component rounded to 0.01 µT
    np.testing.assert_allclose(body["mag"], np.round(readings[:n], 2), atol=1e-9)
    page.wait_for_selector("#downloads[data-ready=true]")
    with page.expect_download() as info:
        page.click("#downloads a[data-format='json']")
    full = page.request.get(
        f"{server.url}/api/v1/calibrations/{json.loads(Path(info.value.path()).read_text())['id']}"
    ).json()
    # The verdict first, in µT on new directions; the file for the use chosen (a phone app: JSON) under it.
    assert page.text_content("#verdict-words") == full["verdict"]["words"]
    assert full["verdict"]["words"].startswith("Apply it: error of the field strength on new directions ")
    assert page.get_attribute("#use-file", "data-format") == "json"
    assert full["model"]["type"] == "magnetometer" and full["metrics"]["field_source"] == "model"
    assert full["metrics"]["field_ut"] == pytest.approx(field, rel=1e-9)
    assert full["metrics"]["coverage"] >= 0.9
    np.testing.assert_allclose(full["model"]["b"], B_TRUE, atol=1.0)
    np.testing.assert_allclose(full["model"]["M"], M_true, atol=0.02)
    expect(page.locator("#result-ok")).to_have_text(f"Calibration {full['id']} passed its checks.")
    summary = page.text_content("#result-summary")
    assert "before →" in summary and f"{full['metrics']['cv_error_ut']:.2f} µT" in summary
    assert page.locator("#result-mag svg.mag-sphere").count() == 2
    assert page.locator("#downloads a[data-format='json']").count() == 1
    shots(page, "result")
    # Start over asks first, in place (the compass page binds the wizard's two taps), then turns afresh.
    page.click("#start-over")
    expect(page.locator("#start-over-ask")).to_be_visible()
    expect(page.locator("#start-over-no")).to_be_focused()
    page.click("#start-over-no")
    expect(page.locator("#start-over")).to_be_focused()
    page.click("#start-over")
    page.click("#start-over-yes")
    page.wait_for_url("**/wizard?protocol=compass")
    expect(page.locator("#compass-start-btn")).to_be_visible()
    assert page.errors == []


def test_a_live_turn_checks_the_phone_s_calibration_from_its_page(mag_page, server):
    """Issue 47: a 60-second turn on the page is enough for the compass's check. The calibration's page offers the
    live turn; the compass page then checks the calibration on it (no new calibration), here one whose hard iron
    moved by 8 µT: calibrate again, naming the hard iron."""
    page = mag_page
    readings, M_true = turn(11, 50.0)
    cal = page.request.post(
        f"{server.url}/api/v1/calibrations",
        data={"method": "magnetometer", "mag": readings.tolist(), "field_ut": 50.0, "source": "phone"},
    ).json()
    page.goto(f"{server.url}/c/{cal['id']}")
    expect(page.locator("#check-live")).to_be_visible()
    expect(page.locator("#check-live-link")).to_have_text("Turn the phone for a minute")
    shots(page, "check_offered")
    page.click("#check-live-link")
    page.wait_for_url(f"**/wizard?protocol=compass&source=phone&check={cal['id']}")
    expect(page.locator("#compass-start")).to_contain_text("makes no new calibration")
    assert page.locator("#compass-where").count() == 0 and page.text_content("#compass-solve") == "Check now"
    shots(page, "check_start")
    # The same phone turned again, its hard iron moved by 8 µT along z.
    noise = np.random.default_rng(12).normal(0.0, 0.3, (N_TURN, 3))
    moved = 50.0 * spiral(N_TURN) @ np.linalg.inv(M_true).T + B_TRUE + [0.0, 0.0, 8.0] + noise
    created: list[str] = []
    page.on("request", lambda r: created.append(r.url) if r.url.endswith("/api/v1/calibrations") else None)
    feed = magnetometer(page)
    feed(moved[0])
    page.click("#compass-start-btn")
    page.wait_for_function("() => document.querySelector('#compass-coverage').dataset.count === '1'")
    for k, m in enumerate(moved[1:], start=2):
        feed(m)
        page.wait_for_function(
            f"() => Number(document.querySelector('#compass-coverage').dataset.count) >= {k}"
            " || !document.querySelector('#compass-check').hidden"
        )
        if not page.is_hidden("#compass-check"):
            break
    expect(page.locator("#compass-check")).to_be_visible(timeout=20_000)
    assert page.get_attribute(".check-result", "data-verdict") == "calibrate_again"
    text = page.inner_text("#check-result")
    assert "Verdict: calibrate again." in text and "Drifted: hard iron" in text, text
    assert created == []  # the turn checked the calibration and made none
    expect(page.locator("#compass-check a[href='/c/" + cal["id"] + "']")).to_be_visible()
    shots(page, "check_result")
    assert page.errors == []


def test_a_phyphox_upload_shows_the_sphere_before_and_after(page, server, tmp_path):
    readings, _M_true = turn(12, 48.0, n=400)
    t = np.arange(len(readings)) / 10.0
    path = tmp_path / "Raw Data.csv"
    header = '"Time (s)","Magnetic field x (µT)","Magnetic field y (µT)","Magnetic field z (µT)"'
    path.write_text(
        header + "\n" + "\n".join(",".join(f"{v:.6f}" for v in row) for row in np.column_stack([t, readings])) + "\n",
        encoding="utf-8",
    )
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(path))
    page.click("#upload-form button[type=submit]")
    expect(page.locator("#compass-recording")).to_be_visible()
    assert page.is_hidden("#calibrate-recording")  # no accelerometer: nothing still to calibrate from
    page.click("#compass-recording")
    expect(page.locator("#result")).to_be_visible()
    expect(page.locator("#result-mag-box")).to_be_visible()
    assert page.locator("#result-mag svg.mag-sphere.before").count() == 1
    assert page.locator("#result-mag svg.mag-sphere.after").count() == 1
    assert page.locator("#result-mag svg.before path.face.covered").count() > 0
    b = [float(page.text_content(f"#result-b tr:nth-child({i}) td")) for i in (1, 2, 3)]
    np.testing.assert_allclose(b, B_TRUE, atol=1.0)
    shots(page, "upload_result")
    assert page.errors == []
