"""Layout and accessibility of every page and state reachable without emulating the motion sensors
for long, at a small phone's width (320 px), a common phone's (390 px) and a desktop's (1280 px).

For each page and state, at each width (the one page resized), in real Chromium against a real trical server:
- no horizontal scrolling of the page: ``document.documentElement.scrollWidth <= innerWidth`` (a
  table scrolls in its own box, not the page); a failure names the element that reaches furthest
  right past the viewport;
- axe-core (tests/e2e/axe.py, default rules: WCAG 2 A/AA and best practices) reports no violation;
- every visible button, link, input, select and summary is at least 44 px tall (WCAG 2.5.5's size;
  24 px is 2.5.8's floor). Links inside running text are left out: WCAG 2.5.8 exempts a target in a
  sentence, whose size the line of text sets; a link counts as such when it is displayed inline and
  the paragraph, list item, cell, caption or label that holds it has text besides its own;
- a full-page screenshot is written to test-artifacts/layout_<state>_<width>.png.
"""

from __future__ import annotations

import pytest

from tests.conftest import DATA
from tests.e2e.axe import axe_context, describe, violations
from tests.e2e.conftest import shot
from tests.e2e.source_words import other_source_words
from tests.live_server import LiveServer

WIDTHS = [320, 390, 1280]
MIN_TARGET_PX = 44


@pytest.fixture(scope="module")
def layout_server(tmp_path_factory):
    db = tmp_path_factory.mktemp("layout") / "trical.db"
    s = LiveServer({"TRICAL_DATABASE_URL": f"sqlite:///{db}"}).start()
    yield s
    s.stop()


def start_page(page, url):
    page.goto(url + "/")


def upload_refused(page, url):
    page.goto(url + "/")
    page.set_input_files(
        "#log-file",
        {
            "name": "bad_line.csv",
            "mimeType": "text/csv",  # a bad line, named first
            "buffer": b"acc_x,acc_y,acc_z\n0.1,0.2,9.8\n0.1,abc,9.8\n",
        },
    )
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#upload-msg:has-text('Upload refused')")


def upload_calibrated(page, url):
    page.goto(url + "/")
    page.set_input_files("#log-file", str(DATA / "six_orientations_150hz.csv"))
    page.click("#options-summary")
    page.fill("#log-rate", "150")
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#result:not([hidden])")  # method auto at once
    page.wait_for_selector("#downloads[data-ready=true]")
    page.click("#result-details summary")  # the details open too


def upload_pose_files(page, url):
    """A maker's six pose files chosen at once: the segments' File column and the files' notes."""
    page.goto(url + "/")
    page.set_input_files(
        "#log-file",
        [
            str(DATA / "real" / "mpu6050_pose_files" / f"{axis}_axis_{sign}.csv")
            for axis in "xyz"
            for sign in ("pos", "neg")
        ],
    )
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#result:not([hidden])")
    page.wait_for_selector("#downloads[data-ready=true]")


def upload_counts_compass(page, url):
    """A magnetometer turned by hand, logged in counts: the unit menus say counts and offer the parts."""
    page.goto(url + "/")
    page.set_input_files("#log-file", str(DATA / "real" / "magnetometer" / "tomisuarez2_qmc5883l_turn_every10.csv"))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#result:not([hidden])")


def upload_flight_log(page, url):
    """A PX4 log of a board warming up: its sensors' table, the IMU menu, the temperature curve."""
    import tempfile
    from pathlib import Path

    from tests.e2e.test_flight_log_page import warming_px4_log

    with tempfile.TemporaryDirectory() as tmp:
        log = warming_px4_log(Path(tmp) / "warm_up.ulg")
        page.goto(url + "/")
        page.set_input_files("#log-file", str(log))
        page.click("#upload-form button[type=submit]")
        page.wait_for_selector("#flight:not([hidden])")
        # a still board: it supports the noise of its rest first, which runs at once (nothing else is tried)
        page.wait_for_selector("#supports-list li[data-method=noise][data-ready=true]")
        page.wait_for_selector("#result:not([hidden])", timeout=60_000)


