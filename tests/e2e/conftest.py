"""Real headless Chromium (Debian's package, driven by Playwright) against a real trical server.

`make test` installs Debian's chromium when it is missing; without it these tests fail loudly.
Screenshots of every step go to test-artifacts/.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from tests.e2e.axe import axe_context
from tests.live_server import ROOT, LiveServer, free_port

CHROMIUM = os.environ.get("TRICAL_CHROMIUM", "/usr/bin/chromium")
ARTIFACTS = ROOT / "test-artifacts"
LAUNCH_TIMEOUT_MS = 60_000  # Playwright's launch fails with Chromium's own output past this
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


def phone_shim(sign: str) -> str:
    """The script of `phone_shim.js` (motion played by the page's timer), reporting in iOS's sign
    (up reads −g) or the W3C sign (up reads +g)."""
    assert sign in ("ios", "w3c"), sign
    prefix = "window.__phoneSign = 1;\n" if sign == "w3c" else ""
    return prefix + (Path(__file__).parent / "phone_shim.js").read_text()


@pytest.fixture(scope="session")
def browser():
    if not Path(CHROMIUM).exists():
        pytest.fail(f"Chromium is not installed at {CHROMIUM}: run `make test` (it installs Debian's chromium)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, timeout=LAUNCH_TIMEOUT_MS)
        yield b
        b.close()


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """One real server (its own SQLite file) for the tests of a module: each test has its own browser
    context, so its own sessions and storage, and no test reads what another wrote. Starting a server
    costs a process and the application's imports; one a test cost minutes of the suite."""
    db = tmp_path_factory.mktemp("server") / "trical.db"
    # As `make run` serves: the desktop's listener on loopback and the phone's door (on a free port of its own).
    s = LiveServer({"TRICAL_DATABASE_URL": f"sqlite:///{db}", "TRICAL_PHONE_PORT": str(free_port())}).start()
    yield s
    try:
        s.check_alive("during the test")
    finally:
        s.stop()


def watched_page(context):
    """A new page of ``context`` whose script errors and console errors collect in ``page.errors``."""
    pg = context.new_page()
    errors: list[str] = []
    pg.on("pageerror", lambda exc: errors.append(str(exc)))
    pg.on("console", lambda msg: errors.append(msg.text) if msg.type == "error" else None)
    pg.errors = errors
    return pg


@pytest.fixture
def page(browser, request):
    context = browser.new_context(viewport={"width": 360, "height": 640}, device_scale_factor=1)
    yield watched_page(context)
    context.close()


def shot(page, name: str, request=None) -> Path:
    """Save a full-page screenshot as a test artifact."""
    ARTIFACTS.mkdir(exist_ok=True)
    path = ARTIFACTS / (re.sub(r"[^A-Za-z0-9_.-]", "_", name) + ".png")
    # Two frames first: after a change of the viewport's width, Chromium may not yet have repainted a scrolled
    # box (the paste-ready lines came out blank at 390 px although their text was there).
    page.evaluate("() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")
    page.screenshot(path=str(path), full_page=True)
    return path


def tab_to(page, selector: str, limit: int = 40) -> None:
    """Press Tab until the element ``selector`` has the focus (keyboard reachability)."""
    for _ in range(limit):
        page.keyboard.press("Tab")
        if page.evaluate("(s) => document.activeElement === document.querySelector(s)", selector):
            return
    raise AssertionError(f"Tab never reached {selector}")


@pytest.fixture
def axe_page(browser):
    """A phone-width page whose CSP lets axe in (the layout checks), with its errors collected."""
    context = axe_context(browser, viewport={"width": 390, "height": 900}, device_scale_factor=1)
    yield watched_page(context)
    context.close()
