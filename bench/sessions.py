"""Wizard sessions through the HTTP API: what a phone waits for at each step.

    python bench/sessions.py [--runs 20]

Starts `trical serve` on a free loopback port with a temporary SQLite database and runs wizard
sessions as the page does: create, one capture per position (the raw samples of capture_s = 5 s
at 60 Hz, 300 samples, JSON), solve. The six flow's poses come from m = X a + y rounded to the
browser's 0.1 m/s²; the cube24 flow is the phone-in-cube simulation of tests/cube_phone.py (Särkkä et al.'s
motion). Prints p50/p99 of each call and the server's time per session, beside the time a person
spends (capture_s per position). Figures, not a pass/fail.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import httpx
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from tests.cube_phone import phone_cube
from tests.live_server import live_server
from tests.phone_poses import pose_samples

SIX = ["+z", "-x", "+y", "-z", "+x", "-y"]


def _timed(call) -> tuple[float, httpx.Response]:
    t0 = time.perf_counter()
    r = call()
    return (time.perf_counter() - t0) * 1000.0, r


def run(http: httpx.Client, protocol: str, captures: list[dict]) -> dict[str, list[float]]:
    times: dict[str, list[float]] = {"create": [], "capture": [], "solve": []}
    ms, r = _timed(lambda: http.post("/api/v1/sessions", json={"protocol": protocol}))
    assert r.status_code == 201, r.text
    times["create"].append(ms)
    s = r.json()
    h = {"Authorization": f"Bearer {s['token']}"}
    for body in captures:
        # _timed calls the lambda at once, in this iteration: B023's late binding cannot happen.
        ms, r = _timed(lambda: http.post(f"/api/v1/sessions/{s['id']}/captures", json=body, headers=h))  # noqa: B023
        assert r.status_code == 201, r.text
        times["capture"].append(ms)
    ms, r = _timed(lambda: http.post(f"/api/v1/sessions/{s['id']}/solve", headers=h))
    assert r.status_code == 201, r.text
    times["solve"].append(ms)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=20)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    six = [pose_samples(label, rng) for label in SIX]
    phone = phone_cube(0, static_s=5.0)
    cube = [phone.capture(k) for k in range(1, 25)]

    def p(a, q):
        return float(np.percentile(a, q))

    with (
        tempfile.TemporaryDirectory() as tmp,
        live_server({"TRICAL_DATABASE_URL": f"sqlite:///{tmp}/bench.db"}) as server,
        httpx.Client(base_url=server.url, timeout=120) as http,
    ):
        run(http, "six", six)  # warm-up
        for protocol, captures, runs, person_s in (
            ("six", six, args.runs, 6 * 5),
            ("cube24", cube, max(1, args.runs // 5), 24 * 5),
        ):
            all_times: dict[str, list[float]] = {"create": [], "capture": [], "solve": []}
            for _ in range(runs):
                for k, v in run(http, protocol, captures).items():
                    all_times[k] += v
            per_session = (sum(all_times["create"]) + sum(all_times["capture"]) + sum(all_times["solve"])) / runs
            print(
                f"{protocol}: {runs} sessions, {len(captures)} captures of "
                f"{len(captures[0]['acc'])} samples each, one server, loopback"
            )
            print(f"  {'call':<10}{'p50 ms':>10}{'p99 ms':>10}")
            for k, v in all_times.items():
                print(f"  {k:<10}{p(v, 50):>10.1f}{p(v, 99):>10.1f}")
            print(
                f"  server time per session {per_session / 1000:.2f} s; the person holds still "
                f"{person_s} s (capture_s = 5)"
            )


if __name__ == "__main__":
    main()
