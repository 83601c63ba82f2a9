"""Benchmark of the noise characterisation (the Allan deviation, ``trical noise``) against allantools.

    PYTHONPATH=. python bench/noise.py [--dir var] [--runs 3]
    PYTHONPATH=. python bench/noise.py --no-night          # skip the 8 h six-axis night

Generates once, cached under ``--dir`` (seeded ``np.random.default_rng``):

* ``noise_gyr_3h_200hz_….npy``: 3 h at 200 Hz of a gyroscope, N×4 (time in s first, then x, y, z in
  rad/s): white noise of density N, a rate random walk K, and flicker noise (the bias instability
  B) as a sum of first-order Gauss–Markov processes with correlation times 1 s … 1000 s, four per
  decade, whose power spectral density approximates B² / (2π f) (IEEE Std 952-1997, Annex C); B is
  large enough that its floor (0.664 B) lies above the crossing of the white noise and the random
  walk, so that a flat part shows;
* ``noise_night_8h_200hz_….csv``: 8 h at 200 Hz of six axes (accelerometer and gyroscope, with a
  header row ``time_s,acc_x,…,gyr_z``), for the peak memory of a night's recording (the issue's
  bound is 2 GB).

Then, in one run, times side by side, ``--runs`` times each, in turn (min and median of the wall time,
the peak resident memory of the child):

(a) ``python -m app.cli noise FILE --sampling-rate-hz 200 --sensor gyr --json``, end to end;
(b) what a user would run instead: a Python child that loads the same file with numpy and runs
    allantools' ``oadev`` on the three axes at the same τ (read from trical's JSON, ``adev.gyr.tau_s``,
    as m = τ·fs; octave-spaced m when trical gave none);
(c) the floor, on the same file: the process's start (``python -c "import numpy"``), then one read of
    the file (``numpy.load``), then one pass of trical's inner loop over the three axes (the phase and
    the second differences at one τ: what each of the 61 τ costs at least), each a child of its own.

and the largest relative difference between trical's Allan deviation and allantools' (the issue asks
1e-9), the data's size and the bound on the peak memory (the data's size plus 50 %).

Each child is started by a small launcher process that forks it and reads its peak memory with
``os.wait4``: Linux keeps the peak of the process that called ``exec`` (this script, holding the
generated data) in the child's, so a child started from here directly would report this script's.
Every command runs once untimed first, so that Python's compiled modules are written as on a user's
machine after its first run (``PYTHONDONTWRITEBYTECODE`` is dropped for the children).

Prints figures only; nothing passes or fails. allantools comes with the ``bench`` extra
(``pip install -e '.[bench]'``).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.signal import lfilter

from app.calibration.noise.allan import FUSED, NOT_BUILT

FS = 200.0
TRUTH = {"noise_density": 2.0e-3, "random_walk": 4.0e-5, "bias_instability": 1.0e-3}  # rad/s/√Hz, rad/s·√Hz, rad/s
SEED = 20250131

ALLANTOOLS_CHILD = """
import json, sys
import numpy as np
import allantools
path, fs, ms = sys.argv[1], float(sys.argv[2]), json.loads(sys.argv[3])
data = np.load(path)
taus = [m / fs for m in ms]
out = [allantools.oadev(np.ascontiguousarray(data[:, 1 + i]), rate=fs, data_type="freq", taus=taus)[1].tolist()
       for i in range(3)]
json.dump(out, sys.stdout)
"""


FLOOR_READ = """
import sys
import numpy as np
data = np.load(sys.argv[1])
"""

FLOOR_PASS = """
import sys
import numpy as np
from app.calibration.noise.allan import _sums_of_share, phase_of
data = np.load(sys.argv[1], mmap_mode="r")
for k in range(3):
    x, _ = phase_of(data[:, 1 + k], float(sys.argv[2]))
    _sums_of_share(x, np.array([1]), 0, 1)
"""

LAUNCHER = """
import json, os, sys, time
start = time.perf_counter()
pid = os.fork()
if pid == 0:
    os.execv(sys.argv[2], sys.argv[2:])
_, status, usage = os.wait4(pid, 0)
wall = time.perf_counter() - start
with open(sys.argv[1], "w") as f:
    json.dump([wall, usage.ru_maxrss / 1024, os.waitstatus_to_exitcode(status), usage.ru_utime + usage.ru_stime], f)