def upload_column_map(page, url):
    page.goto(url + "/")
    page.set_input_files(
        "#log-file",
        {
            "name": "north_east_down.csv",
            "mimeType": "text/csv",
            "buffer": b"north,east,down,pressure,humidity\n0.1,0.2,9.8,1013,45\n0.1,0.2,9.8,1013,45\n",
        },
    )  # five columns the data cannot name
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#columns-map:not([hidden])")


# Six poses of an ideal sensor, each 3° off its axis (tests/calibration/test_trust.py): a calibration
# that must not be applied, so its result offers no file.
TILTED_SIX = """-x -9.7932 0.3660 0.3349
+x 9.7932 -0.4520 -0.1930
-y 0.5121 -9.7932 -0.0012
+y -0.1190 9.7932 0.4978
-z 0.2712 0.4300 -9.7932
+z -0.3740 -0.3520 9.7932"""


def paste_refused_result(page, url):
    page.goto(url + "/")
    page.fill("#paste", TILTED_SIX)
    page.click("#fill")
    page.click("#readings-form button[type=submit]")
    page.wait_for_selector("#result:not([hidden])")
    page.wait_for_selector("#downloads[data-ready=true]", state="attached")
    assert page.get_attribute("#verdict", "data-apply") == "false" and page.locator("#use").is_hidden()


def wizard(query: str = ""):
    def open_wizard(page, url):
        page.goto(url + "/wizard" + query)
        page.wait_for_load_state("networkidle")

    return open_wizard


def docs(page, url):
    page.goto(url + "/docs")
    page.wait_for_selector(".opblock", timeout=20_000)


def board(
    query: str = "?protocol=six&source=board", lines: tuple[str, ...] = (), baud: str | None = None, serial: bool = True
):
    """A wizard page with a board (tests/e2e/board_shim.js, the stand-in for the Web Serial API)
    printing `lines` at 100 a second, connected at `baud`; without `serial`, a browser lacking the API."""

    def open_board(page, url):
        from tests.e2e.test_board import SHIM

        if serial:
            page.add_init_script(SHIM)
        else:
            page.add_init_script("delete Navigator.prototype.serial; delete Navigator.prototype.bluetooth;")
        page.goto(url + "/wizard" + query)
        page.wait_for_load_state("networkidle")
        if not serial:
            return
        page.evaluate("(lines) => window.__board.play(lines, 100)", list(lines))
        if baud:
            page.select_option("#board-baud", baud)
        page.click("#board-usb")
        if lines and not baud:
            page.wait_for_selector("#board-live[data-acc-unit='m/s^2']")
            page.wait_for_timeout(300)  # a redraw of the live view with its plot
        else:
            page.wait_for_selector("#board-msg:not([hidden])", timeout=6_000)

    return open_board


# 20 s of a board's lines: more than the page may take to count their rate (its window, app/io/board/formats.py
# RATE_WINDOW_S, once a loaded machine held the page), as a board prints for as long as it is on. With 6 s of
# lines, a pause of the page early on left too few arrivals after it to decide, and the lines ran out (CI).
UNI = tuple(f"Uni:{0.12 + 0.01 * (k % 3):.2f},-0.05,9.79,0.001,-0.002,0.000,21.5,-3.2,40.1" for k in range(2000))


def start_no_serial(page, url):
    page.add_init_script("delete Navigator.prototype.serial; delete Navigator.prototype.bluetooth;")
    page.goto(url + "/")


# axe's options per state. On /docs one rule is off: Swagger UI writes the API's title as an h1 and
# each tag as an h3 with no h2 between (heading-order, a best practice, not a WCAG criterion), in
# markup that its script builds and that trical could change only by patching Swagger UI.
AXE_OPTIONS = {"docs": {"rules": {"heading-order": {"enabled": False}}}}

