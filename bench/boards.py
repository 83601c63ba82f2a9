"""A board's six flow in the browser, timed, and the same lines uploaded as a log.

    python bench/boards.py [--capture-s 5] [--turn-s 8]

Starts `trical serve` (temporary SQLite) and Debian's Chromium (Playwright), opens the six wizard with the
Web Serial stand-in of the browser tests (tests/e2e/board_shim.js), and plays the MPU-6050's six real pose
files (tests/data/real/mpu6050_pose_files, an ESP32 printing `t,aX,aY,aZ,...` at 62.9 Hz) as the board's
lines. Each file holds about 3.2 s, less than the 1.5 s hold and a 5 s capture take, so each pose plays its
file's rows three times in a row, the board's clock going on. Prints:

1. the time from *Connect a board (USB)* to the verdict's downloads, in the page's own time: what a person
   waits, apart from turning the board, which the played lines do at once; and that time with ``--turn-s``
   seconds a turn added for a person's hands;
2. the session's X and y beside the closed form of Georgieva et al. (section 3.3.1) on the means of the rows
   the session captured, found in the lines played (the same rows: equal to rounding);
3. the same lines uploaded as one log (``POST /api/v1/recordings``) and calibrated ``six_position``: the
   segments its detector finds are longer than the captures, so X and y differ by the noise of the extra
   rows; the difference is printed, and both calibrations' error on the six poses.

Figures, not a pass/fail.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import httpx
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from app.calibration import fit_six_position
from tests.e2e.conftest import CHROMIUM, CHROMIUM_ARGS, LAUNCH_TIMEOUT_MS
from tests.e2e.test_board import BOOT, CAPTURED, ORDER, SHIM, pose_rows
from tests.live_server import live_server

G = 9.80665
LOOPS = 3


def board_lines(loops: int) -> tuple[list[str], np.ndarray]:
    """Boot text, the header, then each pose's rows ``loops`` times (the first pose once more while the
    person connects), the board's millis() going on; and the accelerometer rows as printed."""
    header, _ = pose_rows("+z")
    lines, acc = BOOT + [header], []
    t_end = 0
    for label in [ORDER[0]] + ORDER:
        _, rows = pose_rows(label)
        for _ in range(loops):
            shift = t_end + 16 - int(rows[0][0])
            for row in rows:
                lines.append(",".join([str(int(row[0]) + shift)] + row[1:]))
                acc.append([float(v) for v in row[1:4]])
            t_end = int(rows[-1][0]) + shift
    return lines, np.array(acc)


def find_rows(acc: np.ndarray, capture: np.ndarray) -> int:
    """Where a capture's samples start among the rows played (each capture is a run of them)."""
    for i in np.flatnonzero(np.all(acc == capture[0], axis=1)):
        if i + len(capture) <= len(acc) and np.array_equal(acc[i : i + len(capture)], capture):
            return int(i)
    raise AssertionError("a capture's samples are not a run of the rows played")


def run_flow(url: str, lines: list[str], capture_s: float) -> tuple[float, list[dict], dict, str]:
    from playwright.sync_api import sync_playwright

    sent: list[dict] = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, timeout=LAUNCH_TIMEOUT_MS)
        page = browser.new_page(viewport={"width": 1280, "height": 900})
        page.add_init_script(SHIM)
        page.on("request", lambda r: sent.append(r.post_data_json) if r.url.endswith("/captures") else None)
        page.goto(f"{url}/wizard?protocol=six&source=board&capture_s={capture_s:g}")
        page.evaluate("([lines, hz]) => window.__board.play(lines, hz, '\\r\\n')", [lines, 62.5])
        t0 = page.evaluate("performance.now()")
        page.click("#board-usb")
        for label in ORDER:
            page.wait_for_selector(CAPTURED.format(label), state="attached", timeout=120_000)
        page.wait_for_selector("#downloads[data-ready=true]", timeout=60_000)
        elapsed = (page.evaluate("performance.now()") - t0) / 1000.0
        saved = page.evaluate("JSON.parse(localStorage.getItem('trical.wizard.six.board'))")
        cal_id = page.evaluate("document.querySelector('#result-ok').textContent.split(' ')[1]")
        browser.close()
    return elapsed, sent, saved, cal_id


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--capture-s", type=float, default=5.0, help="seconds captured per pose (the wizard's default)")
    parser.add_argument("--turn-s", type=float, default=8.0, help="seconds a person takes to turn the board to a pose")
    args = parser.parse_args()
    lines, acc = board_lines(LOOPS)
    with (
        tempfile.TemporaryDirectory() as tmp,
        live_server({"TRICAL_DATABASE_URL": f"sqlite:///{Path(tmp) / 'trical.db'}"}) as server,
    ):
        elapsed, sent, saved, cal_id = run_flow(server.url, lines, args.capture_s)
        with httpx.Client(base_url=server.url, timeout=60) as http:
            flow = http.get(
                f"/api/v1/calibrations/{cal_id}", headers={"Authorization": f"Bearer {saved['token']}"}
            ).json()
            log = "\n".join(lines[len(BOOT) :]) + "\n"
            rec = http.post("/api/v1/recordings", files={"file": ("board.csv", log.encode(), "text/csv")})
            rec.raise_for_status()
            upload = http.post(
                "/api/v1/calibrations", json={"method": "six_position", "recording_id": rec.json()["id"]}
            ).json()
    print(f"six flow over the Web Serial stand-in, {args.capture_s:g} s a pose, lines at 62.5 Hz:")
    print(
        f"  Connect → verdict: {elapsed:.1f} s of the page's time; with {args.turn_s:g} s a turn for a person's "
        f"hands: {elapsed + 6 * args.turn_s:.1f} s (the issue's bound: 120 s)"
    )
    X, y = np.array(flow["model"]["X"]), np.array(flow["model"]["y"])
    starts = [find_rows(acc, np.array(c["acc"])) for c in sent]
    means = [acc[s : s + len(c["acc"])].mean(axis=0) for s, c in zip(starts, sent)]
    closed = fit_six_position(np.array(means), [c["position"] for c in sent], gravity=G)
    where = ", ".join(f"{c['position']} rows {s}–{s + len(c['acc']) - 1}" for s, c in zip(starts, sent))
    print(f"  captures: {where}")
    print(
        f"  session vs closed form on the captured rows: max |ΔX| {np.abs(X - closed.X).max():.2e}, "
        f"max |Δy| {np.abs(y - closed.y).max():.2e} m/s²"
    )
    Xu, yu = np.array(upload["model"]["X"]), np.array(upload["model"]["y"])
    used = upload.get("segments_used")
    print(
        f"  the same lines uploaded as a log ({rec.json()['n_samples']} rows, {len(rec.json()['segments'])} still "
        f"segments, used {used}): max |ΔX| {np.abs(X - Xu).max():.2e}, max |Δy| {np.abs(y - yu).max():.2e} m/s²"
    )
    for name, body in (("session", flow), ("upload", upload)):
        m = body["metrics"]
        print(
            f"  {name}: error on the six poses {m['error_before_mg']:.2f} mg → {m['error_after_mg']:.3f} mg, "
            f"ok = {body['ok']}"
        )


if __name__ == "__main__":
    main()
