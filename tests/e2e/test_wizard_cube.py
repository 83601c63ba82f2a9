"""The guided cube24 flow of the wizard in real headless Chromium against a real trical server.

The phone in its cube is played by the page's own timer (tests/e2e/phone_shim.js, as in the WebKit
tests): the accelerometer reads m = X f + y in each position (f = g times the up axis on a level
plane), and each turn is a half sine of the rate about the rotation's axis in the sensor frame, 90°
in all, sampled at 60 Hz. Turns fed from the test process in real time were lost when the browser
or the test stalled on a loaded machine; played by the page, they cannot be."""

from __future__ import annotations

import itertools
import json
import time
from pathlib import Path

import numpy as np
from playwright.sync_api import expect

from app.calibration import CANONICAL_SIX, STANDARD_GRAVITY
from app.calibration.cube.protocols import CUBE24_ROTATIONS, CUBE24_UPS, cube24
from app.calibration.cube.turns import TURN_WORDS
from app.guided.capture_rules import MAX_ROTATION_DEG_S
from app.web.tables import page_tables
from tests.cube_phone import X_ACC, Y_ACC
from tests.e2e.conftest import ARTIFACTS, phone_shim, shot, tab_to
from tests.e2e.source_words import assert_only_its_words
from tests.e2e.test_wizard import G, Motion, captures_sent

ATTITUDES = cube24().attitudes  # R_k: sensor → calibration frame
# A quarter turn in about 1.4 s, as a person makes it (peaks of 100–130 °/s).
PEAK_DEG_S = 100.0
# White noise on every sample, as a phone's sensors have it (a noiseless capture has no sample variance,
# and Särkkä et al.'s weighted fit has nothing to weigh): about 1 mg and 0.05 °/s, seeded.
ACC_SD = 0.01  # m/s²
GYR_SD = 0.05  # deg/s
URL = "/wizard?protocol=cube24&capture_s=1"
COUNT = '#cube-count[data-captured="{}"]'


def up_vector(label: str) -> np.ndarray:
    v = np.zeros(3)
    v["xyz".index(label[1])] = 1.0 if label[0] == "+" else -1.0
    return v


def reading(k: int) -> np.ndarray:
    """The accelerometer in position k (1-based) on a level plane: m = X f + y, f = g · up."""
    return X_ACC @ (G * up_vector(CUBE24_UPS[k - 1])) + Y_ACC


def turn_axis_in_sensor_frame(k_from: int, label: str) -> np.ndarray:
    """The axis of the quarter turn `label` (calibration frame, e.g. "z+") as the sensor in position
    k_from sees it: R_kᵀ a."""
    axis = np.zeros(3)
    axis["xyz".index(label[0])] = 1.0 if label[1] == "+" else -1.0
    return ATTITUDES[k_from - 1].T @ axis