"""
"""Forks the command from a small process and writes its wall time, peak RSS (MiB), exit status and CPU time."""


def flicker(rng: np.random.Generator, n: int, fs: float, b: float, axes: int) -> np.ndarray:
    """Flicker rate noise of bias instability ``b``: Gauss–Markov processes x_k = φ x_{k−1} + q √(1−φ²) w_k
    with τ_c log-spaced over 1 s … 1000 s, d = 4 per decade; their summed spectrum
    Σ 2 q² τ_c / (1 + (2π f τ_c)²) ≈ q² d / (2 ln 10 · f), set equal to b² / (2π f): q² = b² ln 10 / (π d)."""
    d = 4
    taus = np.logspace(0, 3, 3 * d + 1)
    q = b * np.sqrt(np.log(10) / (np.pi * d))
    out = np.zeros((n, axes))
    for tau_c in taus:
        phi = np.exp(-1.0 / (fs * tau_c))
        w = rng.standard_normal((n, axes))
        out += lfilter([q * np.sqrt(1 - phi**2)], [1.0, -phi], w, axis=0)
    return out


def gyro(rng: np.random.Generator, n: int, fs: float, axes: int = 3) -> np.ndarray:
    """White noise N √fs per sample, a rate random walk of K / √fs per sample, and the flicker."""
    white = rng.standard_normal((n, axes)) * TRUTH["noise_density"] * np.sqrt(fs)
    walk = np.cumsum(rng.standard_normal((n, axes)) * TRUTH["random_walk"] / np.sqrt(fs), axis=0)
    return 0.002 + white + walk + flicker(rng, n, fs, TRUTH["bias_instability"], axes)


def make_gyr_file(folder: Path, hours: float) -> Path:
    path = folder / f"noise_gyr_{hours:g}h_{FS:g}hz_seed{SEED}_b{TRUTH['bias_instability']:g}.npy"
    if not path.exists():
        n = int(hours * 3600 * FS)
        data = np.column_stack([np.arange(n) / FS, gyro(np.random.default_rng(SEED), n, FS)])
        np.save(path, data)
    return path


def make_night_file(folder: Path, hours: float) -> Path:
    """Six axes as a CSV log with a header row (the .npy reader holds one sensor only)."""
    import pyarrow as pa
    import pyarrow.csv as pacsv

    path = folder / f"noise_night_{hours:g}h_{FS:g}hz_seed{SEED}_b{TRUTH['bias_instability']:g}.csv"
    if not path.exists():
        rng = np.random.default_rng(SEED + 1)
        n = int(hours * 3600 * FS)
        acc = np.array([0.0, 0.0, 9.80665]) + 10 * gyro(rng, n, FS)  # m/s², same noise shape scaled
        gyr = gyro(rng, n, FS)
        cols = {"time_s": np.arange(n) / FS}
        cols |= {f"acc_{a}": acc[:, i] for i, a in enumerate("xyz")}
        cols |= {f"gyr_{a}": gyr[:, i] for i, a in enumerate("xyz")}
        del acc, gyr
        pacsv.write_csv(pa.table(cols), path)
    return path


def run(cmd: list[str]) -> tuple[float, float, int, str, str, float]:
    """Wall time (s), peak RSS of the child (MiB), exit status, stdout, stderr, CPU time (user + system, s,
    all threads: less disturbed than the wall time by other work on the machine) (module docstring: the
    launcher)."""
    root = Path(__file__).resolve().parent.parent
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    with (
        tempfile.TemporaryFile("w+") as out,
        tempfile.TemporaryFile("w+") as err,
        tempfile.NamedTemporaryFile("r", suffix=".json") as figures,
    ):
        subprocess.run(
            [sys.executable, "-c", LAUNCHER, figures.name, *cmd],
            stdout=out,
            stderr=err,
            cwd=root,
            env={**env, "PYTHONPATH": str(root)},
            check=True,
        )
        wall, rss, status, cpu = json.load(figures)
        out.seek(0)
        err.seek(0)
        return wall, rss, status, out.read(), err.read(), cpu


def trical_cmd(path: Path, sensor: str | None) -> list[str]:
    cmd = [sys.executable, "-m", "app.cli", "noise", str(path), "--sampling-rate-hz", f"{FS:g}", "--json"]
    return cmd + (["--sensor", sensor] if sensor else [])


def summary(name: str, runs: list[tuple[float, float, float]]) -> tuple[float, float]:
    walls, rss, cpu = [r[0] for r in runs], [r[1] for r in runs], [r[2] for r in runs]
    print(
        f"{name:<44} wall min {min(walls):5.2f} s  median {statistics.median(walls):5.2f} s  "
        f"CPU median {statistics.median(cpu):5.2f} s  peak RSS max {max(rss):4.0f} MiB"
    )
    return min(walls), statistics.median(walls)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dir", type=Path, default=Path("var"), help="where the generated recordings are cached")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--hours", type=float, default=3.0, help="length of the gyroscope recording")
    ap.add_argument("--night-hours", type=float, default=8.0)
    ap.add_argument("--no-night", action="store_true", help="skip the six-axis night")
    args = ap.parse_args()
    args.dir.mkdir(parents=True, exist_ok=True)

    t0 = time.perf_counter()
    path = make_gyr_file(args.dir, args.hours)
    print(
        f"gyroscope: {path} ({path.stat().st_size / 2**20:.0f} MiB, {args.hours:g} h at {FS:g} Hz; "
        f"ready in {time.perf_counter() - t0:.1f} s)"
    )
    print("truth: " + ", ".join(f"{k} {v:.3g}" for k, v in TRUTH.items()))

    python = sys.executable
    ms = None
    _, _, status, out, err, _ = run(trical_cmd(path, "gyr"))  # untimed: compiles trical's modules once
    if status in (0, 3):
        ms = sorted({max(1, round(t * FS)) for t in json.loads(out)["adev"]["gyr"]["tau_s"]})
    else:
        print(f"trical noise failed (exit {status}): {err.strip().splitlines()[-1] if err.strip() else '-'}")
    if ms is None:
        n = int(args.hours * 3600 * FS)
        ms = [2**k for k in range(int(np.log2(n // 4)) + 1)]
        print(f"(no τ from trical: allantools runs on {len(ms)} octave-spaced m instead)")
    commands = {
        "trical": trical_cmd(path, "gyr"),
        "allantools": [python, "-c", ALLANTOOLS_CHILD, str(path), f"{FS:g}", json.dumps(ms)],
        "start": [python, "-c", "import numpy"],
        "read": [python, "-c", FLOOR_READ, str(path)],
        "pass": [python, "-c", FLOOR_PASS, str(path), f"{FS:g}"],
    }
    runs: dict[str, list[tuple[float, float, float]]] = {name: [] for name in commands}
    outputs: dict[str, str] = {}
    for name, cmd in commands.items():
        if name != "trical":
            run(cmd)  # untimed, as trical's first run
    for _ in range(args.runs):
        for name, cmd in commands.items():  # in turn, so that a busy moment of the machine spreads over all
            wall, rss, status, out, err, cpu = run(cmd)
            if status not in (0, 3):
                print(f"{name} failed (exit {status}): {err.strip().splitlines()[-1] if err.strip() else '-'}")
                continue
            runs[name].append((wall, rss, cpu))
            outputs[name] = out

    estimate = json.loads(outputs["trical"])["model"]["gyr"] if "trical" in outputs else None
    if estimate:
        print("trical: " + ", ".join(f"{k} {estimate[k]}" for k in TRUTH))
    if "trical" in outputs and "allantools" in outputs:
        ours = np.array(json.loads(outputs["trical"])["adev"]["gyr"]["value"])
        theirs = np.array(json.loads(outputs["allantools"])).T
        if ours.shape == theirs.shape:
            worst = float(np.max(np.abs(ours / theirs - 1)))
            print(f"Allan deviation, trical against allantools: largest relative difference {worst:.1e}")

    size = path.stat().st_size / 2**20
    print(
        f"\n{len(ms)} τ values, 3 axes, {args.runs} runs each; the data: {size:.0f} MiB, so the peak memory bound "
        f"(data + 50 %) is {1.5 * size:.0f} MiB"
    )
    print(
        "trical's Allan sums (and the floor's pass): "
        + (
            "the compiled, fused loop (app/calibration/noise/allan_fused.pyx)"
            if FUSED
            else f"the numpy loop ({NOT_BUILT})"
        )
    )
    best = {}
    labels = {
        "trical": "(a) trical noise --sensor gyr",
        "allantools": "(b) numpy.load + allantools.oadev",
        "start": "(c) floor: start (python -c 'import numpy')",
        "read": "    floor: start + numpy.load",
        "pass": "    floor: start + one pass (1 τ, 3 axes)",
    }
    for name, label in labels.items():
        if runs[name]:
            best[name] = summary(label, runs[name])
    if "trical" in best and "allantools" in best:
        print(
            f"ratio trical / allantools: min {best['trical'][0] / best['allantools'][0]:.2f}, "
            f"median {best['trical'][1] / best['allantools'][1]:.2f} "
            f"(allantools / trical: {best['allantools'][1] / best['trical'][1]:.1f}×)"
        )
    if "trical" in best and "pass" in best:
        print(f"trical − floor (start + one pass), median: {best['trical'][1] - best['pass'][1]:.2f} s")

    if not args.no_night:
        t0 = time.perf_counter()
        night = make_night_file(args.dir, args.night_hours)
        print(
            f"\nnight: {night} ({night.stat().st_size / 2**20:.0f} MiB, {args.night_hours:g} h at {FS:g} Hz, "
            f"acc + gyr; ready in {time.perf_counter() - t0:.1f} s)"
        )
        wall, rss, status, _, err, _ = run(trical_cmd(night, None))
        if status in (0, 3):
            print(f"trical noise (six axes): wall {wall:.1f} s, peak RSS {rss:.0f} MiB (bound 2048 MiB)")
        else:
            print(
                f"trical noise failed on the night (exit {status}): "
                f"{err.strip().splitlines()[-1] if err.strip() else '-'}"
            )


if __name__ == "__main__":
    main()
