"""Six-position solve latency through the HTTP API, beside a trivial endpoint of the same server.

    python bench/api_latency.py [--requests 500]

Starts `trical serve` on a free loopback port with a temporary SQLite database, then times
sequential requests over one keep-alive connection: POST /api/v1/calibrations (six_position with
Table 1 of Georgieva et al. (ESGI'95), computed and stored durably: SQLite in WAL with synchronous=FULL)
and GET /healthz. Prints p50 and p99 of each and their ratio, and the machine's load average beside
(the client runs on the same machine). Figures, not a pass/fail.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import httpx
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from app.store.engine import SQLITE_PRAGMAS
from tests.conftest import seed_table
from tests.live_server import live_server

LABELS = ["-x", "+x", "-y", "+y", "-z", "+z"]


def timed(call, n: int) -> np.ndarray:
    out = np.empty(n)
    for i in range(n):
        t0 = time.perf_counter()
        call()
        out[i] = time.perf_counter() - t0
    return out * 1000.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--requests", type=int, default=500)
    args = parser.parse_args()
    body = {
        "method": "six_position",
        "gravity": 9.81,
        "readings": [{"up": u, "mean": m} for u, m in zip(LABELS, seed_table(1)[:6].tolist())],
    }
    with (
        tempfile.TemporaryDirectory() as tmp,
        live_server({"TRICAL_DATABASE_URL": f"sqlite:///{tmp}/bench.db"}) as server,
        httpx.Client(base_url=server.url, timeout=30) as http,
    ):

        def solve():
            r = http.post("/api/v1/calibrations", json=body)
            assert r.status_code == 201, r.text

        def health():
            assert http.get("/healthz").status_code == 200

        timed(solve, 20), timed(health, 20)  # warm-up
        solve_ms = timed(solve, args.requests)
        health_ms = timed(health, args.requests)

    def p(a, q):
        return float(np.percentile(a, q))

    one, five, _ = os.getloadavg()
    pragmas = ", ".join(f"{k}={v}" for k, v in SQLITE_PRAGMAS.items())
    print(f"{args.requests} sequential requests per endpoint, one keep-alive connection, loopback; SQLite {pragmas}")
    print(f"load average {one:.2f} (1 min) {five:.2f} (5 min) on {os.cpu_count()} CPUs")
    print(f"{'endpoint':<36}{'p50 ms':>10}{'p99 ms':>10}")
    print(f"{'POST /api/v1/calibrations (six)':<36}{p(solve_ms, 50):>10.2f}{p(solve_ms, 99):>10.2f}")
    print(f"{'GET /healthz':<36}{p(health_ms, 50):>10.2f}{p(health_ms, 99):>10.2f}")
    print(
        f"{'ratio six / healthz':<36}{p(solve_ms, 50) / p(health_ms, 50):>10.2f}"
        f"{p(solve_ms, 99) / p(health_ms, 99):>10.2f}"
    )


if __name__ == "__main__":
    main()
