"""Hands-off capturing in real headless Chromium against a real trical server: the screen wake lock, the
sound and vibration cues, the size of the live instruction and the two-step Start over.

The browser's own interfaces are watched from inside the page (an init script, before the page's
modules run): navigator.wakeLock.request hands out sentinels that record their release,
navigator.vibrate records its patterns, and AudioContext.prototype.createOscillator is wrapped so that
every tone records its frequency when it starts. Nothing of trical's is replaced; the motion comes from
the DevTools protocol's sensor overrides as in test_wizard.py."""

from __future__ import annotations

import json

import numpy as np
from playwright.sync_api import expect

from tests.e2e.conftest import shot
from tests.e2e.test_wizard import Motion, reading, repeat_the_first_pose, wait_captured
from tests.e2e.test_wizard_compass import mag_browser, mag_page, magnetometer, turn  # noqa: F401 (fixtures)
from tests.e2e.test_wizard_free import UPS
from tests.e2e.test_wizard_free import reading as free_reading

# What each cue sounds and feels like (static/js/cues.js): every kind is told apart by both.
TONE_KIND = {523.0: "start", 880.0: "captured", 220.0: "refused", 660.0: "finished"}
BUZZ_KIND = {"30": "start", "80": "captured", "[60,80,60]": "refused", "[120,60,120]": "finished"}

# The log of every call, in order, kept in sessionStorage too so that it outlives a reload
# (window.__spy.before: the previous page's log).
SPY = """
(() => {
  const before = JSON.parse(sessionStorage.getItem('spy') || '[]');
  const log = [];
  const note = (entry) => { log.push(entry); sessionStorage.setItem('spy', JSON.stringify(log)); };
  const sentinels = [];
  window.__spy = { before, log, sentinels, hadWakeLock: 'wakeLock' in navigator };
  const api = navigator.wakeLock || {};
  api.request = (type) => {
    note(['wake', type]);
    const s = new EventTarget();
    s.type = type;
    s.released = false;
    s.release = () => {
      if (!s.released) { s.released = true; note(['release']); s.dispatchEvent(new Event('release')); }
      return Promise.resolve();
    };
    sentinels.push(s);
    return Promise.resolve(s);
  };
  if (!('wakeLock' in navigator)) Object.defineProperty(navigator, 'wakeLock', { value: api, configurable: true });
  Object.defineProperty(navigator, 'vibrate', { configurable: true, value: (pattern) => {
    note(['buzz', JSON.stringify(pattern)]);
    return true;
  } });
  const create = AudioContext.prototype.createOscillator;
  AudioContext.prototype.createOscillator = function () {
    const osc = create.call(this);
    const start = osc.start;
    osc.start = function (...args) { note(['tone', osc.frequency.value]); return start.apply(this, args); };
    return osc;
  };
})();
"""

# What a hidden page means for a wake lock: the browser releases it, then says the page is hidden;
# visible again, it says so. Only the visibility is simulated; the page's own listener reacts.
HIDE_AND_SHOW = """() => {
  const set = (state) => Object.defineProperty(document, 'visibilityState', { configurable: true, get: () => state });
  set('hidden');
  window.__spy.sentinels.forEach((s) => s.release());
  document.dispatchEvent(new Event('visibilitychange'));
  set('visible');
  document.dispatchEvent(new Event('visibilitychange'));
}"""


def spy(page) -> None:
    page.add_init_script(SPY)


def log(page, key: str = "log") -> list:
    return page.evaluate(f"() => window.__spy.{key}")


def cues(entries: list) -> tuple[list[str], list[str]]:
    """The cue kinds heard (tones) and felt (vibrations), each in order."""
    heard = [TONE_KIND[e[1]] for e in entries if e[0] == "tone"]
    felt = [BUZZ_KIND[e[1]] for e in entries if e[0] == "buzz"]
    return heard, felt


def assert_cues(page, expected: list[str]) -> None:
    heard, felt = cues(log(page))
    assert heard == expected, heard
    assert felt == expected, felt


def wakes(entries: list) -> int:
    return sum(1 for e in entries if e[0] == "wake")


