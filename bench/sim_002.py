"""Farago et al. Table 2 recomputed: 500 simulated scenarios at 1 mg and 5 mg, every solver, against the CRB.

Farago et al. (IEEE Access) section III.A: parameters drawn by eqs. (17)–(18), points by eqs.
(19)–(20) and the nine-bin selection (simulations/triangular.py).  Every solver of
``fit_triangular`` runs on the same scenarios.  For each parameter the table gives the mean and the
SD of the absolute error (the columns of Farago et al. Table 2), the Cramér–Rao bound sqrt(mean CRB) and the
solver's RMS error divided by it; ``z`` is the per-scenario normalised RMS sqrt(mean(err²/CRB)).

Usage: ``PYTHONPATH=. python bench/sim_002.py [--scenarios 500] [--seed 2002]``.  Prints figures,
never pass/fail.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from app.calibration.still.triangular import SOLVERS, fit_triangular
from simulations.triangular import PARAM_NAMES, cramer_rao_bound, simulate_scenario

# Farago et al. Table 2 as printed: mean and SD of |error| at 1 mg and 5 mg.
PAPER = {
    "k_xx": (2.98e-4, 1.39e-3, 2.37e-4, 1.07e-3),
    "k_yy": (3.18e-4, 1.64e-3, 2.27e-4, 1.22e-3),
    "k_zz": (2.47e-4, 1.07e-3, 1.68e-4, 8.98e-4),
    "k_xy": (1.49e-3, 2.61e-3, 1.22e-3, 2.24e-3),
    "k_xz": (1.42e-3, 2.67e-3, 1.23e-3, 2.07e-3),
    "k_yz": (1.45e-3, 3.3e-3, 1.26e-3, 2.53e-3),
    "o_x": (2.39e-4, 1.05e-3, 1.88e-4, 9.2e-4),
    "o_y": (2.54e-4, 1.18e-3, 1.91e-4, 8.35e-4),
    "o_z": (2.04e-4, 1.08e-3, 1.5e-4, 7.76e-4),
}
NOISES = (0.001, 0.005)


def run(n: int, seed: int) -> dict:
    out = {}
    for k, noise in enumerate(NOISES):
        rng = np.random.default_rng([seed, k])
        crb, err = [], {s: [] for s in SOLVERS}
        secs = dict.fromkeys(SOLVERS, 0.0)
        for _ in range(n):
            sc = simulate_scenario(rng, noise_g=noise)
            crb.append(np.diag(cramer_rao_bound(sc.p, sc.directions, noise)))
            for s in SOLVERS:
                t0 = time.perf_counter()
                cal = fit_triangular(sc.points, gravity=1.0, solver=s)
                secs[s] += time.perf_counter() - t0
                err[s].append(cal.p - sc.p)
        out[noise] = {"crb": np.array(crb), "err": {s: np.array(v) for s, v in err.items()}, "secs": secs}
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenarios", type=int, default=500)
    ap.add_argument("--seed", type=int, default=2002)
    args = ap.parse_args()
    t0 = time.perf_counter()
    res = run(args.scenarios, args.seed)
    n = args.scenarios
    print(
        f"Farago et al. Table 2 recomputed: {n} scenarios per noise level, seed {args.seed}, N = 18 points (2 per bin)"
    )
    print("offsets in g; CRB = sqrt(mean over scenarios of the Cramér–Rao variance); ratio = RMS error / CRB;")
    print("z = sqrt(mean(err² / CRB)) per scenario.\n")
    for s in SOLVERS:
        print(f"solver {s}  (mean fit time {1000 * res[NOISES[0]]['secs'][s] / n:.1f} ms at 1 mg)")
        print(
            f"{'param':6} {'mean|e| 1mg':>11} {'5mg':>9} {'SD|e| 1mg':>10} {'5mg':>9} |"
            f" {'CRB 1mg':>9} {'ratio':>6} {'z':>5} | {'CRB 5mg':>9} {'ratio':>6} {'z':>5}"
        )
        for j, name in enumerate(PARAM_NAMES):
            cells = []
            for noise in NOISES:
                e = np.abs(res[noise]["err"][s][:, j])
                cells.append((e.mean(), e.std(ddof=1)))
            right = []
            for noise in NOISES:
                e = res[noise]["err"][s][:, j]
                c = res[noise]["crb"][:, j]
                bound = np.sqrt(c.mean())
                right.append(f"{bound:9.2e} {np.sqrt(np.mean(e**2)) / bound:6.2f} {np.sqrt(np.mean(e**2 / c)):5.2f}")
            print(
                f"{name:6} {cells[0][0]:11.2e} {cells[1][0]:9.2e} {cells[0][1]:10.2e} {cells[1][1]:9.2e} | "
                + " | ".join(right)
            )
        print()
    print("Farago et al. Table 2 as printed (mean|e| 1 mg, 5 mg; SD|e| 1 mg, 5 mg):")
    for name in PARAM_NAMES:
        print(f"{name:6} " + " ".join(f"{v:9.2e}" for v in PAPER[name]))
    print(f"\ntotal {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
