"""The compass from a flight's 95 % intervals on short flights whose residuals stay correlated as real ones do:
the block jackknife trical uses (blocks of ten correlation times) beside shorter blocks and a
heteroskedasticity-and-autocorrelation-consistent covariance, on the same seeded flights.

    PYTHONPATH=. python bench/flight_compass_intervals.py [--flights 150] [--seed 5000] [--real] [--level 60]

Each flight (simulations.flight_compass) lasts 1–5 min (uniform) at 25 Hz with the logged attitude off by 0.5° per
axis wandering with a time constant of 1–16 s (log-uniform): the residuals' correlation times of the real
flights trical was tried on (1.4–15.7 s). The model is fixed to the truth's (``soft_iron+motor``, the mounting
given) so that only the intervals differ. For each estimator it prints the share of the 12 parameters inside
their intervals, the median half-width of the offsets (µT), and the blocks or degrees of freedom:

- ``jackknife 10τ``: what trical does (app.calibration.magnetometer.flight_model.block_jackknife, Student's t at
  G − 1), with blocks of 10 integrated correlation times;
- ``jackknife 5τ``: the same with blocks half as long (more blocks, narrower, less independent);
- ``EWC``: the equal-weighted cosine long-run variance of the scores ``wᵢ Xᵢᵀ εᵢ`` with ν = n / (10 τ) cosines and
  Student's t at ν (U. K. Müller, "A theory of robust long-run variance estimation", J. Econometrics 141(2), 2007;
  E. Lazarus, D. J. Lewis, J. H. Stock and M. W. Watson, "HAR inference: recommendations for practice", J.
  Business & Economic Statistics 36(4), 2018), M's entries by the delta method (dM = −M dS M).

With ``--level N`` it prints instead the partial update's figures on N seeded level flights (within 2° of level,
2.5 min at 10 Hz, no soft iron, written as ArduPilot logs with stale offsets stored, 5 µT per axis, and calibrated
by the method ``compass_flight``): how many were partial updates, how many ok, and the share of the updated numbers
inside their intervals — which assume the held values right, so that a stale held value shows as a lower share.

With ``--real`` it prints instead, for every compass of the real flight logs (tests/data/real/flight) whose fit has
intervals, the blocks, degrees of freedom and largest half-widths of b, M and k with the jackknife of ten correlation
times without overlap (what trical did before) and with what it does now.

It prints figures only; nothing passes or fails.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from flight_compass import fit_seeded  # bench/, the script's folder
from flight_compass_logs import calibrate_log
from scipy import stats

import app.calibration.magnetometer.flight as flight
from app.calibration.magnetometer import flight_model as fm
from simulations.flight_compass import simulate_flight

MOUNTINGS = (2, 8, 0, 4)
MODEL = "soft_iron"
FEW_BLOCKS = 4


def _flights(count: int, seed: int):
    draws = np.random.default_rng(seed)
    for k in range(count):
        duration = float(draws.uniform(60.0, 300.0))
        tau = float(np.exp(draws.uniform(np.log(1.0), np.log(16.0))))
        yield simulate_flight(
            seed + k,
            duration_s=duration,
            attitude_tau_s=tau,
            attitude_error_deg=0.5,
            orientation=MOUNTINGS[k % len(MOUNTINGS)],
        )


UPPER = np.triu_indices(3)
"""M's six entries in one order for every estimator: the upper triangle, row by row."""


def _truth(f) -> np.ndarray:
    t = f["truth"]
    return np.concatenate([t["M"][UPPER], t["b"], t["k"]])


def _upper_first(values: np.ndarray) -> np.ndarray:
    """``(M's entries in MATRIX_PARAMETERS' order, b, k)`` with M's entries put in :data:`UPPER`'s order."""
    M = np.zeros((3, 3))
    for value, (i, j) in zip(values, fm.MATRIX_PARAMETERS[MODEL]):
        M[i, j] = M[j, i] = value
    return np.concatenate([M[UPPER], values[6:]])


def _jackknife(f, block_times: float, steps: int, short: float) -> tuple[np.ndarray, np.ndarray, float, int]:
    flight.BLOCK_CORRELATION_TIMES, flight.BLOCK_STEPS, flight.SHORT_BLOCK_CORRELATION_TIMES = block_times, steps, short
    r = fit_seeded(f, "soft_iron+motor")
    intervals = r.to_dict()["intervals"]
    if r.offsets_half_width_ut is None:
        return np.full(12, np.nan), np.full(12, np.nan), 0.0, intervals["blocks"]
    values = np.concatenate([r.matrix[UPPER], r.offsets_ut, r.motor_coefficients])
    half = np.concatenate([r.matrix_half_width[UPPER], r.offsets_half_width_ut, r.motor_half_width])
    return values, half, float(intervals["dof"]), int(intervals["blocks"])


