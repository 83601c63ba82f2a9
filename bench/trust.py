"""What the cross-validated error promises against what a person gets, for 9–30 free poses.

    PYTHONPATH=. python bench/trust.py [--sessions 40] [--seed 1]

For each number of poses, ``--sessions`` simulated free-pose sessions of a phone
(simulations.free_poses: Farago et al.'s unit errors, 0.5 mg of noise per pose, a
third of the poses off by 3 mg of hand tremor) are calibrated by ``method: auto`` (which picks
triangular for free poses). Beside each other, averaged over the sessions: the raw error, the
in-sample error, the cross-validated error ``cv_error_mg``, and the true error on 1000 fresh poses
read the same way; then how often the result says ok, and how often an ok result is worse than raw
on the fresh poses (must be never). Fewer than 9 free poses are refused (insufficient_data).

It prints figures only; nothing passes or fails.
"""

from __future__ import annotations

import argparse

import numpy as np

from app.calibration import InsufficientDataError
from app.workflows.still import choose_model
from simulations.free_poses import free_pose_session, fresh_error_mg

POSES = (5, 9, 10, 12, 15, 20, 25, 30)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sessions", type=int, default=40)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    print(
        f"{'poses':>5} {'raw mg':>8} {'in-sample':>10} {'cv mg':>8} {'fresh mg':>9} {'cv/fresh':>9} "
        f"{'ok %':>6} {'ok but worse':>13}"
    )
    for n in POSES:
        rows, refused = [], 0
        for _ in range(args.sessions):
            p, means = free_pose_session(rng, n)
            try:
                result, _, _ = choose_model(means, unit="g", gravity=1.0)
            except InsufficientDataError:
                refused += 1
                continue
            fresh, raw = fresh_error_mg(rng, p, result.apply)
            m = result.metrics
            rows.append((raw, m["error_after_mg"], m["cv_error_mg"], fresh, result.ok, result.ok and fresh >= raw))
        if not rows:
            print(f"{n:>5}  all {refused} sessions refused: a magnitude model needs 9 free poses")
            continue
        raw, inside, cv, fresh, ok, harm = (np.array([r[k] for r in rows], dtype=float) for k in range(6))
        has_cv = ~np.isnan(cv)
        cv_mean = np.mean(cv[has_cv]) if has_cv.any() else float("nan")
        ratio = cv_mean / np.mean(fresh[has_cv]) if has_cv.any() else float("nan")
        print(
            f"{n:>5} {raw.mean():>8.2f} {inside.mean():>10.2f} {cv_mean:>8.2f} {fresh.mean():>9.2f} "
            f"{ratio:>9.2f} {100 * ok.mean():>6.0f} {int(harm.sum()):>13d}"
        )


if __name__ == "__main__":
    main()