STATES = {
    "start": start_page,
    "upload_refused": upload_refused,
    "upload_result": upload_calibrated,
    "upload_column_map": upload_column_map,
    "upload_pose_files": upload_pose_files,
    "upload_counts_compass": upload_counts_compass,
    "upload_flight_log": upload_flight_log,
    "paste_refused_result": paste_refused_result,
    "wizard_six": wizard(),
    "wizard_cube24": wizard("?protocol=cube24"),
    "wizard_free": wizard("?protocol=free"),
    "wizard_compass": wizard("?protocol=compass"),
    "wizard_noise": wizard("?protocol=noise"),
    "board_live": board(lines=UNI),
    "board_silent": board(),
    "board_unreadable": board(lines=UNI, baud="9600"),
    "board_no_serial": board(serial=False),
    "board_compass_live": board("?protocol=compass&source=board", lines=UNI),
    "start_no_serial": start_no_serial,
    "docs": docs,
}

# Elements past the right edge of the viewport that are not inside a box that scrolls or clips
# on its own; the one reaching furthest right (the innermost of equals) is named.
OVERFLOW = """() => {
  const width = window.innerWidth;
  const clipped = (el) => {
    for (let p = el.parentElement; p && p !== document.documentElement; p = p.parentElement) {
      if (["auto", "scroll", "hidden", "clip"].includes(getComputedStyle(p).overflowX)) return true;
    }
    return false;
  };
  const name = (el) => el.tagName.toLowerCase() + (el.id ? "#" + el.id : "")
    + [...el.classList].map((c) => "." + c).join("");
  const path = (el) => {
    const parts = [];
    for (let p = el; p && p !== document.body; p = p.parentElement) parts.unshift(name(p));
    return parts.join(" > ");
  };
  const out = [];
  for (const el of document.body.querySelectorAll("*")) {
    const r = el.getBoundingClientRect();
    // Its own box, or the text it holds when that spills out of its box (a token that does not wrap).
    const spill = getComputedStyle(el).overflowX === "visible" ? r.left + el.scrollWidth : r.right;
    const right = Math.max(r.right, spill);
    if (r.width > 0 && right > width + 0.5 && !clipped(el)) {
      out.push({path: path(el), right: Math.round(right), text: (el.textContent || "").trim().slice(0, 60)});
    }
  }
  out.sort((a, b) => b.right - a.right);
  return {scrollWidth: document.documentElement.scrollWidth, innerWidth: width, offenders: out.slice(0, 5)};
}"""

SMALL_TARGETS = """(minPx) => {
  const visible = (el) => {
    const r = el.getBoundingClientRect();
    const s = getComputedStyle(el);
    return r.width > 0 && r.height > 0 && s.visibility !== "hidden" && s.display !== "none";
  };
  // A link displayed inline in a paragraph, list item, cell, caption or label that holds other text.
  const inSentence = (a) => {
    if (a.tagName !== "A" || getComputedStyle(a).display !== "inline") return false;
    let block = a.parentElement;
    while (block && getComputedStyle(block).display.startsWith("inline")) block = block.parentElement;
    if (!block || !["P", "LI", "TD", "DD", "FIGCAPTION", "LABEL", "BLOCKQUOTE"].includes(block.tagName)) return false;
    return block.textContent.trim().length > a.textContent.trim().length;
  };
  const name = (el) => el.tagName.toLowerCase() + (el.id ? "#" + el.id : "")
    + [...el.classList].map((c) => "." + c).join("");
  return [...document.querySelectorAll("button, a[href], input, select, summary")]
    .filter((el) => el.type !== "hidden" && visible(el) && !inSentence(el))
    .map((el) => ({el, r: el.getBoundingClientRect()}))
    .filter(({r}) => r.height < minPx)
    .map(({el, r}) => `${name(el)} "${(el.textContent || el.value || "").trim().slice(0, 40)}" `
      + `${Math.round(r.width)}×${Math.round(r.height)} px`);
}"""