class Cube:
    """The phone in the cube, its motion played by the page's own timer (tests/e2e/phone_shim.js, in
    the W3C sign): each position's accelerometer reading, and quarter turns of its gyroscope.

    A turn is a half sine of the rate about the rotation's axis in the sensor frame (a constant rate
    would read as a clipped gyroscope: a flat top), its peak a little different each turn, 90° in all,
    sampled at each 60 Hz event's time by the page: a stall of this process on a loaded machine can
    neither stretch nor cut it. Without a gyroscope, the accelerometer alone through the DevTools
    protocol's sensor overrides, as Chromium gives it."""

    def __init__(self, page, gyroscope=True):
        self.page = page
        self.gyroscope = gyroscope
        if gyroscope:
            page.add_init_script(phone_shim("w3c") + f"\nwindow.__phone.noise({ACC_SD}, {GYR_SD}, 24);")
        else:  # what a browser without a gyroscope gives: accelerometers only
            self.motion = Motion.__new__(Motion)
            self.motion.cdp = page.context.new_cdp_session(page)
            for sensor in ("accelerometer", "linear-acceleration"):
                self.motion.cdp.send("Emulation.setSensorOverrideEnabled", {"enabled": True, "type": sensor})
                self.motion.send(sensor, (0.0, 0.0, 0.0))
        self.turns: list[dict] = []  # what the page played: label, duration and the angle of its samples
        self.acc = reading(1)

    def place(self, k: int):
        """At rest in position k (the page must be open: the shim lives in it)."""
        self.acc = reading(k)
        if self.gyroscope:
            self.page.evaluate("(acc) => window.__phone.set(acc, [0, 0, 0])", [float(v) for v in self.acc])
        else:
            self.motion.acc(self.acc)

    def turn(self, k_from: int, label: str, then_acc=None):
        """Turn the cube by a quarter `label` (calibration frame) from the attitude of position k_from,
        then rest reading `then_acc` (by default what it read before); returns when the page has played it."""
        axis = turn_axis_in_sensor_frame(k_from, label)
        peak = PEAK_DEG_S + 3.0 * (len(self.turns) % 11)
        self.acc = self.acc if then_acc is None else then_acc
        played = self.page.evaluate(
            "([axis, peak, then]) => (window.__phone.turn(axis, peak, then), window.__phone.turns.length)",
            [[float(v) for v in axis], peak, [float(v) for v in self.acc]],
        )
        self.page.wait_for_function("(n) => window.__phone.turns.length > n", arg=played, timeout=15_000)
        done = self.page.evaluate("() => window.__phone.turns.at(-1)")
        self.turns.append({"label": label, "seconds": done["ms"] / 1000.0, "angle_deg": done["angle"]})

    def move_into(self, page, k: int, label: str | None = None):
        """The turn of the protocol from position k − 1 into k (or `label` instead), then rest in k."""
        self.turn(k - 1, label or CUBE24_ROTATIONS[k - 2], then_acc=reading(k))


def wait_captured(page, n: int, timeout=30_000):
    try:
        page.wait_for_selector(COUNT.format(n), state="attached", timeout=timeout)
    except Exception as exc:  # say what the page said instead
        said = {sel: page.text_content(sel) for sel in ("#instruction", "#status", "#cube-count", "#turn-alert")}
        raise AssertionError(
            f"position {n} was not captured within {timeout / 1000:g} s; the page says {said}"
        ) from exc


def saved_session(page, server) -> dict:
    saved = json.loads(page.evaluate("localStorage.getItem('trical.wizard.cube24')"))
    r = page.request.get(
        f"{server.url}/api/v1/sessions/{saved['id']}", headers={"Authorization": f"Bearer {saved['token']}"}
    )
    assert r.status == 200, r.text()
    return r.json()


def turn_integral_deg(motion: dict) -> float:
    """The angle of a turn about a fixed axis from the page's samples: the trapezoid of |ω| (deg/s)."""
    t = np.asarray(motion["t_ms"], dtype=float) / 1000.0
    rate = np.linalg.norm(np.asarray(motion["gyr"], dtype=float), axis=1)
    return float(np.sum(np.diff(t) * (rate[1:] + rate[:-1]) / 2.0))


def check_moves(sent: list[dict]):
    """Each move runs from the end of the capture accepted before it to the start of its own still
    window, without a gap: exactly the samples in between."""
    for prev, cap in itertools.pairwise(sent):
        motion = cap["motion"]
        t = np.array(motion["t_ms"])
        assert len(t) >= 20 and len(motion["gyr"]) == len(t) == len(motion["acc"])
        assert t[0] > prev["t_ms"][-1] and t[-1] < cap["t_ms"][0]
        # The next sample (every 16 ms of the page's clock) on either side; a lost still window or
        # capture would be 1.5 s or more.
        assert t[0] - prev["t_ms"][-1] < 250 and cap["t_ms"][0] - t[-1] < 250
        assert np.all(np.diff(t) > 0)