def _ewc(f) -> tuple[np.ndarray, np.ndarray, float, int]:
    Q = f["truth"]["Q"]
    u, e, p = f["mag_raw_ut"] @ Q.T, f["expected_ut"], f["current_a"]
    w = flight._weights(e)
    X, y = fm.design(u, e, p, MODEL, True)
    n, _, P = X.shape
    A = np.einsum("n,nip,niq->pq", w, X, X)
    theta = np.linalg.solve(A, np.einsum("n,nip,ni->p", w, X, y))
    eps = y - np.einsum("nip,p->ni", X, theta)
    fit = fm.from_theta(theta, MODEL, True)
    nu = int(np.clip(n / (10.0 * fm.correlation_time(fit.field(u, p) - e)), 2, 60))
    scores = w[:, None] * np.einsum("nip,ni->np", X, eps)
    cosines = np.cos(np.pi * np.outer(np.arange(1, nu + 1), np.arange(n) + 0.5) / n) @ scores
    A_inv = np.linalg.inv(A)
    V = A_inv @ (2.0 / nu * cosines.T @ cosines) @ A_inv
    G = np.eye(P)  # d(M's entries, b, k) / dθ: M = S⁻¹, so dM = −M dS M
    for j, E in enumerate(fm._basis(MODEL)):
        dM = -fit.M @ E @ fit.M
        for i, (a, b) in enumerate(fm.MATRIX_PARAMETERS[MODEL]):
            G[i, j] = dM[a, b]
    half = stats.t.ppf(0.975, nu) * np.sqrt(np.diag(G @ V @ G.T))
    return _upper_first(fm.parameters(fit)), _upper_first(half), float(nu), nu


REAL = Path(__file__).resolve().parent.parent / "tests" / "data" / "real" / "flight"
FORMATS = {".bin": "dataflash", ".ulg": "ulog"}
NO_FIX = {"latitude_deg": 47.4, "longitude_deg": 8.5, "date": "2025-01-03"}
"""The place and day given where a log has no GPS fix or no GPS time (the corpus table's)."""


def _real_row(path: Path, instance: int) -> list[str] | None:
    cells = []
    for settings in ((10.0, 1, 10.0), (10.0, 4, 5.0)):  # before, now
        flight.BLOCK_CORRELATION_TIMES, flight.BLOCK_STEPS, flight.SHORT_BLOCK_CORRELATION_TIMES = settings
        request = {"mag_instance": instance}
        try:
            body = calibrate_log(path, FORMATS[path.suffix.lower()], request)
        except Exception:  # refused (too few samples, no compass, not ready): no intervals to compare
            try:
                body = calibrate_log(path, FORMATS[path.suffix.lower()], {**request, **NO_FIX})
            except Exception:
                return None
        ivl, unc = body["flight"].get("intervals") or {}, body.get("uncertainty") or {}
        if not ivl or unc.get("b") is None:
            return None
        big = [max(np.max(np.abs(unc[key])), 0.0) if unc.get(key) is not None else float("nan") for key in "bMk"]
        fit = body["flight"]["structure"] + ("*" if body["flight"].get("updated") else "")
        cells.append(f"{fit:<11}{ivl['blocks']:>2} {ivl['dof']:>5} {big[0]:>7.2f} {big[1]:>6.3f} {big[2]:>6.3f}")
    return cells


def real_main() -> None:
    print(
        "compass from the flight on the real logs: the structure fitted (* a partial update), blocks, dof, "
        "largest 95 % half-width of b (µT), M, k (µT per unit of power)"
    )
    print(f"{'log':<32}{'mag':>4}  {'before (10τ, no overlap)':<42}{'now (10/5τ, overlapping)':<42}")
    for path in sorted(REAL.iterdir()):
        if path.suffix.lower() not in FORMATS:
            continue
        for instance in range(3):
            cells = _real_row(path, instance)
            if cells:
                print(f"{path.name:<32}{instance:>4}  {cells[0]:<42}{cells[1]:<42}")


