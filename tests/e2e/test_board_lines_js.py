"""The lines a board prints (static/js/board_lines.js) and their timing (static/js/board.js), run as the
page runs them: imported by real Chromium from the real server."""

from __future__ import annotations

import json

import pytest

from app.io.board.formats import MOTIONCAL_RAW

G = 9.80665


@pytest.fixture
def js(page, server):
    page.goto(server.url + "/wizard?protocol=six")

    def run(body: str):
        return page.evaluate(
            "async () => { const m = await import('/static/js/board_lines.js'); "
            f"const b = await import('/static/js/board.js'); {body} }}"
        )

    return run


def test_line_ends_cr_lf_crlf_and_one_split_across_chunks(js):
    chunks = ["a\r", "\nb\rc\n", "d\r\n", "e"]
    assert js(f"const s = new m.LineSplitter(); return {json.dumps(chunks)}.flatMap((c) => s.push(c));") == [
        "a",
        "b",
        "c",
        "d",
    ]


def test_raw_lines_at_motioncal_s_scales(js):
    r = js(
        "const l = new m.BoardLines(); return [l.push('Raw:0,-8192,16384,16,-32,0,215,-100,3000'), l.format, l.units];"
    )
    (reading,), fmt, units = r
    assert fmt == "raw" and units == {"acc": "m/s^2", "gyr": "deg/s", "mag": "uT"}
    assert reading["acc"] == pytest.approx([0, -G * 8192 * MOTIONCAL_RAW["acc_g_per_count"], 2 * G], abs=1e-12)
    assert reading["gyr"] == pytest.approx([1.0, -2.0, 0.0]) and reading["mag"] == pytest.approx([21.5, -10.0, 300.0])


def test_boot_text_is_skipped_and_counted_then_uni_lines(js):
    lines = [
        "",
        "Adafruit SensorLab",
        "Uni:0.10,-0.20,9.79,0.010,0.020,-0.030,21.50,-3.20,40.10",
        "oops",
        "Raw:0,0,8192,0,0,0,0,0,0",
    ]
    got = js(
        f"const l = new m.BoardLines(); const out = {json.dumps(lines)}.map((x) => l.push(x)); "
        "return [out, l.format, l.skipped, l.lastSkipped, l.readings];"
    )
    out, fmt, skipped, last, readings = got
    assert fmt == "uni" and readings == 1 and skipped == 3 and last == "Raw:0,0,8192,0,0,0,0,0,0"
    assert out == [
        [],
        [],
        [{"t": None, "acc": [0.1, -0.2, 9.79], "gyr": [0.01, 0.02, -0.03], "mag": [21.5, -3.2, 40.1]}],
        [],
        [],
    ]


def test_a_csv_header_names_the_columns_and_the_time_unit_comes_from_its_steps(js):
    lines = ["Timestamp,aX (g),aY (g),aZ (g),Temp (C),gX,gY,gZ"] + [
        f"{410 + 16 * k},0.1,0.2,9.8,26.1,0.03,0.02,0.01" for k in range(6)
    ]
    out = js(
        f"const l = new m.BoardLines(); const out = {json.dumps(lines)}.map((x) => l.push(x)); "
        "return [out, l.format, l.hasTime, l.timeMs, l.skipped];"
    )
    readings, fmt, has_time, time_ms, skipped = out
    assert fmt == "csv" and has_time and time_ms == 1 and skipped == 0 and readings[0] == []
    assert [r["t"] for (r,) in readings[1:]] == [None, None, None, None, 410 + 16 * 4, 410 + 16 * 5]
    (last,) = readings[-1]
    assert last["acc"] == [0.1, 0.2, 9.8] and last["gyr"] == [0.03, 0.02, 0.01] and last["mag"] is None


