"""Load test: many concurrent clients running the six-position flow against one server.

    python bench/load_six.py [--clients 50] [--requests 1000]

Starts `trical serve` on a free loopback port with a temporary SQLite database, then runs
`--requests` six-position calibrations (POST, then GET of the stored resource) spread over
`--clients` concurrent clients, each with its own keep-alive connection. Prints throughput,
p50/p90/p99 latency and the error count, and checks afterwards that every acknowledged
calibration can be read back. Loopback only; bounded in count and time.
"""

from __future__ import annotations

import argparse
import asyncio
import sys
import tempfile
import time
from pathlib import Path

import httpx
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from tests.conftest import seed_table
from tests.live_server import live_server

LABELS = ["-x", "+x", "-y", "+y", "-z", "+z"]


async def client_loop(url: str, jobs: asyncio.Queue, latencies: list, errors: list, ids: list, rng):
    async with httpx.AsyncClient(base_url=url, timeout=60) as http:
        while True:
            try:
                i = jobs.get_nowait()
            except asyncio.QueueEmpty:
                return
            means = seed_table(1)[:6] + rng.normal(0, 0.01, (6, 3))
            body = {
                "method": "six_position",
                "device_id": f"dev{i % 50}",
                "gravity": 9.81,
                "readings": [{"up": u, "mean": m} for u, m in zip(LABELS, means.tolist())],
            }
            t0 = time.perf_counter()
            try:
                r = await http.post("/api/v1/calibrations", json=body)
                if r.status_code != 201:
                    errors.append(f"POST {r.status_code}: {r.text[:200]}")
                    continue
                got = await http.get(f"/api/v1/calibrations/{r.json()['id']}")
                if got.status_code != 200:
                    errors.append(f"GET {got.status_code}")
                    continue
                ids.append(r.json()["id"])
                latencies.append(time.perf_counter() - t0)
            except httpx.HTTPError as exc:
                errors.append(f"{type(exc).__name__}: {exc}")


async def run(url: str, clients: int, requests: int):
    jobs: asyncio.Queue = asyncio.Queue()
    for i in range(requests):
        jobs.put_nowait(i)
    latencies: list = []
    errors: list = []
    ids: list = []
    t0 = time.perf_counter()
    await asyncio.wait_for(
        asyncio.gather(
            *(client_loop(url, jobs, latencies, errors, ids, np.random.default_rng(c)) for c in range(clients))
        ),
        timeout=600,
    )
    return time.perf_counter() - t0, np.array(latencies) * 1000.0, errors, ids


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, default=50)
    parser.add_argument("--requests", type=int, default=1000)
    args = parser.parse_args()
    with (
        tempfile.TemporaryDirectory() as tmp,
        live_server({"TRICAL_DATABASE_URL": f"sqlite:///{tmp}/load.db"}) as server,
    ):
        wall, lat, errors, ids = asyncio.run(run(server.url, args.clients, args.requests))
        with httpx.Client(base_url=server.url, timeout=30) as http:
            missing = sum(http.get(f"/api/v1/calibrations/{i}").status_code != 200 for i in ids)
    print(
        f"{args.requests} six-position flows (POST + GET) from {args.clients} concurrent clients, one server, loopback"
    )
    print(f"wall {wall:.2f} s, {len(lat) / wall:.1f} flows/s, errors {len(errors)}, acknowledged but missing {missing}")
    if len(lat):
        print(
            f"latency ms: p50 {np.percentile(lat, 50):.1f}  p90 {np.percentile(lat, 90):.1f}  "
            f"p99 {np.percentile(lat, 99):.1f}  max {lat.max():.1f}"
        )
    for e in errors[:5]:
        print("error:", e)


if __name__ == "__main__":
    main()
