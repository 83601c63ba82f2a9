"""How often the temperature calibration's 95 % intervals hold the truth, and the drift it leaves, over
seeded warm-ups.

    PYTHONPATH=. python bench/temperature.py [--runs 300] [--minutes 30] [--rate 50] [--seed 1000] [--noise real|white]
                                             [--walk K]

Each run simulates a still board warming up from 15 °C towards 55 °C (simulations.temperature:
a first-order warm-up, τ = 400 s, the temperature read with 0.02 °C of noise, sample times jittering by 2 %),
each axis's offset a known cubic (ACC_TRUTH, GYR_TRUTH), the noise drawn in 5 s blocks from the real still
MPU-6050 recording of tests/data/real (``--noise real``, its correlation in time kept within a block) or white.
It calibrates it twice:

- the order fixed at 3 (the truth's): whether each fitted coefficient's 95 % interval holds the true one, and
  whether the 95 % band of the offset holds the true offset at each of the curve's 41 temperatures;
- the order chosen on bands left out (what a user gets): the orders chosen, the offset drift over the range
  raw and on bands left out (peak to peak, largest axis, mg and °/s), and the RMS error of the corrected
  offset against the truth over the range.

``--walk K`` adds to the gyroscope a rate random walk of K rad/s²/√Hz (a bias wandering in time): over a
warm-up, whose temperature rises with time, such a wander cannot be told from a drift with temperature, and
the intervals, made from the bins' residuals, do not hold it — the run measures by how much.

Figures only; nothing passes or fails.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from app.calibration.temperature import (
    FIGURE_SCALE,
    calibrate_temperature,
    offset_at,
    shift_polynomial,
)
from simulations.temperature import ACC_TRUTH, GYR_TRUTH, T_POLY_REF_C, simulate_warm_up

TRUTH = {"acc": ACC_TRUTH, "gyr": GYR_TRUTH}


def truth_about(model: dict, sensor: str) -> np.ndarray:
    c = shift_polynomial(TRUTH[sensor], T_POLY_REF_C, model["t_ref_c"])
    if model["relative"]:
        c[:, 0] = 0.0
    return c


def true_offset(model: dict, sensor: str, t: np.ndarray) -> np.ndarray:
    return offset_at({**model, "coefficients": truth_about(model, sensor).tolist()}, t)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=300)
    ap.add_argument("--minutes", type=float, default=30.0)
    ap.add_argument("--rate", type=float, default=50.0)
    ap.add_argument("--seed", type=int, default=1000)
    ap.add_argument("--noise", choices=("real", "white"), default="real")
    ap.add_argument("--walk", type=float, default=0.0, help="the gyroscope's rate random walk K, rad/s^2/sqrt(Hz)")
    args = ap.parse_args()
    noise = None
    if args.noise == "real":
        from tests.temperature_logs import real_still_noise

        noise = real_still_noise()
    hits = {s: [0, 0] for s in TRUTH}
    band = {s: [0, 0] for s in TRUTH}
    orders = {s: Counter() for s in TRUTH}
    raw = {s: [] for s in TRUTH}
    cv = {s: [] for s in TRUTH}
    rms = {s: [] for s in TRUTH}
    ok = 0
    start = time.perf_counter()
    for run in range(args.runs):
        rng = np.random.default_rng(args.seed + run)
        w = simulate_warm_up(rng, duration_s=60 * args.minutes, sampling_rate_hz=args.rate, noise=noise)
        gyr = w.gyr
        if args.walk:
            gyr = gyr + np.cumsum(rng.normal(0.0, args.walk / np.sqrt(args.rate), gyr.shape), axis=0)
        fixed = calibrate_temperature(
            w.temperature_c, acc=w.acc, gyr=gyr, sampling_rate_hz=args.rate, time_s=w.time_s, order=3
        )
        chosen = calibrate_temperature(w.temperature_c, acc=w.acc, gyr=gyr, sampling_rate_hz=args.rate, time_s=w.time_s)
        ok += chosen.ok
        for s in TRUTH:
            model, unc = fixed.sensors[s]["model"], fixed.sensors[s]["uncertainty"]
            half = np.asarray(unc["coefficients"])
            err = np.abs(np.asarray(model["coefficients"]) - truth_about(model, s))
            fitted = half > 0
            hits[s][0] += int(np.sum(err[fitted] <= half[fitted]))
            hits[s][1] += int(fitted.sum())
            curve = fixed.sensors[s]["curve"]
            t = np.asarray(curve["t_c"])
            inside = np.abs(np.asarray(curve["offset"]) - true_offset(model, s, t)) <= np.asarray(curve["half_width"])
            if model["relative"]:  # the reference temperature's offset is 0 by definition: no interval to test
                inside = inside[np.abs(t - model["t_ref_c"]) > 1e-9]
            band[s][0] += int(inside.sum())
            band[s][1] += int(inside.size)
            m = chosen.sensors[s]
            orders[s].update(m["model"]["order"])
            raw[s].append(m["metrics"]["drift_raw_max"])
            cv[s].append(m["metrics"]["drift_cv_max"])
            t = np.linspace(m["model"]["t_min_c"], m["model"]["t_max_c"], 200)
            diff = offset_at(m["model"], t) - true_offset(m["model"], s, t)
            rms[s].append(float(np.sqrt(np.mean(diff**2))) * FIGURE_SCALE[s])
    took = time.perf_counter() - start
    print(
        f"{args.runs} warm-ups of {args.minutes:g} min at {args.rate:g} Hz, 15 → 55 °C (τ 400 s), {args.noise} noise"
        f"{f', gyroscope rate random walk {args.walk:g} rad/s^2/sqrt(Hz)' if args.walk else ''}; "
        f"{took:.1f} s ({1000 * took / args.runs / 2:.0f} ms a calibration)"
    )
    print(f"ok (order chosen): {ok} of {args.runs}")
    units = {"acc": "mg", "gyr": "°/s"}
    for s in TRUTH:
        c, b = hits[s], band[s]
        print(
            f"{s}: coefficients' 95 % intervals hold the truth {100 * c[0] / c[1]:.1f} % ({c[0]}/{c[1]}); "
            f"the offset's band at each temperature {100 * b[0] / b[1]:.1f} % ({b[0]}/{b[1]})"
        )
        print(f"  orders chosen (axes): {dict(sorted(orders[s].items()))}")
        print(
            f"  drift over the range (largest axis, peak to peak): raw median {np.median(raw[s]):.3g} {units[s]}, "
            f"on bands left out median {np.median(cv[s]):.3g} {units[s]} "
            f"(95th percentile {np.percentile(cv[s], 95):.3g})"
        )
        print(
            f"  fitted offset against the truth over the range: RMS median {np.median(rms[s]):.3g} {units[s]}, "
            f"95th percentile {np.percentile(rms[s], 95):.3g}"
        )
    both = [hits["acc"][0] + hits["gyr"][0], hits["acc"][1] + hits["gyr"][1]]
    print(f"all coefficients: {100 * both[0] / both[1]:.1f} % (target 93–97 %)")


if __name__ == "__main__":
    main()