def test_the_24_positions_hands_free_recover_the_accelerometer(page, server):
    sent = captures_sent(page)
    cube = Cube(page)
    page.goto(server.url + URL)
    start = " ".join(page.text_content("#start").split())
    assert "in a fixed order" in start and "jig" in start and "about 4 minutes" in start
    assert "uploaded through the API" in start  # the recorded-sequence route, kept as one line
    shot(page, "cube_start")
    assert_only_its_words(page, "phone")
    cube.place(1)
    t0 = time.monotonic()
    page.click("#start-btn")
    expect(page.locator("#capture-h")).to_have_text("Position 1 of 24")
    page.wait_for_selector("#progress:not([value='0'])", timeout=10_000)
    shot(page, "cube_capturing_1")
    assert_only_its_words(page, "phone")
    wait_captured(page, 1)
    for k in range(2, 25):
        if k in (2, 5):  # between positions: the turn to make, with an arrow and words
            turn = page.locator("#cube-turn svg")
            assert turn.get_attribute("data-position") == str(k - 1)
            assert turn.get_attribute("data-turn") == CUBE24_ROTATIONS[k - 2]
            assert page.locator("#cube-target svg").get_attribute("data-position") == str(k)
            words = {
                "z+": "turn the cube a quarter counter-clockwise (seen from above) on the plane",
                "x+": "tip the cube 90° over the jig edge (about x, its top moving towards −y)",
            }
            assert words[CUBE24_ROTATIONS[k - 2]] in page.text_content("#instruction")
            shot(page, f"cube_turn_into_{k}")
        cube.move_into(page, k)
        wait_captured(page, k)
    page.wait_for_selector("#downloads[data-ready=true]", timeout=30_000)
    elapsed = time.monotonic() - t0
    shot(page, "cube_result")
    assert_only_its_words(page, "phone")
    for width in (320, 390, 1280):  # no sideways scroll of the result at any width (its tables scroll in their box)
        page.set_viewport_size({"width": width, "height": 800})
        shot(page, f"cube_result_{width}")
        assert page.evaluate("() => document.documentElement.scrollWidth <= innerWidth"), (
            f"the result scrolls at {width} px"
        )
    page.set_viewport_size({"width": 360, "height": 640})

    # The server checked every turn by integrating the page's gyroscope samples (Särkkä et al. eq. (2)).
    session = saved_session(page, server)
    turns = [c["turn"] for c in session["captures"][1:]]
    assert [t["expected"] for t in turns] == list(CUBE24_ROTATIONS) and all(t["ok"] for t in turns)
    fed = np.array([t["angle_deg"] for t in cube.turns])
    seen = np.array([t["angle_deg"] for t in turns])
    errors = np.array([t["end_error_deg"] for t in turns])
    check_moves(sent)
    sent_angle = np.array([turn_integral_deg(c["motion"]) for c in sent[1:]])
    assert [c["position"] for c in sent] == [str(k) for k in range(1, 25)] and not any(c["redo"] for c in sent)

    # What the page shows: Särkkä et al.'s model with its half-widths, checks, warnings, downloads.
    with page.expect_download() as info:
        page.click("#downloads a[data-format=json]")
    doc = json.loads(Path(info.value.path()).read_text())
    acc, gyr = doc["model"]["acc"], doc["model"]["gyr"]
    note = (
        f"cube24 wizard, capture_s=1: {elapsed:.1f} s from the Start tap to the downloads "
        f"({elapsed / 24:.1f} s a position, turns of about 1.3 s peaking at 100-130 °/s, played by the page); "
        f"turn angle seen by the server minus the angle played: {np.min(seen - fed):+.2f}° to "
        f"{np.max(seen - fed):+.2f}° "
        f"(mean {np.mean(seen - fed):+.2f}°, sd {np.std(seen - fed):.2f}°), minus the trapezoid of the samples "
        f"the page sent: up to {np.abs(seen - sent_angle).max():.2f}°; end attitude error up to "
        f"{errors.max():.2f}°; acc S − X up to {np.abs(np.array(acc['S']) - X_ACC).max():.4f}, "
        f"b − y up to {np.abs(np.array(acc['b']) - Y_ACC).max():.4f} m/s²; "
        f"gyr S − I up to {np.abs(np.array(gyr['S']) - np.eye(3)).max():.4f}, b up to "
        f"{np.degrees(np.abs(gyr['b']).max()):.3f} °/s; "
        f"ok={doc['ok']} {[w for w in doc['warnings'] if 'rotation' in w]}"
    )
    print("\n" + note)
    ARTIFACTS.mkdir(exist_ok=True)
    per_turn = [
        {"turn": k + 2, "fed": round(f, 3), "seen": round(v, 3), "end_error": round(e, 3)}
        for k, (f, v, e) in enumerate(zip(fed, seen, errors))
    ]
    (ARTIFACTS / "wizard_cube_timing.txt").write_text(note + "\n" + json.dumps(per_turn) + "\n")
    # The page played each turn as a half sine of 90° sampled every 16 ms of its own clock (a late timer
    # dispatches the samples it owes, each with its time): the trapezoid of those samples is 90° within
    # a few hundredths, however loaded the machine.
    assert np.all(np.abs(fed - 90.0) < 0.5), fed
    # The server's angle is the integral of the samples the page sent (the axis is fixed in a turn, so
    # the angle is ∫|ω| dt): within a few tenths of a degree, the difference between its interpolation
    # and the trapezoid here.
    assert np.all(np.abs(seen - sent_angle) < 0.5), list(zip(sent_angle, seen))
    # The server sees the angle played: the same samples, integrated by the server's interpolation
    # (far inside its tolerance of 0.1 per quaternion element, about 11°).
    assert np.all(np.abs(seen - fed) < 0.5), list(zip(fed, seen))
    assert np.all(errors < np.abs(seen - 90.0) + 1.0), list(zip(seen, errors))  # off by what it saw, no more
    # Each position's mean carries the noise over about a second at 60 Hz (0.01 / √60 ≈ 0.0013 m/s²);
    # S and b within a few times that over g.
    fed_readings = np.array([reading(k) for k in range(1, 25)])
    assert np.abs(np.array([c["mean"] for c in session["captures"]]) - fed_readings).max() < 6 * ACC_SD / np.sqrt(50)
    np.testing.assert_allclose(acc["S"], X_ACC, atol=5e-4)
    np.testing.assert_allclose(acc["b"], Y_ACC, atol=3e-3)
    # The gyroscope had no bias, only noise; its estimate is only as good as the turns' sampling.
    np.testing.assert_allclose(gyr["S"], np.eye(3), atol=0.02)
    np.testing.assert_allclose(gyr["b"], 0.0, atol=np.radians(0.5))
    cell = page.text_content("#cube-acc-S tr:first-child td:first-child")
    assert cell.startswith(f"{acc['S'][0][0]:.6f} ± ")
    assert page.text_content("#cube-acc-b tr:nth-child(2) td").startswith(f"{acc['b'][1]:.6f} ± ")
    assert page.locator("#cube-acc-D tr").count() == 3 and page.locator("#cube-acc-misalignment tr").count() == 3
    assert page.text_content("#cube-gyr-S tr:nth-child(3) td:nth-child(3)").startswith(f"{gyr['S'][2][2]:.6f} ± ")
    assert "b (rad/s)" in page.text_content("#cube-model") and "b (m/s^2)" in page.text_content("#cube-model")
    assert ("passed its checks" in page.text_content("#result-ok")) == doc["ok"]
    assert "may already calibrate" in page.text_content("#result-warnings")
    # The accelerometer's norm per position before and after, |m| and |S⁻¹(m − b)| (Särkkä et al. eq. (1)):
    # 24 rows and the chart's 48 dots. (How close to g they come is the API tests' business.)
    norms = page.eval_on_selector_all("#norm-table tbody tr", "rs => rs.map(r => [...r.cells].map(c => c.textContent))")
    assert [r[0] for r in norms] == [str(k) for k in range(1, 25)]
    means = np.array([c["mean"] for c in session["captures"]])
    S, b = np.array(acc["S"]), np.array(acc["b"])
    np.testing.assert_allclose([float(r[1]) for r in norms], np.linalg.norm(means, axis=1), atol=6e-5)
    np.testing.assert_allclose(
        [float(r[2]) for r in norms], np.linalg.norm(np.linalg.solve(S, (means - b).T).T, axis=1), atol=6e-5
    )
    assert page.locator("#norm-chart svg circle").count() == 48
    links = page.eval_on_selector_all("#downloads a", "as => as.map(a => [a.dataset.format, a.textContent])")
    # Every format: JSON, C and the tables hold each sensor's correction; ArduPilot and PX4 the accelerometer's.
    assert links == [
        ["json", "JSON"],
        ["c", "C header"],
        ["ardupilot", "ArduPilot"],
        ["px4", "PX4"],
        ["betaflight", "Betaflight"],
        ["inav", "INAV"],
        ["yaml", "YAML"],
        ["csv", "CSV"],
    ]
    assert page.eval_on_selector_all("#downloads li span", "ss => ss.length") == 0
    assert page.errors == []


