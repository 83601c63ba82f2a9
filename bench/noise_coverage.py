"""How often the 95 % intervals of the noise terms hold the truth, over 200 simulated recordings.

    PYTHONPATH=. python bench/noise_coverage.py [--runs 200] [--minutes 20] [--seed 100]

Each run simulates a still gyroscope at 100 Hz (simulations.noise: white noise N,
flicker B, random walk K, the values of tests/calibration/test_noise.py), characterises it by the
overlapping Allan deviation (app.calibration.noise.characterise.characterise_noise) and checks, per axis, whether
each term's 95 % interval holds the true value. It prints, per term, the coverage over the axes that
had a figure and how many were null (too short a recording to see the term). Figures only; nothing
passes or fails.
"""

from __future__ import annotations

import argparse

import numpy as np

from app.calibration.noise.characterise import characterise_noise
from simulations.noise import simulate_still

FS = 100.0
TRUTH = {"noise_density": 0.01, "bias_instability": 0.015, "random_walk": 0.00224}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--minutes", type=float, default=20.0)
    ap.add_argument("--seed", type=int, default=100)
    args = ap.parse_args()
    n = int(args.minutes * 60 * FS)
    hits = dict.fromkeys(TRUTH, 0)
    seen = dict.fromkeys(TRUTH, 0)
    nulls = dict.fromkeys(TRUTH, 0)
    for run in range(args.runs):
        rng = np.random.default_rng(args.seed + run)
        samples = simulate_still(
            rng,
            n_samples=n,
            sampling_rate_hz=FS,
            N=TRUTH["noise_density"],
            B=TRUTH["bias_instability"],
            K=TRUTH["random_walk"],
        )
        r = characterise_noise(samples, FS, unit="rad/s")
        for name, truth in TRUTH.items():
            for interval in r["uncertainty"][name]:
                if interval is None:
                    nulls[name] += 1
                    continue
                seen[name] += 1
                hits[name] += interval[0] <= truth <= interval[1]
    print(f"{args.runs} recordings of {args.minutes:g} min at {FS:g} Hz, 3 axes each")
    print(f"{'term':<18}{'truth':>10}{'coverage':>10}{'axes':>6}{'null':>6}")
    for name, truth in TRUTH.items():
        cover = hits[name] / seen[name] if seen[name] else float("nan")
        print(f"{name:<18}{truth:>10.4g}{100 * cover:>9.1f}%{seen[name]:>6}{nulls[name]:>6}")


if __name__ == "__main__":
    main()
