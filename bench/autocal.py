"""Auto-calibration of a synthetic week at 100 Hz, end to end through the CLI, beside actipy.

    PYTHONPATH=. python bench/autocal.py [--seed 7] [--runs 3] [--dir var] [--no-actipy]

1. Generates (once, cached in ``--dir``) a week at 100 Hz — 60 480 000 samples, float32 .npy,
   726 MB — of rest bouts (posture-like and random orientations) and movement bouts through the
   sensor errors of Farago et al. eq. (17) with 3 mg noise (:mod:`simulations.autocal`), and the
   true parameters beside it (``.json``).
2. Runs ``trical autocal FILE --sampling-rate-hz 100 --unit g --json`` as a subprocess (``python -m
   app.cli``), ``--runs`` times, timing the wall clock; peak memory is the child's ``ru_maxrss``
   (each run is wrapped in its own small process, so the figure is that run's own).
3. Times detection + selection + fit (+ comparison fits) alone in a fresh process.
4. The floor, each in a fresh process timed whole, ``--runs`` times: the process's start (``python -c
   "import numpy"``); one read of the file (4 MB pieces into one buffer); one pass computing the 5 s
   windows' sums (the least an auto-calibration reads and computes) on every core.
5. When actipy is installed (``pip install '.[bench]'``), times its ``calibrate_gravity`` on the
   same samples (as a pandas DataFrame with a DatetimeIndex, which it needs) in a fresh process,
   with its peak memory, and evaluates its coefficients on trical's control points.
6. The summary: trical, actipy's fit alone and the floor side by side, each time with its process's peak
   memory, the data's size and the bound on memory (the data's size + 50 %), and actipy / trical.

It prints figures only; nothing passes or fails.  Note the machine's load (``uptime``): the 2 cores are
shared.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

N_SAMPLES = 7 * 86400 * 100
PARAMS = ("k_xx", "k_yy", "k_zz", "k_xy", "k_xz", "k_yz", "o_x", "o_y", "o_z")


def make_week(path: Path, seed: int) -> dict:
    """Generate the week into ``path`` (memory-mapped) unless it is there; returns the truth."""
    from simulations.autocal import simulate_recording

    meta = path.with_suffix(".json")
    if path.exists() and meta.exists():
        truth = json.loads(meta.read_text())
        if truth.get("seed") == seed and truth.get("n_samples") == N_SAMPLES:
            return truth
    t0 = time.perf_counter()
    out = np.lib.format.open_memmap(path, mode="w+", dtype=np.float32, shape=(N_SAMPLES, 3))
    _, sim = simulate_recording(
        np.random.default_rng(seed), duration_s=N_SAMPLES / 100.0, sampling_rate_hz=100.0, noise_g=0.003, out=out
    )
    out.flush()
    del out
    truth = {
        "seed": seed,
        "n_samples": N_SAMPLES,
        "p": sim.p.tolist(),
        "rest_bouts": int(len(sim.rest_bouts)),
        "generated_in_s": time.perf_counter() - t0,
    }
    meta.write_text(json.dumps(truth))
    return truth


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return env


CPU_S: list[float] = []
"""The CPU time (user + system) of each command :func:`run_measured` ran, in order: beside the wall time, what a
loaded machine inflates less."""


def run_measured(cmd: list[str]) -> tuple[float, int, str]:
    """Run ``cmd`` inside a wrapper process; returns (wall s, the command's peak RSS in kB, stdout), and appends
    its CPU time to :data:`CPU_S`."""
    wrapper = (
        "import resource, subprocess, sys, time, json\n"
        "t = time.perf_counter()\n"
        "p = subprocess.run(sys.argv[1:], stdout=subprocess.PIPE)\n"
        "dt = time.perf_counter() - t\n"
        "sys.stderr.write(json.dumps({'wall': dt, 'rc': p.returncode, "
        "'maxrss': resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, "
        "'cpu': resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime "
        "+ resource.getrusage(resource.RUSAGE_CHILDREN).ru_stime}) + '\\n')\n"
        "sys.stdout.buffer.write(p.stdout)\n"
    )
    p = subprocess.run([sys.executable, "-c", wrapper, *cmd], capture_output=True, env=_env(), cwd=ROOT)
    info = json.loads(p.stderr.decode().strip().splitlines()[-1])
    if info["rc"] not in (0, 3):
        raise SystemExit(f"{cmd} failed with status {info['rc']}")
    CPU_S.append(info["cpu"])
    return info["wall"], info["maxrss"], p.stdout.decode()


def core_child(path: str) -> None:
    """Detection + selection + fit in this process, memory-mapped."""
    t0 = time.perf_counter()
    from app.calibration.autocal import autocalibrate
    from app.calibration.segments.stationary_002 import detect_rest_segments

    t_import = time.perf_counter() - t0
    x = np.load(path, mmap_mode="r")
    t1 = time.perf_counter()
    rest = detect_rest_segments(x, 100.0, gravity=1.0)
    t2 = time.perf_counter()
    res = autocalibrate(rest, compare=False)
    t3 = time.perf_counter()
    autocalibrate(rest, compare=True)
    t4 = time.perf_counter()
    print(
        json.dumps(
            {
                "import_s": t_import,
                "detect_s": t2 - t1,
                "select_fit_s": t3 - t2,
                "select_fit_compare_s": t4 - t3,
                "ok": res.ok,
                "maxrss_kb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,
            }
        )
    )


def read_child(path: str) -> None:
    """The floor's read: the whole file once, in 4 MB pieces into one buffer (no copy of the week kept)."""
    buf = bytearray(4 << 20)
    with open(path, "rb", buffering=0) as f:
        while f.readinto(buf):
            pass


def pass_child(path: str) -> None:
    """The floor's pass: each 5 s window's sums of x, y, z (one matrix-vector product each, as trical's
    detection sums a still segment) over the memory-mapped file, in as many threads as cores."""
    from concurrent.futures import ThreadPoolExecutor

    from app.calibration.segments.stationary_002 import _PageReleaser

    x = np.load(path, mmap_mode="r")
    pages = _PageReleaser(x)  # as trical's detection: the pages read leave the process (its peak stays small)
    seg, step = 500, 500 * 256
    ones = np.ones(seg, dtype=x.dtype)
    whole = (len(x) // seg) * seg
    threads = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    cuts = [(whole // step * k // threads) * step for k in range(threads)] + [whole]

    def part(lo: int, hi: int) -> float:
        total = 0.0
        for s in range(lo, hi, step):
            c = x[s : min(s + step, hi)]
            total += float(np.matmul(ones, c.reshape(-1, seg, 3)).sum())
            pages.release(c)
        return total

    with ThreadPoolExecutor(threads) as pool:
        sum(pool.map(part, cuts[:-1], cuts[1:]))


def actipy_child(path: str) -> None:
    """actipy's calibrate_gravity on the same samples (DataFrame with a DatetimeIndex)."""
    import warnings

    import pandas as pd
    from actipy import processing

    x = np.load(path, mmap_mode="r")
    t0 = time.perf_counter()
    idx = pd.date_range("2026-01-05", periods=len(x), freq="10ms")
    df = pd.DataFrame({"x": x[:, 0], "y": x[:, 1], "z": x[:, 2]}, index=idx)
    t1 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, info = processing.calibrate_gravity(df, _inplace=True)
    t2 = time.perf_counter()
    info = {k: (float(v) if isinstance(v, (int, float, np.floating, np.integer)) else v) for k, v in info.items()}
    print(
        json.dumps(
            {
                "frame_s": t1 - t0,
                "calibrate_s": t2 - t1,
                "info": info,
                "maxrss_kb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,
            }
        )
    )


def _fmt_params(est, true) -> str:
    err = np.abs(np.asarray(est) - np.asarray(true))
    return "  ".join(f"{n} {e:.1e}" for n, e in zip(PARAMS, err))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--dir", type=Path, default=ROOT / "var")
    ap.add_argument("--no-actipy", action="store_true")
    ap.add_argument("--core", help=argparse.SUPPRESS)
    ap.add_argument("--actipy", help=argparse.SUPPRESS)
    ap.add_argument("--read", help=argparse.SUPPRESS)
    ap.add_argument("--pass", dest="pass_", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.core:
        return core_child(args.core)
    if args.actipy:
        return actipy_child(args.actipy)
    if args.read:
        return read_child(args.read)
    if args.pass_:
        return pass_child(args.pass_)

    args.dir.mkdir(parents=True, exist_ok=True)
    path = args.dir / f"autocal_week_seed{args.seed}.npy"
    truth = make_week(path, args.seed)
    p_true = np.array(truth["p"])
    print(
        f"data: {path} ({path.stat().st_size / 1e6:.0f} MB, {N_SAMPLES:,} samples, {truth['rest_bouts']} rest bouts, "
        f"seed {args.seed}); load: {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f} "
        f"on {os.cpu_count()} CPUs"
    )
    # Warm the page cache once so that every run reads the same way.
    subprocess.run(["cat", str(path)], stdout=subprocess.DEVNULL)

    cmd = [sys.executable, "-m", "app.cli", "autocal", str(path), "--sampling-rate-hz", "100", "--unit", "g", "--json"]
    print("\n$ trical autocal " + path.name + " --sampling-rate-hz 100 --unit g --json")
    walls, peaks, cpus, body = [], [], [], None
    for i in range(args.runs):
        wall, peak, out = run_measured(cmd)
        walls.append(wall)
        peaks.append(peak)
        cpus.append(CPU_S[-1])
        body = json.loads(out)
        print(
            f"  run {i + 1}: {wall:.2f} s wall ({cpus[-1]:.2f} s CPU), {N_SAMPLES / wall / 1e6:.1f} M samples/s, "
            f"peak RSS {peak / 1024:.0f} MB"
        )
    best = min(walls)
    print(
        f"  best {best:.2f} s ({N_SAMPLES / best / 1e6:.1f} M samples/s), median {np.median(walls):.2f} s; "
        f"peak RSS max {max(peaks) / 1024:.0f} MB"
    )
    K, o = np.array(body["model"]["K"]), np.array(body["model"]["o"])
    p_est = np.array([K[0, 0], K[1, 1], K[2, 2], K[1, 0], K[2, 0], K[2, 1], *o])
    m, det = body["metrics"], body["detection"]
    print(
        f"  ok {body['ok']}; {det['n_rest']} rest segments of {det['n_segments']}, {m['count']} points, "
        f"{m['count_control']} control points"
    )
    print(f"  |p̂ − p|: {_fmt_params(p_est, p_true)}")
    print(
        f"  held-out |r − 1|: {m['error_before_mg']:.2f} mg before, {m['error_after_mg']:.3f} mg after, "
        f"R = {m['improvement_pct']:.0f} % (eq. (21))"
    )
    print(f"  {'method':<22}{'before mg':>10}{'after mg':>10}{'R %':>9}{'points':>8}")
    for name, row in body["comparison"].items():
        print(
            f"  {name:<22}{row['error_before_mg']:>10.2f}{row['error_after_mg']:>10.3f}"
            f"{row['improvement_pct']:>9.0f}{row['count']:>8}"
        )

    wall, peak, out = run_measured([sys.executable, str(Path(__file__).resolve()), "--core", str(path)])
    core = json.loads(out)
    core_s = core["detect_s"] + core["select_fit_s"]
    print(
        f"\ncore in-process: import {core['import_s']:.2f} s, detection {core['detect_s']:.2f} s, selection + fit "
        f"{core['select_fit_s']:.3f} s (with the comparison fits {core['select_fit_compare_s']:.3f} s); "
        f"detection + selection + fit {core_s:.2f} s = {N_SAMPLES / core_s / 1e6:.0f} M samples/s"
    )

    me = [sys.executable, str(Path(__file__).resolve())]
    floor = {}
    for name, cmd in (
        ("start", [sys.executable, "-c", "import numpy"]),
        ("read", [*me, "--read", str(path)]),
        ("pass", [*me, "--pass", str(path)]),
    ):
        runs = [(*run_measured(cmd)[:2], CPU_S[-1]) for _ in range(args.runs)]
        floor[name] = (min(w for w, _, _ in runs), max(p for _, p, _ in runs), min(c for _, _, c in runs))

    actipy_s = actipy_peak = None
    if not args.no_actipy:
        try:
            import actipy
        except ImportError:
            print("\nactipy is not installed: pip install '.[bench]' to compare")
        else:
            wall, actipy_peak, out = run_measured([*me, "--actipy", str(path)])
            actipy_process_cpu = CPU_S[-1]
            res = json.loads(out)
            info = res["info"]
            actipy_s = res["calibrate_s"]
            print(
                f"\nactipy {actipy.__version__} calibrate_gravity: {actipy_s:.2f} s "
                f"({N_SAMPLES / actipy_s / 1e6:.1f} M samples/s; "
                f"building its DataFrame {res['frame_s']:.2f} s more), "
                f"peak RSS {actipy_peak / 1024:.0f} MB; CalibOK {info.get('CalibOK')}, {info.get('CalibNumSamples')} "
                f"windows, its own error {info.get('CalibErrorBefore(mg)'):.2f} → "
                f"{info.get('CalibErrorAfter(mg)'):.2f} mg"
            )
            print(f"  trical detection + selection + fit is {actipy_s / core_s:.1f}× faster")
            if info.get("CalibOK"):
                slope = np.array([info[f"Calib{a}Slope"] for a in "xyz"])
                icpt = np.array([info[f"Calib{a}Intercept"] for a in "xyz"])
                # actipy: a = intercept + slope·v  ⇔  a = slope (v + intercept/slope)
                p_act = np.r_[slope, 0.0, 0.0, 0.0, icpt / slope]
                print(f"  |p̂ − p| (no cross-axis terms): {_fmt_params(p_act, p_true)}")
                ctl = np.array(body["control"])
                after = np.abs(np.linalg.norm(icpt + ctl * slope, axis=1) - 1.0).mean() * 1000
                before = np.abs(np.linalg.norm(ctl, axis=1) - 1.0).mean() * 1000
                print(f"  on trical's control points: {before:.2f} mg before, {after:.3f} mg after")

    size_mb = path.stat().st_size / 2**20
    print(
        f"\nsummary (best of {args.runs} for trical and the floor; peak RSS of each process; data {size_mb:.0f} MiB, "
        f"bound data + 50 % = {1.5 * size_mb:.0f} MiB); load {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs"
    )

    def row(name: str, seconds: float, peak_kb: float, cpu: str, note: str = "") -> None:
        print(f"  {name:<42}{seconds:>7.2f} s{peak_kb / 1024:>8.0f} MiB{cpu:>14}  {note}")

    print(f"  {'':<42}{'wall':>9}{'peak':>12}{'CPU':>14}")
    row(
        "trical autocal (whole process)",
        best,
        max(peaks),
        f"{min(cpus):.2f} s",
        "within the bound" if max(peaks) / 1024 <= 1.5 * size_mb else "ABOVE the bound",
    )
    if actipy_s is not None and actipy_peak is not None:
        row(
            "actipy calibrate_gravity (its fit alone)",
            actipy_s,
            actipy_peak,
            f"({actipy_process_cpu:.2f} s)",
            "peak of its process, DataFrame included; CPU of the whole process",
        )
    for name, key, note in (
        ("floor: the process's start (import numpy)", "start", ""),
        ("floor: one read of the file", "read", "process included"),
        ("floor: one pass, the 5 s windows' sums", "pass", "process included, every core"),
    ):
        wall, peak, cpu = floor[key]
        row(name, wall, peak, f"{cpu:.2f} s", note)
    if actipy_s is not None:
        print(f"  actipy / trical: {actipy_s / best:.2f}×; trical / floor pass: {best / floor['pass'][0]:.2f}×")
    else:
        print(f"  trical / floor pass: {best / floor['pass'][0]:.2f}×")


if __name__ == "__main__":
    main()