def level_main(count: int, seed: int) -> None:
    import tempfile

    from tests.flight_compass_logs import seeded_flight, write_flight_compass_logs

    partial = ok = 0
    hits: dict[str, list[bool]] = {"b": [], "k": []}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(count):
            f = seeded_flight(seed + k, orientation=0, tilt_deg=2.0, soft_iron=0.0, duration_s=150.0, rate_hz=10.0)
            log = write_flight_compass_logs(Path(tmp), f, stem=f"level{k}")[0]
            body = calibrate_log(log, "dataflash")
            updated, unc = body["flight"].get("updated"), body.get("uncertainty") or {}
            if not updated or unc.get("b") is None:
                continue
            partial += 1
            ok += bool(body["ok"])
            for key in hits:
                if unc.get(key) is None:
                    continue
                new = updated[key] if isinstance(updated[key], list) else [updated[key]] * 3
                off = np.abs(np.asarray(body["model"][key]) - f["truth"][key])
                hits[key] += [bool(o <= h) for o, h, u in zip(off, unc[key], new) if u]
    print(f"{count} level flights: {partial} partial updates, {ok} of them ok")
    for key, row in hits.items():
        share = np.mean(row) if row else float("nan")
        print(f"  updated {key}: {len(row)} numbers, {share:.3f} inside their 95 % intervals")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--flights", type=int, default=150)
    parser.add_argument("--seed", type=int, default=5000)
    parser.add_argument("--real", action="store_true", help="the real flight logs' widths instead")
    parser.add_argument("--level", type=int, default=0, help="the partial update on this many level flights instead")
    args = parser.parse_args()
    if args.level:
        level_main(args.level, args.seed)
        return
    if args.real:
        real_main()
        return
    estimators = {
        "jackknife 10τ": lambda f: _jackknife(f, 10.0, 1, 10.0),
        "overlap 10τ": lambda f: _jackknife(f, 10.0, 4, 10.0),
        "overlap 5τ": lambda f: _jackknife(f, 5.0, 4, 5.0),
        "overlap 10/5τ": lambda f: _jackknife(f, 10.0, 4, 5.0),
        "EWC": _ewc,
    }
    rows = {name: {"hits": [], "few": [], "offsets": [], "dof": [], "is_few": []} for name in estimators}
    for f in _flights(args.flights, args.seed):
        truth = _truth(f)
        few = None
        for name, estimate in estimators.items():
            values, half, dof, blocks = estimate(f)
            few = blocks <= FEW_BLOCKS if few is None else few  # the flights today's jackknife cuts into few blocks
            hits = list(np.abs(values - truth) <= half)
            rows[name]["hits"] += hits
            rows[name]["few"] += hits if few else []
            rows[name]["offsets"].append(np.max(half[6:9]))
            rows[name]["dof"].append(dof)
            rows[name]["is_few"].append(few)
    flight.BLOCK_CORRELATION_TIMES, flight.BLOCK_STEPS, flight.SHORT_BLOCK_CORRELATION_TIMES = 10.0, 4, 5.0
    base = np.array(rows["jackknife 10τ"]["offsets"])
    print(f"{args.flights} flights of 1–5 min, attitude error wandering over 1–16 s; 95 % intervals")
    print(
        f"{'estimator':<15}{'coverage':>9}{f'≤{FEW_BLOCKS} blocks':>11}{'offsets ±µT':>13}"
        f"{'÷ jackknife 10τ':>17}{f'on ≤{FEW_BLOCKS}':>8}{'dof (10/50/90 %)':>20}"
    )
    for name, row in rows.items():
        lo, mid, hi = np.percentile(row["dof"], [10, 50, 90])
        ratio = np.array(row["offsets"]) / base
        few_ratio = np.nanmedian(ratio[np.array(row["is_few"])])
        print(
            f"{name:<15}{np.mean(row['hits']):>9.3f}{np.mean(row['few']):>11.3f}"
            f"{np.nanmedian(row['offsets']):>13.2f}{np.nanmedian(ratio):>17.2f}{few_ratio:>8.2f}"
            f"{f'{lo:.1f} / {mid:.1f} / {hi:.1f}':>20}"
        )
    few = len(rows["jackknife 10τ"]["few"]) // 12
    print(f"(≤{FEW_BLOCKS} blocks: the {few} flights that blocks of 10τ without overlap cut into so few)")


if __name__ == "__main__":
    main()