def start_and_capture_three(page, server):
    """Open the cube flow, tap Start and capture positions 1–3 hands-free; the sent captures and the cube."""
    sent = captures_sent(page)
    cube = Cube(page)
    page.goto(server.url + URL)
    cube.place(1)
    page.click("#start-btn")
    wait_captured(page, 1)
    for k in (2, 3):
        cube.move_into(page, k)
        wait_captured(page, k)
    return sent, cube


def test_a_wrong_turn_is_named_at_once_and_the_corrected_move_passes(page, server):
    sent, cube = start_and_capture_three(page, server)
    cube.move_into(page, 4, label="z-")  # clockwise instead of counter-clockwise
    alert = page.locator("#turn-alert")
    expect(alert).to_be_visible(timeout=30_000)
    assert alert.get_attribute("role") == "alert"
    text = alert.text_content()
    assert (
        "wrong turn into position 4: the cube made a quarter turn clockwise (seen from above). Put it back "
        "in position 3, then turn the cube a quarter counter-clockwise (seen from above) on the plane"
    ) in text
    pic = page.locator("#turn-alert svg")
    assert pic.get_attribute("data-position") == "3" and pic.get_attribute("data-turn") == "z+"
    assert "counter-clockwise" in pic.get_attribute("aria-label")
    assert "Wrong turn into position 4" in page.text_content("#instruction")
    assert page.get_attribute(COUNT.format(3), "data-captured") == "3"
    shot(page, "cube_wrong_turn")
    assert_only_its_words(page, "phone")

    cube.turn(4, "z+")  # back into position 3...
    cube.move_into(page, 4)  # ...and the right turn
    wait_captured(page, 4)
    expect(alert).to_be_hidden()
    cube.move_into(page, 5)  # and on: the tip over the jig edge
    wait_captured(page, 5)
    shot(page, "cube_after_correction")
    assert [c["position"] for c in sent] == ["1", "2", "3", "4", "4", "5"]
    # Both attempts at 4 carry the move from the end of 3: the second includes the wrong turn and
    # the way back, whose net rotation is the protocol's.
    assert sent[3]["motion"]["t_ms"][0] == sent[4]["motion"]["t_ms"][0]
    check_moves([sent[2], sent[4], sent[5]])
    captures = saved_session(page, server)["captures"]
    assert [c["position"] for c in captures] == ["1", "2", "3", "4", "5"]
    assert captures[3]["turn"]["made"] == "z+90"
    # Chromium logs the refused request itself; nothing else went wrong.
    assert page.errors == ["Failed to load resource: the server responded with a status of 422 (Unprocessable Entity)"]