def layout_problems(page, state: str, width: int, shot_name: str | None = None) -> list[str]:
    """What is wrong with the page as it stands: sideways scrolling, axe violations, small targets (its
    screenshot: test-artifacts/<shot_name>.png, layout_<state>_<width> unless named)."""
    shot(page, shot_name or f"layout_{state}_{width}")
    problems = []
    fit = page.evaluate(OVERFLOW)
    if fit["scrollWidth"] > fit["innerWidth"]:
        worst = "\n".join(f"  {o['path']} reaches {o['right']} px ({o['text']!r})" for o in fit["offenders"])
        problems.append(
            f"the page scrolls sideways: scrollWidth {fit['scrollWidth']} > {fit['innerWidth']} px;"
            f" furthest right:\n{worst or '  (no element outside a scrolling box)'}"
        )
    found = violations(page, AXE_OPTIONS.get(state))
    if found:
        problems.append("axe: " + describe(found))
    small = page.evaluate(SMALL_TARGETS, MIN_TARGET_PX)
    if small:
        problems.append(f"{len(small)} touch targets under {MIN_TARGET_PX} px tall:\n  " + "\n  ".join(small[:15]))
    return [f"{state} at {width} px: {p}" for p in problems]


def looked_at(page, state: str, widths=(390, 1280)) -> list[str]:
    """:func:`layout_problems` of the page as it stands at each width, the one page resized in place (and given
    back its size); screenshots test-artifacts/<state>_<width>.png."""
    size = page.viewport_size
    problems = []
    for width in widths:
        page.set_viewport_size({"width": width, "height": 900})
        problems += layout_problems(page, state, width, f"{state}_{width}")
    page.set_viewport_size(size)
    return problems


def source_of(state: str) -> str | None:
    """A wizard state's source: a board's (board_*, and the noise page, a board's only) or a phone's."""
    if state.startswith("board_") or state == "wizard_noise":
        return "board"
    return "phone" if state.startswith("wizard_") else None


@pytest.mark.parametrize("state", list(STATES))
def test_layout(browser, layout_server, state):
    """Each state set up once, at the smallest width, then measured at each width by resizing the one page, the
    smallest first (a drawing made at load fits the widths after it): three set-ups a state took three minutes of
    the suite's real time for what one shows."""
    context = axe_context(browser, viewport={"width": WIDTHS[0], "height": 800}, device_scale_factor=1)
    try:
        page = context.new_page()
        STATES[state](page, layout_server.url)
        problems = []
        for width in WIDTHS:
            page.set_viewport_size({"width": width, "height": 800})
            problems += layout_problems(page, state, width)
        source = source_of(state)
        if source:  # a wizard page says only its own source's words (tests/e2e/source_words.py)
            problems += [f"{state}: the other source's word {w}" for w in other_source_words(page, source)]
        assert not problems, "\n".join(problems)
    finally:
        context.close()


def test_the_six_flow_while_capturing_and_at_its_result(browser, layout_server):
    # The six flow run once with the sensors emulated (tests/e2e/test_wizard.py), each state measured
    # at every width by resizing the one page: capturing (a refused repeat, the longest instruction),
    # then the result with its details open.
    from tests.e2e.test_wizard import Motion, grant_on_tap, reading, repeat_the_first_pose, wait_captured

    context = axe_context(browser, viewport={"width": 390, "height": 800}, device_scale_factor=1)
    problems: list[str] = []

    def measure(state):
        for width in WIDTHS:
            page.set_viewport_size({"width": width, "height": 800})
            problems.extend(layout_problems(page, state, width))
        page.set_viewport_size({"width": 390, "height": 800})

    try:
        page = context.new_page()
        grant_on_tap(page)
        motion = Motion(page)
        repeat_the_first_pose(page, motion, layout_server.url)
        measure("wizard_six_repeat_refused")
        for label in ("-z", "+x", "-x", "+y", "-y"):
            motion.acc(reading(label))
            wait_captured(page, label)
        page.wait_for_selector("#downloads[data-ready=true]", timeout=20_000)
        page.click("#result-details summary")
        measure("wizard_six_result")
    finally:
        context.close()
    assert not problems, "\n".join(problems)
