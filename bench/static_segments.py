"""Figures of static-segment detection: boundary errors on simulated logs, and speed on 10^7 samples.

Run from the repository root:  PYTHONPATH=. python bench/static_segments.py
"""

import time

import numpy as np

from app.calibration.segments.static import detect_static_segments, still_threshold, window_stats
from simulations.logs import simulate_static_log

CASES = {
    "clean": {},
    "bumps": {"n_bumps": 2},
    "drift 0.3": {"drift": 0.3},
    "quantised 0.1": {"quantisation_step": 0.1},
    "all + repeats": {"repeats": 2, "n_bumps": 1, "drift": 0.1, "quantisation_step": 0.1},
}


def boundary_errors(n_seeds: int = 10) -> None:
    print("boundary error = detected − true, seconds (start, end); over", n_seeds, "seeds per case")
    for fs in (100.0, 150.0, 200.0):
        for name, kw in CASES.items():
            starts, ends, missed = [], [], 0
            for seed in range(n_seeds):
                log = simulate_static_log(np.random.default_rng(seed), sampling_rate_hz=fs, **kw)
                segs = detect_static_segments(log.samples, fs)
                if [s.up for s in segs] != [lab for *_, lab in log.segments]:
                    missed += 1
                    continue
                starts += [(s.start - t[0]) / fs for s, t in zip(segs, log.segments)]
                ends += [(s.end - t[1]) / fs for s, t in zip(segs, log.segments)]
            s, e = np.array(starts), np.array(ends)
            print(
                f"{fs:5.0f} Hz {name:15s} start {s.mean():+.3f} [{s.min():+.3f}, {s.max():+.3f}]  "
                f"end {e.mean():+.3f} [{e.min():+.3f}, {e.max():+.3f}]  max |err| "
                f"{max(np.abs(s).max(), np.abs(e).max()):.3f} s  wrong logs {missed}/{n_seeds}"
            )


def speed(n: int = 10_000_000) -> None:
    log = simulate_static_log(np.random.default_rng(4), sampling_rate_hz=100.0, repeats=4, n_bumps=2, drift=0.1)
    reps = -(-n // len(log.samples))
    big = np.ascontiguousarray(np.tile(log.samples, (reps, 1))[:n])
    spread, norm = window_stats(big, 50)
    g, thr = still_threshold(spread, norm)
    print(f"threshold on this log: {thr:.3f} m/s² ({100 * thr / g:.2f} % of g = {g:.4f})")
    best = []
    for _ in range(3):
        t0 = time.perf_counter()
        segs = detect_static_segments(big, 100.0)
        best.append(time.perf_counter() - t0)
    print(
        f"{n:.0e} samples (tiled simulated log, {len(segs)} rests found of {reps * len(log.segments)}): "
        f"best {min(best):.2f} s, median {np.median(best):.2f} s of 3"
    )


if __name__ == "__main__":
    boundary_errors()
    speed()