def test_without_a_gyroscope_the_page_says_the_cube_flow_needs_it(page, server):
    cube = Cube(page, gyroscope=False)
    cube.place(1)
    page.goto(server.url + URL)
    # What Chromium does with accelerometers but no gyroscope: rotationRate with null rates.
    page.evaluate("""window.__rates = [];
      window.addEventListener('devicemotion', (e) => { const r = e.rotationRate;
        window.__rates.push(r === null ? 'null' : [r.alpha, r.beta, r.gamma]); });""")
    page.click("#start-btn")
    problem = page.locator("#problem")
    expect(problem).to_contain_text("This browser gives no gyroscope readings", timeout=5000)
    assert "the cube flow needs them" in problem.text_content()
    assert page.get_attribute("#problem a", "href") == "/wizard?protocol=six"
    assert "No gyroscope" in page.text_content("#status")
    assert page.evaluate("localStorage.length") == 0  # no session was started
    rates = page.evaluate("window.__rates")
    assert len(rates) >= 10 and all(r == "null" or r == [None, None, None] for r in rates), rates[:3]
    print(f"\nChromium without a gyroscope override: rotationRate = {rates[0]!r}")
    shot(page, "cube_no_gyroscope")
    assert_only_its_words(page, "phone")
    assert page.errors == []


