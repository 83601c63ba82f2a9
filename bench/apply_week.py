"""``trical apply`` on a synthetic week of wear at 100 Hz, beside the read alone: wall time and peak memory.

    PYTHONPATH=. python bench/apply_week.py [--days 1 7] [--seed 7] [--format csv [npy parquet]] [--gyro] [--dir DIR]

For each length asked (days; 7 is the week, 60 480 000 rows):

1. Generates, seeded, in a temporary folder (or ``--dir``): the accelerometer of rest and movement bouts through
   the sensor errors of Farago et al. eq. (17) with 3 mg noise (:mod:`simulations.autocal`, the week of
   bench/autocal.py), written as a CSV ``time,acc_x (g),acc_y (g),acc_z (g)`` a million rows at a time (the time in
   seconds, the samples to 10 µg; ``--gyro`` adds a gyroscope at rest, ``gyr_x (rad/s)`` …, which the
   calibration passes through); and a calibration of the same sensor, a triangular fit (Farago et al.) on 18
   still poses drawn through the same parameters, as a JSON body (``cal.json``).
2. Runs, each as a process of its own inside a small wrapper that reads its ``ru_maxrss`` (RUSAGE_CHILDREN):
   - ``trical apply cal.json week.csv -o out.FORMAT`` (``python -m app.cli``), for each ``--format`` asked;
   - the read alone, the floor: the same CSV read in the same chunks (:func:`app.io.readers.chunks.read_in_chunks`),
     nothing applied or written;
   - the bytes alone: the file read in 4 MB pieces (what any reader of it pays).
3. Prints, per length: rows, file size, wall time, CPU time and peak RSS of each, and the output's size; then the
   peak RSS of 1 day beside 7 (bounded memory: the same, whatever the length).

It prints figures only; nothing passes or fails.  The 2 cores are shared: note ``uptime``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

RATE_HZ = 100.0
PIECE = 1_000_000


def make_recording(folder: Path, days: float, seed: int, gyro: bool = False) -> tuple[Path, Path, float]:
    """The CSV of ``days`` at 100 Hz and the calibration's JSON in ``folder``; returns their paths and the seconds
    the generation took."""
    import dataclasses

    import pyarrow as pa
    import pyarrow.csv as pacsv

    from app.calibration.still.triangular import fit_triangular
    from simulations.autocal import simulate_recording
    from simulations.triangular import random_unit_vectors, uncalibrate

    t0 = time.perf_counter()
    n = int(round(days * 86400 * RATE_HZ))
    rng = np.random.default_rng(seed)
    samples = np.lib.format.open_memmap(folder / "samples.npy", mode="w+", dtype=np.float32, shape=(n, 3))
    _, sim = simulate_recording(rng, duration_s=n / RATE_HZ, sampling_rate_hz=RATE_HZ, noise_g=0.003, out=samples)
    csv = folder / f"week_{days:g}d.csv"
    with open(csv, "wb") as out:
        header = "time,acc_x (g),acc_y (g),acc_z (g)" + (",gyr_x (rad/s),gyr_y (rad/s),gyr_z (rad/s)" if gyro else "")
        out.write(header.encode() + b"\n")
        gyro_rng = np.random.default_rng(seed + 1)
        for s in range(0, n, PIECE):
            e = min(n, s + PIECE)
            x = np.round(np.asarray(samples[s:e], dtype=np.float64), 5)
            table = pa.table(
                {
                    "t": np.round(np.arange(s, e) / RATE_HZ, 2),
                    "x": x[:, 0],
                    "y": x[:, 1],
                    "z": x[:, 2],
                    # A gyroscope at rest (bias and 5 mrad/s of white noise), which the calibration passes through.
                    **(
                        {f"g{a}": np.round(gyro_rng.normal(0.01 * k, 0.005, e - s), 5) for k, a in enumerate("xyz")}
                        if gyro
                        else {}
                    ),
                }
            )
            pacsv.write_csv(table, out, write_options=pacsv.WriteOptions(include_header=False))
    del samples
    (folder / "samples.npy").unlink()
    poses = uncalibrate(sim.p, random_unit_vectors(rng, 18)) + rng.normal(0.0, 0.003 / np.sqrt(500), (18, 3))
    result = dataclasses.replace(fit_triangular(poses, gravity=1.0), unit="g")
    cal = folder / "cal.json"
    cal.write_text(json.dumps({**result.to_dict(), "id": "cal_bench"}))
    return csv, cal, time.perf_counter() - t0


WRAPPER = (
    "import resource, subprocess, sys, time, json\n"
    "t = time.perf_counter()\n"
    "p = subprocess.run(sys.argv[1:], stdout=subprocess.PIPE, stderr=subprocess.PIPE)\n"
    "dt = time.perf_counter() - t\n"
    "r = resource.getrusage(resource.RUSAGE_CHILDREN)\n"
    "sys.stderr.write(p.stderr.decode(errors='replace'))\n"
    "sys.stderr.write(json.dumps({'wall': dt, 'rc': p.returncode, 'maxrss_kb': r.ru_maxrss, "
    "'cpu': r.ru_utime + r.ru_stime}) + '\\n')\n"
)
"""A process that runs the command as its only child and says the child's wall time, peak RSS and CPU time."""