def test_six_flow_keeps_the_screen_on_and_cues_every_capture(page, server):
    spy(page)
    motion = Motion(page)
    page.goto(server.url + "/wizard?protocol=six&capture_s=1")
    assert page.evaluate("() => window.__spy.hadWakeLock")  # Chromium has the API: its request was replaced
    page.evaluate(HIDE_AND_SHOW)
    assert log(page) == []  # no session yet: nothing asked, nothing played
    order = ["+z", "-y", "+x", "-z", "-x", "+y"]
    motion.acc(reading(order[0]))
    page.click("#start-btn")
    page.wait_for_function("() => window.__spy.log.some((e) => e[0] === 'wake')")
    assert log(page)[0] == ["wake", "screen"]
    page.wait_for_selector("#progress:not([value='0'])", timeout=10_000)  # the first capture is under way
    assert_cues(page, ["start"])

    # Hidden (the browser releases the lock) and visible again while the session runs: asked again.
    page.evaluate(HIDE_AND_SHOW)
    page.wait_for_function("() => window.__spy.log.filter((e) => e[0] === 'wake').length === 2")
    assert [e[0] for e in log(page) if e[0] in ("wake", "release")] == ["wake", "release", "wake"]
    page.evaluate("() => document.dispatchEvent(new Event('visibilitychange'))")  # visible, lock held: no new request
    page.wait_for_timeout(100)
    assert wakes(log(page)) == 2

    for k, label in enumerate(order):
        if k:
            motion.acc(reading(label))
        wait_captured(page, label)
        done = ["captured" if i < 5 else "finished" for i in range(k + 1)]
        expected = [kind for d in done for kind in ("start", d)]
        page.wait_for_function(f"() => window.__spy.log.filter((e) => e[0] === 'tone').length >= {len(expected)}")
        assert_cues(page, expected)  # a start and a done cue per pose, the last one "finished"
    page.wait_for_selector("#downloads[data-ready=true]", timeout=20_000)
    shot(page, "wizard_cues_result")

    # The result shows: the lock is released after the last cue, and not asked for again.
    entries = log(page)
    assert all(page.evaluate("() => window.__spy.sentinels.map((s) => s.released)"))
    last_cue = max(i for i, e in enumerate(entries) if e[0] in ("tone", "buzz"))
    assert any(e == ["release"] for e in entries[last_cue:]), entries[last_cue:]
    page.evaluate(HIDE_AND_SHOW)
    page.wait_for_timeout(100)
    assert wakes(log(page)) == 2
    assert page.errors == []


def test_a_refused_pose_cues_and_start_over_asks_first(page, server):
    spy(page)
    motion = Motion(page)
    repeat_the_first_pose(page, motion, server.url)  # refused, nothing captured
    page.wait_for_function("() => window.__spy.log.filter((e) => e[0] === 'tone').length >= 3")
    page.wait_for_timeout(2500)  # longer than hold + capture: no capture starts on a done pose
    assert_cues(page, ["start", "captured", "refused"])

    # The Redo buttons are secondary actions: not the primary button's filled accent.
    redo = page.locator('#poses button[data-redo="+z"]')
    expect(redo).to_be_visible()
    colours = redo.evaluate("(b) => [getComputedStyle(b).backgroundColor, getComputedStyle(b).color]")
    primary = page.eval_on_selector(
        "#start-btn", "(b) => [getComputedStyle(b).backgroundColor, getComputedStyle(b).color]"
    )
    assert colours != primary and colours[0] == "rgb(255, 255, 255)", (colours, primary)

    # Start over, first tap: it only asks. Keep it: the session and the capture go on.
    saved = page.evaluate("() => localStorage.getItem('trical.wizard.six')")
    assert saved
    page.click("#start-over")
    ask = page.locator("#start-over-ask")
    expect(ask).to_be_visible()
    expect(ask).to_contain_text("Discard this calibration")
    assert page.is_hidden("#start-over")
    expect(page.locator("#start-over-no")).to_be_focused()  # the safe answer under the thumb
    shot(page, "wizard_start_over_asks")
    page.click("#start-over-no")
    expect(ask).to_be_hidden()
    expect(page.locator("#start-over")).to_be_focused()
    assert page.evaluate("() => localStorage.getItem('trical.wizard.six')") == saved
    motion.acc(reading("-z"))
    wait_captured(page, "-z")  # still capturing, in the same session
    session = json.loads(saved)
    r = page.request.get(
        f"{server.url}/api/v1/sessions/{session['id']}", headers={"Authorization": f"Bearer {session['token']}"}
    )
    assert [c["position"] for c in r.json()["captures"]] == ["+z", "-z"]

    # Second tap: discarded, the lock released, the page back at its start.
    page.click("#start-over")
    page.click("#start-over-yes")
    page.wait_for_function("() => window.__spy && window.__spy.before.length > 0")
    before = log(page, "before")
    assert before[-1] == ["release"] and wakes(before) == 1
    expect(page.locator("#start-btn")).to_have_text("Start")
    assert page.evaluate("() => localStorage.length") == 0
    assert page.is_hidden("#capture") and page.is_hidden("#start-over")
    assert page.errors == []


def test_the_instruction_is_the_largest_text_during_capture(page, server):
    motion = Motion(page)
    for width in (390, 320):
        page.set_viewport_size({"width": width, "height": 800})
        page.goto(server.url + "/wizard?capture_s=1")
        if width == 320:
            page.evaluate("() => localStorage.clear()")
            page.reload()
        motion.acc(reading("+x"))
        page.click("#start-btn")
        expect(page.locator("#instruction")).to_contain_text(
            "Capturing on its left edge as you face the screen", timeout=10_000
        )
        sizes = page.evaluate("""() => ({
          instruction: parseFloat(getComputedStyle(document.querySelector('#instruction')).fontSize),
          headings: [...document.querySelectorAll('h1, h2')].map((h) => parseFloat(getComputedStyle(h).fontSize)),
        })""")
        assert len(sizes["headings"]) >= 3  # the page's h1, and the cards' h2
        assert sizes["instruction"] > max(sizes["headings"]), sizes
        assert sizes["instruction"] >= 28, sizes
        shot(page, f"wizard_cues_instruction_{width}")
        wait_captured(page, "+x")
        motion.acc((3.0, 3.0, 8.8))
        expect(page.locator("#still-text")).to_have_text("Moving")
        motion.acc(reading("+x"))  # the longest instruction: a refused pose with all that remains
        expect(page.locator("#instruction")).to_contain_text(
            "On its left edge as you face the screen, right edge up is already captured", timeout=10_000
        )
        assert page.evaluate("() => document.documentElement.scrollWidth") <= width
        box = page.locator("#instruction").bounding_box()
        assert box["x"] >= 0 and box["x"] + box["width"] <= width
        shot(page, f"wizard_cues_instruction_refused_{width}")
    assert page.errors == []


