"""The free-pose wizard (/wizard?protocol=free) in real headless Chromium, the phone's accelerometer fed
through the DevTools protocol's sensor overrides (rounded by Chromium to 0.1 m/s²), against a real
trical server: the sphere fills, the advice appears, the flow ends at the target or by Finish, and the
calibration recovers the simulated phone."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from playwright.sync_api import expect

from app.calibration.still.advice import fibonacci_sphere
from app.workflows.still import calibrate_unknown
from tests.e2e.conftest import shot
from tests.e2e.source_words import assert_only_its_words
from tests.e2e.test_wizard import X_TRUE, Y_TRUE, G, Motion, captures_sent, chromium_round
from tests.live_server import LiveServer

UPS = fibonacci_sphere(14)  # well spread up-directions
WIDTHS = (320, 390, 1280)


def reading(up) -> np.ndarray:
    """The simulated phone at rest with ``up`` up: m = X f + y with f = g·up."""
    return X_TRUE @ (G * np.asarray(up)) + Y_TRUE


def shots(page, name: str) -> None:
    """A screenshot of the state at each width, back at the phone's width after; no board's words."""
    if page.locator("[data-source]").count():  # a wizard page (not the start page's upload)
        assert_only_its_words(page, "phone")
    for width in WIDTHS:
        page.set_viewport_size({"width": width, "height": 720})
        shot(page, f"wizard_free_{name}_{width}")
        assert page.evaluate("document.documentElement.scrollWidth") <= width, f"{name} scrolls sideways at {width} px"
    page.set_viewport_size({"width": 360, "height": 640})


def put_down(page, motion, k: int) -> None:
    """Rest the phone with UPS[k] up until the page has captured it as pose k + 1."""
    motion.acc(reading(UPS[k]))
    page.wait_for_selector(f'#free-count[data-count="{k + 1}"]', state="attached", timeout=20_000)


def fitted(k: int):
    """The triangular fit of what Chromium handed the page for the first ``k`` poses."""
    return calibrate_unknown(
        "triangular", np.array([chromium_round(reading(u)) for u in UPS[:k]]), unit="m/s^2", gravity=G
    )


def check_recovers_the_phone(cal: dict, k: int) -> None:
    result, _ = fitted(k)
    np.testing.assert_allclose(cal["model"]["K"], result.K, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(cal["model"]["o"], result.o, rtol=1e-6, atol=1e-9)
    assert cal["metrics"]["cv_error_mg"] == pytest.approx(result.metrics["cv_error_mg"], rel=1e-6)
    # a = K (m + o) undoes m = X a + y up to a rotation (a magnitude model cannot see one): K X is
    # orthogonal and K (y + o) = 0, within what the 0.1 m/s² rounding of the readings allows.
    K, o = np.array(cal["model"]["K"]), np.array(cal["model"]["o"])
    R = K @ X_TRUE
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=0.01)
    np.testing.assert_allclose(K @ (Y_TRUE + o), 0.0, atol=0.03)


@pytest.fixture
def server_5mg(tmp_path):
    # 12 poses rounded to 0.1 m/s² give 3–4 mg on new orientations: a 5 mg target is reached at 12.
    s = LiveServer({"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}", "TRICAL_FREE_TARGET_MG": "5"}).start()
    yield s
    s.stop()


def test_free_poses_until_the_target(page, server_5mg):
    server = server_5mg
    sent = captures_sent(page)
    motion = Motion(page)
    page.goto(server.url + "/wizard?protocol=free&capture_s=1")
    shots(page, "start")
    assert "12 or more still poses" in page.text_content("#start")
    motion.acc(reading(UPS[0]))
    page.click("#start-btn")
    page.wait_for_selector('#free-count[data-count="1"]', state="attached", timeout=20_000)
    assert page.locator("#sphere circle.covered").count() == 1
    assert page.locator("#free-advice li").count() == 3
    assert "before the first estimate" in page.text_content("#free-count")
    for k in range(1, 3):
        put_down(page, motion, k)
    shots(page, "three_poses")

    # Back near pose 2 (5° off): the page refuses it without sending, and says to turn further.
    near = UPS[1] + np.tan(np.radians(5)) * np.cross(UPS[1], [0, 0, 1]) / np.linalg.norm(np.cross(UPS[1], [0, 0, 1]))
    motion.acc((1.0, 2.0, 9.0))
    motion.acc(reading(near / np.linalg.norm(near)))
    expect(page.locator("#instruction")).to_contain_text("within 10° of a pose already captured", timeout=10_000)
    shots(page, "too_close")
    page.wait_for_timeout(2500)  # longer than hold + capture
    assert len(sent) == 3

    for k in range(3, 11):
        put_down(page, motion, k)
    assert page.locator("#sphere circle.covered").count() == 11
    assert "mg expected on new orientations" in page.text_content("#free-count")
    advice = page.eval_on_selector_all("#free-advice li", "ls => ls.map(l => l.textContent)")
    assert len(advice) == 3 and all(" up (" in a for a in advice)
    assert page.locator("#sphere g.advised").count() == 3
    assert page.is_enabled("#free-finish")
    shots(page, "eleven_poses")

    motion.acc(reading(UPS[11]))  # the twelfth: 3–4 mg < 5 mg, the target is reached
    page.wait_for_selector("#downloads[data-ready=true]", timeout=30_000)
    finish = page.text_content("#result-finish")
    assert finish.startswith("Target reached: ") and finish.endswith(" mg on new orientations.")
    assert page.get_attribute("#result-finish", "data-reason") == "target"
    assert page.locator("#result-advice li").count() == 3
    assert "generalized variance" in page.text_content("#result-advice")
    assert page.locator("#norm-table tbody tr").count() == 12
    shots(page, "result")

    with page.expect_download() as info:
        page.click("#downloads a[data-format=json]")
    doc = json.loads(Path(info.value.path()).read_text())
    saved = json.loads(page.evaluate("localStorage.getItem('trical.wizard.free')"))
    r = page.request.get(
        f"{server.url}/api/v1/calibrations/{doc['id']}", headers={"Authorization": f"Bearer {saved['token']}"}
    )
    cal = r.json()
    assert cal["finish"]["reason"] == "target" and cal["finish"]["poses"] == 12
    check_recovers_the_phone(cal, 12)
    assert [c.get("position") for c in sent] == [None] * 12  # poses are numbered by the server
    assert page.errors == []


def test_finish_before_the_target_says_it_stopped(page, server):
    motion = Motion(page)
    page.goto(server.url + "/wizard?protocol=free&capture_s=1")
    motion.acc(reading(UPS[0]))
    page.click("#start-btn")
    page.wait_for_selector('#free-count[data-count="1"]', state="attached", timeout=20_000)
    for k in range(1, 9):
        put_down(page, motion, k)
    assert page.is_disabled("#free-finish") and page.text_content("#free-finish") == "Finish (from 10 poses)"
    put_down(page, motion, 9)
    put_down(page, motion, 10)
    expect(page.locator("#free-finish")).to_have_text("Finish now")
    page.click("#free-finish")
    page.wait_for_selector("#downloads[data-ready=true]", timeout=30_000)
    finish = page.text_content("#result-finish")
    assert finish.startswith("Stopped at 11 poses: ") and finish.endswith(
        "mg expected on new orientations, target 2 mg."
    )
    assert page.get_attribute("#result-finish", "data-reason") == "stopped"
    shots(page, "stopped")
    saved = json.loads(page.evaluate("localStorage.getItem('trical.wizard.free')"))
    session = page.request.get(
        f"{server.url}/api/v1/sessions/{saved['id']}", headers={"Authorization": f"Bearer {saved['token']}"}
    ).json()
    cal = page.request.get(
        f"{server.url}/api/v1/calibrations/{session['calibration_id']}",
        headers={"Authorization": f"Bearer {saved['token']}"},
    ).json()
    assert cal["finish"]["reason"] == "stopped"
    check_recovers_the_phone(cal, 11)
    assert page.errors == []