def run_measured(cmd: list[str]) -> dict:
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    p = subprocess.run([sys.executable, "-c", WRAPPER, *cmd], capture_output=True, env=env, cwd=ROOT, timeout=7200)
    lines = p.stderr.decode().strip().splitlines()
    info = json.loads(lines[-1])
    if info["rc"] != 0:
        raise SystemExit(f"{cmd} failed with status {info['rc']}:\n" + "\n".join(lines[-10:-1]))
    return info


READ_ALONE = (
    "import sys\n"
    "from pathlib import Path\n"
    "from app.io.readers.chunks import read_in_chunks\n"
    "rows = sum(c.rows for c in read_in_chunks(Path(sys.argv[1]), name='week').chunks())\n"
    "print(rows)\n"
)
BYTES_ALONE = (
    "import sys\nbuf = bytearray(4 << 20)\nf = open(sys.argv[1], 'rb', buffering=0)\nwhile f.readinto(buf):\n    pass\n"
)


def measure(days: float, seed: int, formats: list[str], folder: Path, gyro: bool = False) -> dict:
    csv, cal, gen_s = make_recording(folder, days, seed, gyro)
    rows = int(round(days * 86400 * RATE_HZ))
    figures = {"days": days, "rows": rows, "csv_mb": csv.stat().st_size / 1e6, "generated_s": gen_s, "apply": {}}
    for fmt in formats:
        out = folder / f"out.{fmt}"
        cmd = [sys.executable, "-m", "app.cli", "apply", str(cal), str(csv), "-o", str(out)]
        figures["apply"][fmt] = {**run_measured(cmd), "out_mb": out.stat().st_size / 1e6}
        out.unlink()
    figures["read"] = run_measured([sys.executable, "-c", READ_ALONE, str(csv)])
    figures["bytes"] = run_measured([sys.executable, "-c", BYTES_ALONE, str(csv)])
    csv.unlink()
    return figures


def line(name: str, f: dict) -> str:
    return f"  {name:<28} {f['wall']:8.1f} s wall  {f['cpu']:8.1f} s CPU  {f['maxrss_kb'] / 1024:8.0f} MB peak RSS"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--days", type=float, nargs="+", default=[1.0, 7.0])
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--format", choices=("csv", "parquet", "npy"), nargs="+", default=["csv"])
    parser.add_argument("--gyro", action="store_true", help="a gyroscope's three columns too (passed through)")
    parser.add_argument("--dir", type=Path, default=None, help="where to write the files (default: a temporary folder)")
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="trical-apply-week-", dir=args.dir))
    print(f"uptime: {os.getloadavg()[0]:.2f} load (1 min), {os.cpu_count()} CPUs; files in {folder}")
    results = []
    try:
        for days in args.days:
            f = measure(days, args.seed, args.format, folder, args.gyro)
            results.append(f)
            print(
                f"{days:g} day(s) at 100 Hz: {f['rows']:,} rows, CSV {f['csv_mb']:.0f} MB "
                f"(generated in {f['generated_s']:.0f} s)"
            )
            for fmt, a in f["apply"].items():
                print(line(f"trical apply -> .{fmt}", a) + f"  ({a['out_mb']:.0f} MB written)")
            print(line("read alone (chunks, floor)", f["read"]))
            print(line("bytes alone (4 MB pieces)", f["bytes"]))
            rates = ", ".join(f"-> .{fmt} {f['rows'] / a['wall'] / 1e6:.2f}" for fmt, a in f["apply"].items())
            print(f"  M rows/s: apply {rates}; read alone {f['rows'] / f['read']['wall'] / 1e6:.2f}", flush=True)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    if len(results) > 1:
        print("peak RSS by length (bounded memory: the same whatever the length):")
        for f in results:
            peaks = ", ".join(f".{fmt} {a['maxrss_kb'] / 1024:.0f} MB" for fmt, a in f["apply"].items())
            print(f"  {f['days']:g} day(s): apply {peaks}; read alone {f['read']['maxrss_kb'] / 1024:.0f} MB")


if __name__ == "__main__":
    main()