def test_a_reload_resumes_at_the_right_position_and_redo_replaces_the_last(page, server):
    sent, cube = start_and_capture_three(page, server)
    page.reload()
    cube.place(3)  # the reloaded page's shim starts afresh: the cube is still in position 3
    page.wait_for_selector("#resume:not([hidden])")
    resume = page.text_content("#resume")
    assert "3 of 24 positions captured" in resume and "Put the cube back in position 3" in resume
    assert "the recording of the next turn starts there" in resume
    assert page.get_attribute("#resume-pic svg", "data-position") == "3"
    assert page.text_content("#start-btn") == "Continue"
    shot(page, "cube_resumed")
    assert_only_its_words(page, "phone")

    tab_to(page, "#start-btn")
    page.keyboard.press("Enter")  # Continue, from the keyboard
    expect(page.locator("#capture-h")).to_have_text("Position 4 of 24")
    page.wait_for_timeout(2500)  # still in position 3: longer than hold + capture, nothing is sent
    assert len(sent) == 3
    cube.move_into(page, 4)
    wait_captured(page, 4)
    cube.move_into(page, 5)
    wait_captured(page, 5)
    assert sent[3]["motion"]["t_ms"][0] > sent[2]["t_ms"][-1]  # the log restarted at Continue
    check_moves(sent[3:])

    redo = page.locator("#redo-last")
    expect(redo).to_have_accessible_name("Redo position 5")
    tab_to(page, "#redo-last")
    shot(page, "cube_redo_focused")
    # What the live region announces, kept as it changes: the cube is still, so the capture starts at
    # once and replaces the redo announcement within a moment.
    page.evaluate("""() => { window.announced = [];
        new MutationObserver(() => window.announced.push(document.querySelector('#status').textContent))
            .observe(document.querySelector('#status'), {childList: true, characterData: true, subtree: true}); }""")
    page.keyboard.press("Enter")
    expect(page.locator("#capture-h")).to_have_text("Redo position 5 of 24")
    page.wait_for_function("() => window.announced.some(t => t.includes('Redo position 5'))", timeout=5000)
    wait_captured(page, 5)  # the count stays at 5 ...
    page.wait_for_function("() => !document.querySelector('#redo-last').hidden")  # ... and the redo is done
    expect(page.locator("#capture-h")).to_have_text("Position 6 of 24")
    assert sent[-1]["redo"] is True and sent[-1]["position"] == "5"
    assert sent[-1]["motion"]["t_ms"][0] == sent[4]["motion"]["t_ms"][0]  # again from the end of 4
    captures = saved_session(page, server)["captures"]
    assert [c["position"] for c in captures] == ["1", "2", "3", "4", "5"]
    for button in page.locator("button:visible").all():  # every visible control has a name
        assert button.evaluate("b => b.textContent.trim() || b.getAttribute('aria-label')")
    assert page.evaluate("document.documentElement.scrollWidth") <= 360  # readable at 360 × 640
    shot(page, "cube_redone")
    assert page.errors == []


