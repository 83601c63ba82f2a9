"""The page in WebKit, the engine of every iPhone browser: WebKitGTK's MiniBrowser (Debian's
webkit2gtk-driver, as recent a WebKit as Safari's) driven through WebKitWebDriver (W3C WebDriver,
via Selenium) on an Xvfb display, against a real trical server.

WebKitGTK has no DeviceMotionEvent: `tests/e2e/phone_shim.js` defines one, dispatches the events itself at
60 Hz in iOS's sign, stubs iOS's `DeviceMotionEvent.requestPermission`, and observes the capture
requests the page sends. `make test` installs webkit2gtk-driver and xvfb when they are missing;
without them these tests fail loudly. Screenshots go to test-artifacts/webkit_*.png.
"""

from __future__ import annotations

import json
import os
import re
import tempfile
import time
from pathlib import Path

import httpx
import pytest

from tests.e2e.conftest import ARTIFACTS, phone_shim
from tests.e2e.test_wizard import IPHONE_UA
from tests.processes import ProcessFailed, check_alive, failure, start_xvfb, stop

WEBKIT_DRIVER = os.environ.get("TRICAL_WEBKIT_DRIVER", "/usr/bin/WebKitWebDriver")
XVFB = os.environ.get("TRICAL_XVFB", "/usr/bin/Xvfb")
MINIBROWSERS = [Path(f"/usr/lib/x86_64-linux-gnu/webkit2gtk-{v}/MiniBrowser") for v in ("4.1", "4.0", "6.0")]
SHIM = phone_shim("ios")
START_TIMEOUT_S = 20.0  # Xvfb writes its display number well within a second, even on a loaded machine
COMMAND_TIMEOUT_S = 90  # a MiniBrowser session's start, and every WebDriver command (scripts time out at 30 s)
PHONE = (390, 844)  # an iPhone's viewport in CSS px; WebKitGTK's window is at least 334 px wide


def minibrowser() -> Path:
    for path in MINIBROWSERS:
        if path.exists():
            return path
    pytest.fail(
        f"WebKitGTK's MiniBrowser is not installed ({', '.join(map(str, MINIBROWSERS))}): "
        "run `make test` (it installs Debian's webkit2gtk-driver)"
    )


class Display:
    """A running Xvfb: its display name, the process and its log, checked before each use."""

    def __init__(self):
        self.process, self.name, self.log = start_xvfb(XVFB, timeout_s=START_TIMEOUT_S)

    def check_alive(self, when: str) -> None:
        check_alive("Xvfb", self.process, self.log, when)

    def close(self) -> None:
        stop(self.process)


@pytest.fixture(scope="session")
def xvfb_display():
    """A virtual X display for the MiniBrowser: Xvfb picks a free number and writes it to a pipe."""
    for path in (WEBKIT_DRIVER, XVFB):
        if not Path(path).exists():
            pytest.fail(f"{path} is missing: run `make test` (it installs Debian's webkit2gtk-driver and xvfb)")
    try:
        display = Display()
    except ProcessFailed as exc:
        pytest.fail(str(exc))
    yield display
    display.close()


