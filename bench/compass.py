"""The compass calibration beside a plain algebraic ellipsoid fit and a sphere (hard-iron only) fit.

    PYTHONPATH=. python bench/compass.py [--sessions 50] [--seed 1]

For each scenario, ``--sessions`` seeded turns (simulations.magnetometer: a random
symmetric soft iron, a hard iron, white noise) are calibrated three ways on the same readings:

- ``trical``: ``fit_magnetometer`` (the algebraic start, Levenberg–Marquardt on |h| − F, the gates);
- ``ellipsoid``: the algebraic least-squares ellipsoid alone, scaled to F (the closed form most
  compass code uses, e.g. the quadric fit of Vasconcelos et al. 2011, section III);
- ``sphere``: the least-squares sphere, offsets only (ArduPilot's and PX4's first step).

Beside each other, as medians over the sessions: the error of b (µT), of M (Frobenius), the RMS of
|h| − F on 2000 fresh readings of the same device over the whole sphere (what a person gets), how
often trical says ok and how often an ok result is worse than the raw readings there (must be
never), and the time of one fit (median, ms; trical's includes its 20 cross-validation refits).
Then the public real recordings in ``tests/data/real/magnetometer/`` (when present): each method's
spread of |h|, and beside an operating system's own hard-iron estimate where the recording has one.

It prints figures only; nothing passes or fails.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from app.calibration.magnetometer import fit_magnetometer
from app.calibration.magnetometer.ellipsoid import fit_ellipsoid, fit_sphere
from app.io.readers import read_log
from app.io.readers.read_options import ReadOptions
from simulations.magnetometer import EARTH_FIELD_UT, random_soft_iron, simulate_turn

F = EARTH_FIELD_UT
SCENARIOS = {
    "full turn, 400 readings, 0.3 µT": dict(n=400, noise_ut=0.3, max_polar_deg=180.0, hard=60.0),
    "phone hard iron 300 µT, 0.5 µT noise": dict(n=400, noise_ut=0.5, max_polar_deg=180.0, hard=300.0),
    "short turn, 80 readings, 1 µT": dict(n=80, noise_ut=1.0, max_polar_deg=180.0, hard=60.0),
    "partial turn (cap of 120°)": dict(n=400, noise_ut=0.3, max_polar_deg=120.0, hard=60.0),
    "noisy partial turn, 150 readings, 3 µT": dict(n=150, noise_ut=3.0, max_polar_deg=120.0, hard=60.0),
    "hemisphere only (screen up)": dict(n=400, noise_ut=0.3, max_polar_deg=90.0, hard=60.0),
}
REAL = Path(__file__).resolve().parents[1] / "tests" / "data" / "real" / "magnetometer"


def _timed(fn, *args, **kwargs):
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, 1000.0 * (time.perf_counter() - t0)


def _fresh_error(rng, M_true, b_true, M, b) -> float:
    fresh = simulate_turn(rng, M_true, b_true, field_ut=F, noise_ut=0.0, n=2000)
    return float(np.sqrt(np.mean((np.linalg.norm((fresh - b) @ M.T, axis=1) - F) ** 2)))


def simulated(sessions: int, seed: int) -> None:
    print(f"simulated turns, medians over {sessions} sessions; F = {F} µT")
    print(
        f"{'scenario':<38} {'method':<10} {'|Δb| µT':>8} {'|ΔM|':>8} {'fresh µT':>9} {'ms':>7} {'ok %':>6} "
        f"{'ok but worse':>13}"
    )
    for name, sc in SCENARIOS.items():
        rng = np.random.default_rng(seed)
        rows = {"trical": [], "ellipsoid": [], "sphere": []}
        oks = worse = 0
        for _ in range(sessions):
            M_true = random_soft_iron(rng)
            b_true = rng.uniform(-sc["hard"], sc["hard"], 3)
            m = simulate_turn(
                rng, M_true, b_true, field_ut=F, noise_ut=sc["noise_ut"], n=sc["n"], max_polar_deg=sc["max_polar_deg"]
            )
            raw = _fresh_error(rng, M_true, b_true, np.eye(3), np.zeros(3))
            result, ms = _timed(fit_magnetometer, m, field_ut=F)
            fits = {"trical": (result.M, result.b, ms)}
            try:
                (M_e, b_e), ms = _timed(fit_ellipsoid, m, F)
                fits["ellipsoid"] = (M_e, b_e, ms)
            except Exception:  # not an ellipsoid: counted as a failure of the plain fit
                fits["ellipsoid"] = None
            (M_s, b_s), ms = _timed(fit_sphere, m, F)
            fits["sphere"] = (M_s, b_s, ms)
            for method, fit in fits.items():
                if fit is None:
                    rows[method].append((np.inf, np.inf, np.inf, np.nan))
                    continue
                M, b, ms = fit
                fresh = _fresh_error(rng, M_true, b_true, M, b)
                rows[method].append((np.linalg.norm(b - b_true), np.linalg.norm(M - M_true), fresh, ms))
                if method == "trical" and result.ok:
                    oks += 1
                    worse += fresh >= raw
        for method, values in rows.items():
            a = np.array(values)
            ok = f"{100 * oks / sessions:6.0f} {worse:>13d}" if method == "trical" else ""
            label = name if method == "trical" else ""
            print(
                f"{label:<38} {method:<10} {np.median(a[:, 0]):8.3f} {np.median(a[:, 1]):8.4f} "
                f"{np.median(a[:, 2]):9.3f} {np.nanmedian(a[:, 3]):7.2f} {ok}"
            )


def _spread(values) -> float:
    lo, hi = np.percentile(values, [5, 95])
    return float(hi - lo)


def real() -> None:
    files = sorted(REAL.glob("**/*.csv")) if REAL.is_dir() else []
    readable = []
    for path in files:
        try:
            log = read_log(path, ReadOptions(format="auto", sampling_rate_hz=None, units={}), name=path.name)
        except Exception as exc:  # a file this checkout cannot read yet: say so
            print(f"{path.relative_to(REAL)}: not read ({exc})")
            continue
        if log.mag is not None:
            readable.append((path, log.mag * (1e-3 if log.units.get("mag") == "nT" else 1.0)))
    if not readable:
        print("no real magnetometer recordings under tests/data/real/magnetometer/")
        return
    print("\nreal recordings: 5–95 % spread of |h| (µT) and the hard iron b (µT)")
    print(f"{'recording':<60} {'n':>5} {'raw':>7} {'sphere':>7} {'ellips.':>7} {'trical':>7}  trical b / ok")
    for path, m in readable:
        if len(m) < 50:
            print(f"{path.relative_to(REAL)!s:<60} {len(m):>5}  too short to calibrate (fewer than 50 readings)")
            continue
        result = fit_magnetometer(m)
        M_s, b_s = fit_sphere(m, result.metrics["field_ut"])
        try:
            M_e, b_e = fit_ellipsoid(m, result.metrics["field_ut"])
            ell = _spread(np.linalg.norm((m - b_e) @ M_e.T, axis=1))
        except Exception:
            ell = float("nan")
        print(
            f"{path.relative_to(REAL)!s:<60} {len(m):>5} {_spread(np.linalg.norm(m, axis=1)):7.2f} "
            f"{_spread(np.linalg.norm((m - b_s) @ M_s.T, axis=1)):7.2f} {ell:7.2f} "
            f"{result.metrics['norm_spread_ut']:7.2f}  {np.round(result.b, 2).tolist()} / {result.ok} "
            f"{'; '.join(r[:60] for r in result.reasons)}"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sessions", type=int, default=50)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    simulated(args.sessions, args.seed)
    real()


if __name__ == "__main__":
    main()