def test_the_first_line_is_held_until_the_next_agrees(js):
    # Connected in the middle of a line: its tail has three numbers, the board's lines have seven
    # (a time and six values); the tail is skipped, and the first two whole lines make the layout.
    lines = ["81,9.80", "2.5,-0.01", "1000,0.1,0.2,9.8,1,2,3", "1010,0.1,0.2,9.8,1,2,3", "1020,0.1,0.2,9.8,1,2,3"]
    got = js(
        f"const l = new m.BoardLines(); const out = {json.dumps(lines)}.map((x) => l.push(x).length); "
        "return [out, l.format, l.layout.width, l.skipped, l.readings];"
    )
    assert got == [[0, 0, 0, 2, 1], "bare", 7, 2, 3]


@pytest.mark.parametrize(
    "line, width, expected",
    [
        ("0.1 0.2 9.8", 3, {"t": None, "acc": [0.1, 0.2, 9.8], "gyr": None, "mag": None}),
        ("0.1\t0.2\t9.8\t1\t2\t3", 6, {"t": None, "acc": [0.1, 0.2, 9.8], "gyr": [1, 2, 3], "mag": None}),
        (
            "1.5;0.1;0.2;9.8;1;2;3;20;30;40",
            10,
            {"t": 1500, "acc": [0.1, 0.2, 9.8], "gyr": [1, 2, 3], "mag": [20, 30, 40]},
        ),
    ],
)
def test_bare_columns(js, line, width, expected):
    got = js(
        f"const l = new m.BoardLines(); l.push({json.dumps(line)}); const r = l.push({json.dumps(line)}); "
        "return [r, l.format, l.layout.width];"
    )
    assert got == [[expected, expected], "bare", width]


def test_the_unit_at_rest_and_the_board_s_rate_whatever_the_bursts(js):
    assert js("return [m.accUnitAtRest(9.81), m.accUnitAtRest(1.01), m.accUnitAtRest(16384)];") == ["m/s^2", "g", None]
    # 100 lines a second of a bare board in g, arriving in bursts of 1 to 9 lines: the times spread the
    # lines evenly, none repeats, and the rate is 100 Hz; the unit is decided from the rest (g).
    got = js("""const src = new b.BoardSource({ onSample: (s) => out.push(s) }); const out = [];
      let t = 1000, k = 0;
      for (let burst = 0; k < 300; burst += 1) {
        const n = 1 + (burst * 7) % 9; let text = '';
        for (let i = 0; i < n; i += 1, k += 1) text += '0.001 -0.002 1.000\\n';
        t += n * 10; src.text(text, t);
      }
      const ts = out.map((s) => s.t);
      return [src.units, src.rate(), ts.every((x, i) => i === 0 || x > ts[i - 1]), out[0].acc[2], out.length];""")
    units, rate, increasing, az, n = got
    assert units == {"acc": "g", "gyr": None, "mag": None} and increasing
    assert rate == pytest.approx(100.0, rel=0.02) and az == pytest.approx(G) and 240 <= n < 300


@pytest.mark.parametrize("burst_s", [1.0, 2.0])
def test_the_rate_counted_over_bursts_of_1_and_2_s_and_times_on_it(js, burst_s):
    """A bare board at 62.5 Hz whose lines reach the page `burst_s` at a time, each burst split in two reads
    0.1 s apart (the twin of tests/io/test_board_lines.py's case): the rate is counted, decided after three
    bursts, and the samples are one interval of it apart, none in a burst repeating a time."""
    got = js(f"""const src = new b.BoardSource({{ onSample: (s) => out.push(s) }}); const out = [];
      const rate = new m.StreamRate(); let lines = 0, decidedAt = null;
      for (let k = 0; k < 10; k += 1) {{
        const t = 1000 * k * {burst_s} + 37 * ((k * 7) % 3);
        const made = Math.round(62.5 * (k + 1) * {burst_s}); const first = Math.floor((made - lines) / 2);
        rate.arrive(first, t / 1000); rate.arrive(made - lines - first, t / 1000 + 0.1);
        src.text('0.001 -0.002 1.000\\n'.repeat(first), t);
        src.text('0.001 -0.002 1.000\\n'.repeat(made - lines - first), t + 100);
        lines = made;
        if (decidedAt === null && rate.rateHz !== null) decidedAt = t / 1000;
      }}
      const steps = out.slice(1).map((s, i) => s.t - out[i].t);
      return [rate.rateHz, decidedAt, src.rate(), Math.min(...steps), Math.max(...steps), out.length, lines];""")
    rate, decided_at, source_rate, step_min, step_max, n, lines = got
    assert decided_at == pytest.approx(3 * burst_s, abs=0.2)
    assert rate == pytest.approx(62.5, rel=0.01) and source_rate == pytest.approx(62.5, rel=0.01)
    # no repeated time, no gap: the first estimate within the delays' spread (74 ms) over its 2 s
    assert 1000 / 62.5 * 0.95 < step_min <= step_max < 1000 / 62.5 * 1.05
    assert lines - 2 * 62.5 * burst_s <= n <= lines