def test_free_flow_cues_its_captures_and_a_pose_too_close(page, server):
    spy(page)
    motion = Motion(page)
    page.goto(server.url + "/wizard?protocol=free&capture_s=1")
    motion.acc(free_reading(UPS[0]))
    page.click("#start-btn")
    page.wait_for_selector('#free-count[data-count="1"]', state="attached", timeout=20_000)
    motion.acc(free_reading(UPS[1]))
    page.wait_for_selector('#free-count[data-count="2"]', state="attached", timeout=20_000)
    # Back near pose 2 (5° off): refused on the page, with its cue.
    side = np.cross(UPS[1], [0, 0, 1])
    near = UPS[1] + np.tan(np.radians(5)) * side / np.linalg.norm(side)
    motion.acc((1.0, 2.0, 9.0))
    motion.acc(free_reading(near / np.linalg.norm(near)))
    expect(page.locator("#instruction")).to_contain_text("within 10° of a pose already captured", timeout=10_000)
    page.wait_for_function("() => window.__spy.log.filter((e) => e[0] === 'tone').length >= 5")
    assert_cues(page, ["start", "captured", "start", "captured", "refused"])
    assert wakes(log(page)) == 1
    assert page.errors == []


# mag_page is the fixture imported above, which pytest passes: not a redefinition (F811).
def test_compass_start_asks_for_the_wake_lock_and_cues_the_first_reading(mag_page, server):  # noqa: F811
    page = mag_page
    spy(page)
    readings, _ = turn(5, 50.0, n=40)
    feed = magnetometer(page)

    page.goto(server.url + "/wizard?protocol=compass")
    expect(page.locator("#compass-start-btn")).to_be_visible()
    feed(readings[0])
    page.click("#compass-start-btn")
    page.wait_for_function("() => document.querySelector('#compass-coverage').dataset.count === '1'")
    page.wait_for_function("() => window.__spy.log.some((e) => e[0] === 'tone')")
    assert wakes(log(page)) == 1 and log(page)[0] == ["wake", "screen"]
    for k, m in enumerate(readings[1:10], start=2):
        feed(m)
        page.wait_for_function(f"() => Number(document.querySelector('#compass-coverage').dataset.count) >= {k}")
    assert_cues(page, ["start"])  # once, at the first reading: the turn may begin

    # Its instruction (the coverage line) is the largest text too, and Start over asks there as well.
    sizes = page.evaluate("""() => [parseFloat(getComputedStyle(document.querySelector('#compass-coverage')).fontSize),
      ...[...document.querySelectorAll('h1, h2')].map((h) => parseFloat(getComputedStyle(h).fontSize))]""")
    assert sizes[0] >= 28 and sizes[0] > max(sizes[1:]), sizes
    page.click("#start-over")
    expect(page.locator("#start-over-ask")).to_be_visible()
    page.click("#start-over-no")
    expect(page.locator("#start-over-ask")).to_be_hidden()
    feed(readings[10])
    page.wait_for_function("() => Number(document.querySelector('#compass-coverage').dataset.count) >= 11")
    page.click("#start-over")
    page.click("#start-over-yes")
    page.wait_for_function("() => window.__spy && window.__spy.before.length > 0")
    assert log(page, "before")[-1] == ["release"]
    expect(page.locator("#compass-start-btn")).to_be_visible()
    assert page.errors == []


def test_without_wake_lock_vibration_or_audio_nothing_breaks(page, server):
    page.add_init_script("""
      delete Navigator.prototype.wakeLock;
      delete Navigator.prototype.vibrate;
      delete window.AudioContext;
      delete window.webkitAudioContext;""")
    motion = Motion(page)
    page.goto(server.url + "/wizard?capture_s=1")
    assert page.evaluate("() => !('wakeLock' in navigator) && !('vibrate' in navigator) && !window.AudioContext")
    motion.acc(reading("-x"))
    page.click("#start-btn")
    wait_captured(page, "-x")
    motion.acc((3.0, 3.0, 8.8))
    expect(page.locator("#still-text")).to_have_text("Moving")
    motion.acc(reading("-x"))
    expect(page.locator("#instruction")).to_contain_text(
        "On its right edge as you face the screen, left edge up is already captured", timeout=10_000
    )
    assert page.errors == []