def test_the_page_s_tables_are_the_server_s(page, server):
    """The page renders the server's tables (app.web.tables.page_tables()) and the scripts read them:
    cube.js has the attitudes, up faces, rotations and turn words of protocols.cube24(), motion.js the
    poses and thresholds; each position's picture names its up face."""
    page.goto(server.url + URL)
    rendered = json.loads(page.text_content("#trical-tables"))
    assert rendered == json.loads(json.dumps(page_tables()))
    got = page.evaluate("""async () => { const m = await import('/static/js/cube.js');
      const motion = await import('/static/js/motion.js'), t = await import('/static/js/tables.js');
      const ks = Array.from({length: 24}, (_, i) => i + 1);
      return [m.CUBE24_ATTITUDES, ks.map(m.upOf), m.CUBE24_ROTATIONS, ks.map((k) => m.cubeSvg(k)), m.TURN_WORDS,
              motion.DEFAULTS, motion.POSES, motion.STANDARD_GRAVITY, t.TABLES]; }""")
    np.testing.assert_array_equal(np.array(got[0]), np.round(ATTITUDES))
    assert got[1] == list(CUBE24_UPS) and got[2] == list(CUBE24_ROTATIONS) and got[4] == TURN_WORDS
    for k, svg in enumerate(got[3], start=1):
        assert f'aria-label="Position {k}: the cube with sensor {CUBE24_UPS[k - 1]} up' in svg
    assert got[5] == rendered["capture"] and got[5]["gyrHigh"] == MAX_ROTATION_DEG_S
    assert got[6] == list(CANONICAL_SIX) and got[7] == STANDARD_GRAVITY and got[8] == rendered


def test_the_motion_log_gives_each_capture_its_move(page, server):
    """MotionLog (cube.js) in Chromium: the move runs from the end of the last accepted capture; a
    redo runs from the end of the capture before it, or from now when that end is not in the log;
    past its size the log drops only what no move or redo needs."""
    page.goto(server.url + URL)
    got = page.evaluate("""async () => { const m = await import('/static/js/cube.js');
      const log = new m.MotionLog({maxSamples: 50});
      const feed = (a, b) => { for (let t = a; t < b; t += 10) log.push({t, acc: [0, 0, 9.8], gyr: [t, 0, 0]}); };
      const span = (mv) => [mv.t_ms[0], mv.t_ms[mv.t_ms.length - 1], mv.t_ms.length, mv.gyr[0][0]];
      const out = {};
      feed(0, 300); out.first = span(log.motion(200));            // resumed: from the log's start
      log.accept(1, 290); feed(300, 600); out.second = span(log.motion(500));
      log.accept(2, 590); feed(600, 900);
      out.redoKnown = [log.redo(2, 890), span(log.motion(800))];  // from the end of 1 again
      out.length = log.samples.length;                             // dropped up to the end of 1 only
      const fresh = new m.MotionLog(); fresh.accept(5, 100);
      for (let t = 110; t < 200; t += 10) fresh.push({t, acc: [0, 0, 0], gyr: [0, 0, 0]});
      out.redoUnknown = [fresh.redo(5, 150), span(fresh.motion(190))];  // from now
      out.redoFirst = new m.MotionLog().redo(1, 0);
      return out; }""")
    assert got["first"] == [0, 190, 20, 0]
    assert got["second"] == [300, 490, 20, 300]
    assert got["redoKnown"] == [True, [300, 790, 50, 300]]
    assert got["length"] == 60  # 300 … 890: the samples after the end of position 1
    assert got["redoUnknown"] == [False, [160, 180, 3, 0]]
    assert got["redoFirst"] is True