def test_the_twins_decide_the_same_rate_at_the_same_arrival(js):
    """The page's StreamRate and the CLI's (app.io.board.lines.StreamRate) given the same arrivals — a
    reader held once for 0.4 s and 3 s, bursts of 1 s with one read late, a host hiccuping now and then —
    decide at the same arrival on the same rate."""
    import numpy as np

    from app.io.board.lines import StreamRate
    from tests.io.test_board_lines import held_reader

    rng = np.random.default_rng(7)
    hiccups, t, due = [], 0.0, 0.0
    while t < 12:
        step = 0.016 + abs(rng.normal(0, 0.003)) + (rng.uniform(0.05, 0.5) if rng.random() < 0.01 else 0.0)
        t, due = t + step, due + 62.5 * step
        hiccups.append((int(due), t))
        due -= int(due)
    streams = [held_reader(0.4), held_reader(3.0), [(100, k + (0.15 if k == 2 else 0.0)) for k in range(8)], hiccups]
    for arrivals in streams:
        rate, python = StreamRate(), None
        for i, (n, t) in enumerate(arrivals):
            rate.arrive(n, t)
            if rate.rate_hz is not None:
                python = [i, rate.rate_hz, rate.span_s]
                break
        page = js(f"""const r = new m.StreamRate(); const arrivals = {json.dumps(arrivals)};
          for (let i = 0; i < arrivals.length; i += 1) {{
            r.arrive(arrivals[i][0], arrivals[i][1]);
            if (r.rateHz !== null) return [i, r.rateHz, r.spanS];
          }}
          return null;""")
        assert python is not None and page is not None
        assert page[0] == python[0] and page[1:] == pytest.approx(python[1:], rel=1e-12)


def test_a_time_column_wins_over_the_arrival(js):
    """The board's own time (millis() at 50 Hz) gives the samples' times and the rate, however the lines
    arrive (here 100 at once every 0.5 s: 200 Hz by their arrival)."""
    got = js("""const src = new b.BoardSource({ onSample: (s) => out.push(s) }); const out = [];
      for (let k = 0; k < 6; k += 1) {
        let text = ''; for (let i = 0; i < 100; i += 1) text += `${20 * (100 * k + i)},0.001,-0.002,1.000\\n`;
        src.text(text, 1000 + 500 * k);
      }
      const steps = out.slice(1).map((s, i) => s.t - out[i].t);
      return [src.rate(), Math.min(...steps), Math.max(...steps)];""")
    rate, step_min, step_max = got
    assert rate == pytest.approx(50.0, rel=1e-9) and step_min == pytest.approx(20.0) and step_max == pytest.approx(20.0)


