"""Load test: six-position calibrations a second that one server process takes over HTTP, durably stored.

    python bench/load_six.py [--clients 50] [--requests 1000] [--profile server.prof]

Starts `trical serve` (one uvicorn process) on a free loopback port with a temporary SQLite database
(WAL journal, synchronous=FULL: a calibration is on disk when its commit returns, before its 201), then
sends `--requests` POST /api/v1/calibrations (six_position, Table 1 of Georgieva et al. (ESGI'95) with
noise) from `--clients` concurrent clients, each with its own keep-alive connection opened before the
clock starts, after `--warmup` sequential ones. Prints calibrations a second, p50/p90/p99 latency of
the POST and the error count, then reads back every acknowledged calibration (GET) and counts those
missing or different. The load average of the machine is printed beside: the clients run on the same
machine as the server. So is the server's CPU time a calibration (from /proc, Linux), which a busy
machine changes less than the rate.

With `--profile OUT` the server runs under cProfile in every thread (bench/serve_profiled.py) and the
functions that take most of its CPU time are printed as shares of it; its rates are not the server's.
Loopback only; bounded in count and time.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import pstats
import sqlite3
import sys
import tempfile
import time
from pathlib import Path

import httpx
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from app.store.engine import SQLITE_PRAGMAS
from tests.conftest import seed_table
from tests.live_server import free_port, live_server

LABELS = ["-x", "+x", "-y", "+y", "-z", "+z"]
HERE = Path(__file__).resolve().parent


def six_body(i: int, rng) -> dict:
    means = seed_table(1)[:6] + rng.normal(0, 0.01, (6, 3))
    return {
        "method": "six_position",
        "device_id": f"dev{i % 50}",
        "gravity": 9.81,
        "readings": [{"up": u, "mean": m} for u, m in zip(LABELS, means.tolist())],
    }


async def client_loop(
    http: httpx.AsyncClient, jobs: asyncio.Queue, latencies: list, errors: list, acknowledged: dict, rng
):
    while True:
        try:
            i = jobs.get_nowait()
        except asyncio.QueueEmpty:
            return
        body = six_body(i, rng)
        t0 = time.perf_counter()
        try:
            r = await http.post("/api/v1/calibrations", json=body)
        except httpx.HTTPError as exc:
            errors.append(f"{type(exc).__name__}: {exc}")
            continue
        if r.status_code != 201:
            errors.append(f"POST {r.status_code}: {r.text[:200]}")
            continue
        latencies.append(time.perf_counter() - t0)
        answer = r.json()
        acknowledged[answer["id"]] = answer


async def run(url: str, clients: int, requests: int):
    jobs: asyncio.Queue = asyncio.Queue()
    for i in range(requests):
        jobs.put_nowait(i)
    latencies: list = []
    errors: list = []
    acknowledged: dict = {}
    # Each client made and connected before the clock starts: making one (its TLS context, though unused)
    # takes tens of ms of the bench's own CPU, which the first requests' latency would otherwise hold.
    https = [httpx.AsyncClient(base_url=url, timeout=60) for _ in range(clients)]
    try:
        await asyncio.gather(*(http.get("/healthz") for http in https))
        t0 = time.perf_counter()
        await asyncio.wait_for(
            asyncio.gather(
                *(
                    client_loop(http, jobs, latencies, errors, acknowledged, np.random.default_rng(c))
                    for c, http in enumerate(https)
                )
            ),
            timeout=600,
        )
        wall = time.perf_counter() - t0
    finally:
        await asyncio.gather(*(http.aclose() for http in https))
    return wall, np.array(latencies) * 1000.0, errors, acknowledged


def read_back(http: httpx.Client, acknowledged: dict) -> tuple[int, int]:
    """(missing, different): acknowledged calibrations not found, and found with other figures than the
    POST answered (the model and metrics; the GET adds the verdict the list and the page read)."""
    missing = different = 0
    for cal_id, posted in acknowledged.items():
        got = http.get(f"/api/v1/calibrations/{cal_id}")
        if got.status_code != 200:
            missing += 1
            continue
        stored = got.json()
        if any(stored.get(k) != posted.get(k) for k in ("id", "created_at", "model", "metrics", "device_id")):
            different += 1
    return missing, different


def cpu_seconds(pid: int) -> float | None:
    """The CPU time (user + system) process ``pid`` has used, from /proc (Linux); None elsewhere."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rpartition(")")[2].split()
    except OSError:
        return None
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime, stime: fields 14 and 15


