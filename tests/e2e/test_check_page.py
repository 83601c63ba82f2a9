"""The check control of a calibration's page /c/{id} and the compare view of the history, in real Chromium
against a real server: a compass calibration checked on a new turn whose hard iron moved (the verdict and what
drifted shown), then compared with the calibration of that turn (the real difference marked)."""

from __future__ import annotations

import httpx
import numpy as np
import pytest

from simulations.magnetometer import simulate_session, simulate_turn
from tests.api.test_check_api import turn_csv
from tests.e2e.axe import axe_context
from tests.e2e.conftest import watched_page
from tests.e2e.test_layout import layout_problems


def turn_file(path, m: np.ndarray):
    path.write_bytes(turn_csv(m, rate_hz=20.0))
    return path


@pytest.mark.parametrize("width", [320, 390, 1280])
def test_a_calibration_checked_on_its_page_and_compared_on_the_history(browser, server, tmp_path, width):
    context = axe_context(browser, viewport={"width": width, "height": 844}, device_scale_factor=1)
    try:
        page = watched_page(context)
        checked_and_compared(page, server, tmp_path, width)
    finally:
        context.close()


def checked_and_compared(page, server, tmp_path, width: int) -> None:
    device = f"compass-e2e-{width}"
    m, M, b = simulate_session(51, n=300)
    moved = simulate_turn(np.random.default_rng(8), M, b + [0.0, 0.0, 5.0], n=300)
    with httpx.Client(base_url=server.url, timeout=60) as http:
        first = http.post(
            "/api/v1/calibrations",
            json={"method": "magnetometer", "mag": m.tolist(), "field_ut": 48.0, "device_id": device},
        ).json()
    page.goto(f"{server.url}/c/{first['id']}")
    page.wait_for_selector("#check-card:not([hidden])")
    page.set_input_files("#check-file", str(turn_file(tmp_path / "moved.csv", moved)))
    page.click("#check-form button[type=submit]")
    page.wait_for_selector(".check-result")
    assert page.get_attribute(".check-result", "data-verdict") == "calibrate_again"
    text = page.inner_text("#check-result")
    assert "Verdict: calibrate again." in text and "Drifted: hard iron" in text and "A fresh calibration:" in text
    problems = layout_problems(page, "calibration_checked", width)
    with httpx.Client(base_url=server.url, timeout=60) as http:
        http.post(
            "/api/v1/calibrations",
            json={"method": "magnetometer", "mag": moved.tolist(), "field_ut": 48.0, "device_id": device},
        ).raise_for_status()
    page.goto(f"{server.url}/history?device={device}")
    page.wait_for_selector("#compare-card:not([hidden])")
    page.click("#compare-form button[type=submit]")
    page.wait_for_selector(".comparison-table")
    real = page.eval_on_selector_all(
        ".comparison-table tr[data-real=true] th", "(rows) => rows.map((r) => r.textContent)"
    )
    assert "hard iron z" in real, real
    problems += layout_problems(page, "history_compared", width)
    assert problems == [], "\n".join(problems)
    assert page.errors == []