class WebKitPhone:
    """An iPhone's browser as far as the page can tell: WebKit, an iPhone's user agent and viewport,
    and the motion of `phone_shim.js`."""

    def __init__(self, driver):
        self.driver = driver

    def open(self, url: str, size=PHONE) -> None:
        self.resize(*size)
        self.driver.get(url)
        # Laid out and painted before the first tap: a WebDriver click is a pointer event at the
        # element's position, and one sent while the page still lays out can land beside it.
        self.wait("document.readyState === 'complete'", 10, "the page's load")
        self.driver.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "requestAnimationFrame(() => requestAnimationFrame(() => done()));"
        )

    def with_motion(self) -> None:
        """Give the open page the shim's motion sensors (before Start is tapped, as iOS has them from load)."""
        self.driver.execute_script(SHIM)

    def resize(self, width: int, height: int) -> None:
        self.driver.set_window_rect(0, 0, width, height)
        for _ in range(50):
            if self.driver.execute_script("return innerWidth") == width:
                return
            time.sleep(0.05)
        raise AssertionError(f"the MiniBrowser's viewport did not become {width} px wide")

    def js(self, expression: str, *args):
        return self.driver.execute_script(f"return ({expression});", *args)

    def set(self, acc, gyr=None) -> None:
        """The readings from now on, in the W3C sign (m/s², deg/s); the shim reports them as iOS does."""
        self.driver.execute_script(
            "window.__phone.set(arguments[0], arguments[1]);",
            [float(v) for v in acc],
            None if gyr is None else [float(v) for v in gyr],
        )

    def turn(self, axis, peak_deg_s: float, then_acc) -> None:
        """A quarter turn about `axis` (sensor frame), played by the page's timer; then at rest reading `then_acc`."""
        self.driver.execute_script(
            "window.__phone.turn(arguments[0], arguments[1], arguments[2]);",
            [float(v) for v in axis],
            float(peak_deg_s),
            [float(v) for v in then_acc],
        )

    def noise(self, acc_sd: float, gyr_sd: float, seed: int) -> None:
        """White noise on every sample from now on (m/s², deg/s), from a generator seeded with `seed`."""
        self.driver.execute_script(
            "window.__phone.noise(arguments[0], arguments[1], arguments[2]);", float(acc_sd), float(gyr_sd), int(seed)
        )

    def wait(self, expression: str, timeout: float = 20.0, what: str = "") -> None:
        """Wait until the JavaScript `expression` is true; on timeout say what the page shows."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            if self.js(expression):
                return
            time.sleep(0.05)
        said = self.js(
            "[...document.querySelectorAll('#instruction, #status, #problem')]"
            ".map(e => e.id + ': ' + e.textContent.trim())"
        )
        raise AssertionError(
            f"{what or expression} not within {timeout:g} s; the page says {said}; errors {self.errors()}"
        )

    def wait_for(self, selector: str, timeout: float = 20.0) -> None:
        self.wait(f"document.querySelector({json.dumps(selector)}) !== null", timeout, selector)

    def text(self, selector: str) -> str:
        return self.js("document.querySelector(arguments[0]).textContent", selector)

    def click(self, selector: str) -> None:
        """A tap: WebDriver's pointer click at the element's centre, once it is in view and still."""
        element = self.driver.find_element("css selector", selector)
        self.driver.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "arguments[0].scrollIntoView({block: 'center', behavior: 'instant'});"
            "requestAnimationFrame(() => requestAnimationFrame(() => done()));",
            element,
        )
        element.click()

    def tap_start(self) -> None:
        """Tap Start, and see that the page asked for motion access from that tap (as iOS requires)."""
        self.click("#start-btn")
        self.wait("window.__phone.permissionCalls.length > 0", 5, "the permission request from the Start tap")
        calls = self.js("window.__phone.permissionCalls")
        assert calls == [True], f"motion access asked {len(calls)} times, within a user activation: {calls}"

    def captures(self) -> list[dict]:
        return self.js("window.__phone.captures")

    def errors(self) -> list[str]:
        return self.js("window.__phone ? window.__phone.errors : []")

    def download(self, fmt: str) -> str:
        """The file behind the page's download link for `fmt`: the Blob its blob: URL was made from."""
        return self.driver.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "window.__phone.blobText(document.querySelector(`#downloads a[data-format=${arguments[0]}]`).href)"
            ".then(done, e => done('failed: ' + e));",
            fmt,
        )

    def saved(self, protocol: str) -> dict:
        return json.loads(self.js(f"localStorage.getItem('trical.wizard.{protocol}')"))

    def stored(self, server, protocol: str, path: str = "") -> dict:
        """GET `path` of the API (default: the flow's session) with the session token the page saved."""
        saved = self.saved(protocol)
        r = httpx.get(
            f"{server.url}/api/v1{path or '/sessions/' + saved['id']}",
            headers={"Authorization": f"Bearer {saved['token']}"},
        )
        assert r.status_code == 200, r.text
        return r.json()

    def scrolls_sideways(self) -> bool:
        return self.js("document.documentElement.scrollWidth > innerWidth")

    def shot(self, name: str) -> Path:
        """The whole page (the window made as tall as the page for the picture) under test-artifacts/."""
        ARTIFACTS.mkdir(exist_ok=True)
        path = ARTIFACTS / ("webkit_" + re.sub(r"[^A-Za-z0-9_.-]", "_", name) + ".png")
        width, height = self.js("[innerWidth, innerHeight]")
        self.driver.set_window_rect(0, 0, width, min(self.js("document.documentElement.scrollHeight"), 6000))
        self.driver.save_screenshot(str(path))
        self.driver.set_window_rect(0, 0, width, height)
        return path


def start_driver(display: Display, browser: Path | None = None, timeout_s: float = COMMAND_TIMEOUT_S):
    """WebKitWebDriver on `display` and a MiniBrowser session through it, each within a time bound.

    Selenium waits for the driver's port a bounded time, but by default waits for the new session (the
    MiniBrowser's start) and for every command with no bound at all: a MiniBrowser that cannot start
    (no display, a flag it does not parse) would hang the suite. The connection here has a timeout.
    """
    from selenium import webdriver
    from selenium.common.exceptions import WebDriverException
    from selenium.webdriver.remote.client_config import ClientConfig
    from selenium.webdriver.remote.remote_connection import RemoteConnection
    from selenium.webdriver.webkitgtk.service import Service

    display.check_alive("before the MiniBrowser started")
    options = webdriver.WebKitGTKOptions()
    options.binary_location = str(browser or minibrowser())
    options.add_argument("--automation")
    options.add_argument("--full-screen")  # no toolbar: the window is the viewport, as narrow as 334 px
    options.add_argument(f"--user-agent={IPHONE_UA}")
    log = Path(tempfile.mkstemp(prefix="trical-webkitwebdriver-", suffix=".log")[1])
    service = Service(executable_path=WEBKIT_DRIVER, env={**os.environ, "DISPLAY": display.name}, log_output=str(log))
    try:
        service.start()
    except WebDriverException as exc:
        service.stop()
        raise failure("WebKitWebDriver", f"did not start ({exc.msg})", log) from None
    config = ClientConfig(remote_server_addr=service.service_url, timeout=timeout_s)
    try:
        driver = webdriver.Remote(command_executor=RemoteConnection(client_config=config), options=options)
    except Exception as exc:  # the session's start timed out or was refused: say why, with both logs
        service.stop()
        display.check_alive("while the MiniBrowser started")
        raise failure(
            "WebKitWebDriver",
            f"started no MiniBrowser session within {timeout_s:g} s ({type(exc).__name__}: {exc})",
            log,
        ) from None
    driver.set_script_timeout(30)
    return driver, service


@pytest.fixture
def webkit(xvfb_display):
    """A fresh MiniBrowser (its own storage) through WebKitWebDriver, as an iPhone."""
    try:
        driver, service = start_driver(xvfb_display)
    except ProcessFailed as exc:
        pytest.fail(str(exc))
    try:
        yield WebKitPhone(driver)
    finally:
        try:
            driver.quit()
        finally:
            service.stop()