def load() -> str:
    one, five, _ = os.getloadavg()
    return f"load average {one:.2f} (1 min) {five:.2f} (5 min) on {os.cpu_count()} CPUs"


def print_profile(path: Path, top: int) -> None:
    stats = pstats.Stats(str(path))
    total = sum(tt for (_cc, _nc, tt, _ct, _callers) in stats.stats.values())  # type: ignore[attr-defined]
    print(f"\nserver CPU time under the profiler {total:.2f} s; top {top} by cumulative share:")
    rows = sorted(stats.stats.items(), key=lambda kv: kv[1][3], reverse=True)  # type: ignore[attr-defined]
    for (file, line, name), (_cc, nc, tt, ct, _callers) in rows[:top]:
        where = f"{Path(file).name}:{line}" if line else file
        print(f"  cum {100 * ct / total:5.1f} %  self {100 * tt / total:5.1f} %  {nc:>8}  {name}  {where}")
    print(f"top {top} by own (self) share:")
    for (file, line, name), (_cc, nc, tt, ct, _callers) in sorted(rows, key=lambda kv: kv[1][2], reverse=True)[:top]:
        where = f"{Path(file).name}:{line}" if line else file
        print(f"  self {100 * tt / total:5.1f} %  cum {100 * ct / total:5.1f} %  {nc:>8}  {name}  {where}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, default=50)
    parser.add_argument("--requests", type=int, default=1000)
    parser.add_argument("--warmup", type=int, default=20, help="Sequential calibrations before the timed ones.")
    parser.add_argument("--profile", type=Path, help="Run the server under cProfile and write its profile here.")
    parser.add_argument("--top", type=int, default=30, help="Lines of the profile printed.")
    args = parser.parse_args()
    port = free_port()
    command = None
    if args.profile:
        command = [sys.executable, str(HERE / "serve_profiled.py"), "--port", str(port), "--out", str(args.profile)]
    print(load(), "(before)")
    with tempfile.TemporaryDirectory() as tmp:
        database = Path(tmp) / "load.db"
        with live_server({"TRICAL_DATABASE_URL": f"sqlite:///{database}"}, port=port, command=command) as server:
            with httpx.Client(base_url=server.url, timeout=30) as http:
                rng = np.random.default_rng(12345)
                for i in range(args.warmup):
                    assert http.post("/api/v1/calibrations", json=six_body(i, rng)).status_code == 201
            assert server.process is not None
            cpu_before = cpu_seconds(server.process.pid)
            wall, lat, errors, acknowledged = asyncio.run(run(server.url, args.clients, args.requests))
            cpu_after = cpu_seconds(server.process.pid)
            print(load(), "(after)")
            missing = different = -1  # not read back under the profiler, whose profile is of the POSTs
            if not args.profile:
                with httpx.Client(base_url=server.url, timeout=30) as http:
                    missing, different = read_back(http, acknowledged)
        with sqlite3.connect(database) as db:
            journal = db.execute("PRAGMA journal_mode").fetchone()[0]
    pragmas = ", ".join(f"{k}={v}" for k, v in SQLITE_PRAGMAS.items())
    print(
        f"{args.requests} six-position calibrations (POST, computed and stored) from {args.clients} concurrent "
        f"clients, one server process, loopback; SQLite {pragmas} (the file's journal: {journal})"
    )
    print(
        f"wall {wall:.2f} s, {len(lat) / wall:.1f} calibrations/s, errors {len(errors)}, "
        f"acknowledged {len(acknowledged)}: missing on read-back {missing}, different {different}"
    )
    if cpu_before is not None and cpu_after is not None and len(lat):
        cpu_ms = 1000 * (cpu_after - cpu_before) / len(lat)
        print(
            f"server CPU {cpu_ms:.2f} ms a calibration (user + system, /proc): at most {1000 / cpu_ms:.0f} "
            "calibrations/s on one free core"
        )
    if len(lat):
        print(
            f"latency ms: p50 {np.percentile(lat, 50):.1f}  p90 {np.percentile(lat, 90):.1f}  "
            f"p99 {np.percentile(lat, 99):.1f}  max {lat.max():.1f}"
        )
    for e in errors[:5]:
        print("error:", e)
    if args.profile:
        print_profile(args.profile, args.top)


if __name__ == "__main__":
    main()