def test_a_stalled_capture_says_what_it_waits_for(js):
    machine = "{ o: (await import('/static/js/tables.js')).TABLES.capture, remaining: () => ['+x', '-y'] }"
    got = js(f"""const machine = {machine};
      return [b.stallWords(machine, {{ still: false, spread: 0.31, gyr: 0.5 }}),
              b.stallWords(machine, {{ still: false, spread: 0.02, gyr: 7.25 }}),
              b.stallWords(machine, {{ still: true, spread: 0.02, gyr: 0.5, pose: '+z', angleDeg: 31 }}),
              b.stallWords(machine, {{ still: true, spread: 0.02, gyr: 0.5, pose: '+z', angleDeg: 3 }})];""")
    assert got == [
        "No capture for 20 s. Waiting for X arrow up (+x) or Y arrow down (-y): the board moves: spread 0.31 m/s² "
        "> 0.1; hold it still in a pose asked.",
        "No capture for 20 s. Waiting for X arrow up (+x) or Y arrow down (-y): the board turns: 7.3 °/s > 3; hold "
        "it still in a pose asked.",
        "No capture for 20 s. Waiting for X arrow up (+x) or Y arrow down (-y): the board is still, 31° from "
        "components up (+z); set it square on a side.",
        "No capture for 20 s. Waiting for X arrow up (+x) or Y arrow down (-y): the board is still, components up "
        "(+z), captured already; turn it to a pose asked.",
    ]


def test_a_board_without_a_compass_is_told_nothing_of_a_compass_reset(page, server):
    """The packet of an accelerometer calibration for a board whose lines carry no magnetometer (an MPU-6050):
    the send box says its compass part concerns nothing on that board, and offers no compass calibration; a board
    that prints a magnetometer is told its compass calibration will be reset (board_panel.js describeSend)."""
    page.goto(server.url + "/wizard?protocol=six&source=board")
    said = page.evaluate(
        """async () => {
          const m = await import('/static/js/board_panel.js');
          const X = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
          const cal = { device_id: 'imu-1', model: { type: 'affine', X, y: [0, 0, 0] } };
          const words = (latest) => {
            const panel = { calibration: cal, compass: null, latest };
            m.BoardPanel.prototype.describeSend.call(panel);
            return [document.querySelector('#board-send-parts').textContent,
                    document.querySelector('#board-send-compass-box').hidden];
          };
          return [words({ acc: [0, 0, 9.8], gyr: [0, 0, 0], mag: null }),
                  words({ acc: [0, 0, 9.8], gyr: [0, 0, 0], mag: [20, 0, -40] })];
        }"""
    )
    (without, hidden), (with_mag, _) = said
    assert "This board prints no magnetometer" in without and "will be reset" not in without and hidden
    assert "The board's compass calibration will be reset" in with_mag


def test_the_board_page_says_what_to_flash_and_copies_the_sketch(browser, server):
    """The board page lists the sketches that print what it reads (static/sketches), each with its baud rate — read
    from the sketch's own Serial.begin — and its libraries; Copy the sketch puts the served file on the clipboard."""
    from app.web.sketches import SKETCHES

    context = browser.new_context(viewport={"width": 390, "height": 800})
    context.grant_permissions(["clipboard-read", "clipboard-write"], origin=server.url)
    page = context.new_page()
    try:
        page.goto(server.url + "/wizard?protocol=six&source=board")
        page.click("#board-sketches summary")
        items = page.locator("#board-sketches li")
        assert [items.nth(i).get_attribute("data-sketch") for i in range(items.count())] == [s.name for s in SKETCHES]
        mpu = page.locator("#board-sketches li[data-sketch='mpu6050_uni']")
        assert "at 115200 baud" in mpu.inner_text() and "Adafruit MPU6050" in mpu.inner_text()
        mpu.locator(".sketch-copy").click()
        expect_copied = "mpu6050_uni.ino copied: paste it into a new sketch of the Arduino IDE."
        # a function, not an expression: the page's CSP forbids eval, which an expression's polling needs
        page.wait_for_function("text => document.querySelector('#sketch-msg').textContent === text", arg=expect_copied)
        pasted = page.evaluate("navigator.clipboard.readText()")
        assert pasted == SKETCHES[0].path.read_text(encoding="utf-8") and "Serial.begin(115200)" in pasted
    finally:
        context.close()
