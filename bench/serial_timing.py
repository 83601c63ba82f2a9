"""The rate and noise density of a serial log stamped by its host, beside one over the median step.

    PYTHONPATH=. python bench/serial_timing.py [--runs 20] [--minutes 3] [--seed 200]

Each run simulates a still gyroscope at 100 Hz with white noise N = 0.01 °/s/√Hz
(simulations.noise), stamps its lines as a USB serial host does on arrival — in
bursts, polls 1–70 ms apart, lines 1–3 ms apart (simulations.serial) — and reads
the stamps as trical does (app.io.readers.timing: the span), and as one over the median step did.
It prints, over the runs, the rate each way and the noise density each gives, as the median and the
range of their ratio to the truth. Figures only; nothing passes or fails.
"""

from __future__ import annotations

import argparse

import numpy as np

from app.calibration.noise.characterise import characterise_noise
from app.io.readers.timing import decide_timing
from simulations.noise import simulate_still
from simulations.serial import host_arrival_times

FS = 100.0
N_TRUE = 0.01


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--minutes", type=float, default=3.0)
    ap.add_argument("--seed", type=int, default=200)
    args = ap.parse_args()
    n = int(args.minutes * 60 * FS)
    rows = {"span": [], "median": []}
    steps_seen = []
    for run in range(args.runs):
        rng = np.random.default_rng(args.seed + run)
        t = host_arrival_times(rng, n_samples=n, sampling_rate_hz=FS)
        gyr = simulate_still(rng, n_samples=n, sampling_rate_hz=FS, N=N_TRUE, B=0.0, K=0.0)
        steps = np.diff(t)
        steps_seen.append((np.median(steps), steps.mean(), steps.max()))
        rates = {"span": decide_timing(t).sampling_rate_hz, "median": 1.0 / float(np.median(steps[steps > 0]))}
        for how, rate in rates.items():
            density = characterise_noise(gyr, rate, unit="deg/s", sensor="gyr")["model"]["noise_density"]
            rows[how].append((rate / FS, *(d / N_TRUE for d in density)))
    med, mean, top = np.median(np.array(steps_seen), axis=0) * 1e3
    print(
        f"{args.runs} runs of {args.minutes:g} min at {FS:g} Hz; host steps: median {med:.2f} ms, mean {mean:.2f} ms, "
        f"max {top:.1f} ms"
    )
    print(f"{'rate from':<10} {'rate / truth':>26} {'noise density / truth (3 axes)':>34}")
    for how, values in rows.items():
        v = np.array(values)
        rate, dens = v[:, 0], v[:, 1:].ravel()
        print(
            f"{how:<10} {np.median(rate):>8.4f} [{rate.min():.4f}, {rate.max():.4f}]"
            f" {np.median(dens):>16.4f} [{dens.min():.4f}, {dens.max():.4f}]"
        )


if __name__ == "__main__":
    main()
