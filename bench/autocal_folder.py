"""Wall time of ``trical autocal FOLDER`` on local processes beside a Dask LocalCluster.

    PYTHONPATH=. python bench/autocal_folder.py [--files 8] [--hours 24] [--rate 25] [--workers CORES] [--runs 2]

Generates (in a temporary folder) ``--files`` synthetic recordings of ``--hours`` each at ``--rate`` Hz
(:mod:`simulations.autocal`), then times ``trical autocal FOLDER --json`` run as a
subprocess, ``--runs`` times each way: with ``--workers`` local processes, and with
``--dask-scheduler`` on a ``dask.distributed.LocalCluster`` of as many single-threaded worker
processes (started once, before the timings; its start-up is printed apart). Needs the dask extra
(``pip install '.[dask]'``).

It prints figures only; nothing passes or fails.  Note the machine's load (``uptime``): the 2 cores are
shared.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from simulations.autocal import simulate_recording  # noqa: E402 - after sys.path.insert


def run_folder(folder: Path, rate: float, db: Path, *extra: str) -> tuple[float, list[dict], str]:
    env = {**os.environ, "TRICAL_DATABASE_URL": f"sqlite:///{db}"}
    cmd = [
        sys.executable,
        "-m",
        "app.cli",
        "autocal",
        str(folder),
        "--sampling-rate-hz",
        str(rate),
        "--unit",
        "g",
        "--json",
        *extra,
    ]
    start = time.perf_counter()
    out = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if out.returncode not in (0, 3):
        raise SystemExit(f"trical autocal failed ({out.returncode}): {out.stderr.strip()}")
    return wall, json.loads(out.stdout), out.stderr


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--files", type=int, default=8)
    ap.add_argument("--hours", type=float, default=24.0)
    ap.add_argument("--rate", type=float, default=25.0)
    ap.add_argument("--workers", type=int, default=len(os.sched_getaffinity(0)))
    ap.add_argument("--runs", type=int, default=2)
    ap.add_argument("--seed", type=int, default=7)
    args = ap.parse_args()
    from dask.distributed import LocalCluster

    with tempfile.TemporaryDirectory(prefix="trical-bench-folder-") as tmp:
        folder = Path(tmp) / "recordings"
        folder.mkdir()
        rng = np.random.default_rng(args.seed)
        for i in range(args.files):
            x, _ = simulate_recording(rng, duration_s=args.hours * 3600, sampling_rate_hz=args.rate)
            np.save(folder / f"rec_{i:03d}.npy", x)
        n = int(args.hours * 3600 * args.rate)
        print(
            f"{args.files} recordings of {args.hours:g} h at {args.rate:g} Hz ({n / 1e6:.2f} M samples each, "
            f"{args.files * n * 12 / 1e6:.0f} MB float32); {args.workers} workers; load {os.getloadavg()[0]:.2f}"
        )
        start = time.perf_counter()
        with LocalCluster(
            n_workers=args.workers, processes=True, threads_per_worker=1, host="127.0.0.1", dashboard_address=None
        ) as cluster:
            print(f"LocalCluster start-up {time.perf_counter() - start:.2f} s ({cluster.scheduler_address})")
            print(f"{'run':>4}{'local s':>10}{'dask s':>10}{'dask/local':>12}  same result")
            for run in range(1, args.runs + 1):
                local_s, local, lines = run_folder(
                    folder, args.rate, Path(tmp) / "db.sqlite", "--workers", str(args.workers)
                )
                dask_s, dask, _ = run_folder(
                    folder, args.rate, Path(tmp) / "db.sqlite", "--dask-scheduler", cluster.scheduler_address
                )
                same = all(a.get("ok") == b.get("ok") and a.get("model") == b.get("model") for a, b in zip(local, dask))
                print(f"{run:>4}{local_s:>10.2f}{dask_s:>10.2f}{dask_s / local_s:>12.2f}  {same}")
                if run == 1:
                    print("     its progress (stderr, a line per file as it finishes):")
                    print("\n".join(f"       {line}" for line in lines.splitlines()))
        ok = sum(1 for b in local if b.get("ok"))
        print(f"{ok} of {len(local)} recordings calibrated")


if __name__ == "__main__":
    main()
