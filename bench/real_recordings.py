"""trical on real still-pose recordings of phones and IMU boards (tests/data/real/README.md).

    python bench/real_recordings.py

For each recording (one session of one device) and each method that applies — ``triangular`` and
``nonorthogonal`` on every recording of 10 or more poses, ``orientations`` where the poses are
axis-aligned — prints the poses, the raw error (mean | |m_i| − g | in mg), the in-sample
``error_after_mg``, the leave-one-out ``cv_error_mg`` and its maximum, ``ok``, and the error on the
same device's other sessions before → after; beside them the peer's own estimate where the source
published one.  Then the issue's regime: 10 and 11 consecutive poses of the Georgieva et al. phone
tables, calibrated with ``triangular``, the rest of the table held out.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from app.workflows.still import Reading, calibrate_known, calibrate_unknown
from tests.real_recordings import (
    MPU6050_LSB_PER_G,
    by_name,
    pose_subsets,
    raw_error_mg,
    recordings,
    tedaldi_apply,
)

MAGNITUDE_METHODS = ("triangular", "nonorthogonal")


def calibrate(rec, method: str, means, holdout=None):
    """The core result and its metrics with the workflow's held-out ones, for one method on still means."""
    if method in MAGNITUDE_METHODS:
        result, held_out = calibrate_unknown(method, means, unit=rec.unit, gravity=rec.gravity, holdout=holdout)
    else:
        readings = [Reading(mean=tuple(m), up=u) for m, u in zip(means, rec.ups)]
        result, held_out = calibrate_known(method, readings, unit=rec.unit, gravity=rec.gravity, holdout=holdout)
    return result, {**result.metrics, **held_out}


def in_sample_mg(result, means, gravity: float) -> float:
    """Mean | |a_i| − g | of the fitted readings after calibration (error_after_mg for every model)."""
    return raw_error_mg(result.apply(np.asarray(means, dtype=float)), gravity)


def peer_line(rec) -> str | None:
    if "tedaldi" in rec.peer:
        p = rec.peer["tedaldi"]
        counts = rec.means * MPU6050_LSB_PER_G
        others = by_name()["mpu6050-session2"].means * MPU6050_LSB_PER_G
        fit = raw_error_mg(tedaldi_apply(p, counts), p["gravity"])
        other = raw_error_mg(tedaldi_apply(p, others), p["gravity"])
        return (
            f"    peer: Tedaldi et al. fit by the recording's own code (tomisuarez2/ImuCalibration): in-sample "
            f"{fit:.3f} mg, other session {other:.2f} mg"
        )
    if "ward" in rec.peer:
        p = rec.peer["ward"]
        cal = calibrate_known(
            "six_position",
            [Reading(mean=tuple(m), up=u) for m, u in zip(rec.means, rec.ups)],
            unit=rec.unit,
            gravity=rec.gravity,
        )[0]
        dX = np.abs(cal.X - np.array(p["S"])).max()
        dy = np.abs(cal.y - np.array(p["b"])).max()
        return (
            f"    peer: the author's per-axis curve_fit of m = S a + b (willward20/UCA-Honors-Capstone): "
            f"trical six_position X, y differ from S, b by at most {max(dX, dy):.1e}"
        )
    return None


def main() -> None:
    recs = by_name()
    print(
        "Real recordings: raw = mean | |m| - g | over the poses; in-sample = the same after calibration on those poses;"
    )
    print(
        "cv = each pose calibrated by the fit made without it (leave-one-out); other = the device's other sessions, "
        "raw -> calibrated."
    )
    print(
        f"{'recording':22} {'method':13} {'poses':>5} {'raw mg':>8} {'in-sample':>10} {'cv mg':>8} {'cv max':>8} "
        f"{'ok':>5} {'other sessions mg':>19}"
    )
    for rec in recordings():
        methods = [m for m in MAGNITUDE_METHODS if len(rec.means) >= 10]
        if rec.ups is not None:
            methods.append("orientations")
        if not methods:
            print(f"{rec.name:22} (one pose: only a held-out session for {', '.join(rec.other_sessions)})")
            continue
        holdout = np.vstack([recs[o].means for o in rec.other_sessions]) if rec.other_sessions else None
        for method in methods:
            result, extra = calibrate(rec, method, rec.means, None if holdout is None else holdout.tolist())
            other = (
                f"{extra['holdout_error_before_mg']:8.2f} -> {extra['holdout_error_after_mg']:6.2f}"
                if holdout is not None
                else ""
            )
            print(
                f"{rec.name:22} {method:13} {len(rec.means):5d} {rec.raw_error_mg:8.2f} "
                f"{in_sample_mg(result, rec.means, rec.gravity):10.3f} {extra['cv_error_mg']:8.2f} "
                f"{extra['cv_error_max_mg']:8.2f} {result.ok!s:>5} {other:>19}"
            )
        line = peer_line(rec)
        if line:
            print(line)
    print()
    print(
        "The issue's regime: 10 or 11 consecutive poses of a Georgieva et al. phone table, triangular, the rest "
        "held out."
    )
    print(
        f"{'recording':22} {'poses':>7} {'raw mg':>8} {'in-sample':>10} {'cv mg':>8} {'cv max':>8} {'ok':>5} "
        f"{'unseen poses mg':>17}  verdict"
    )
    for rec, sl in pose_subsets():
        means = rec.means[sl]
        rest = np.delete(rec.means, np.arange(len(rec.means))[sl], axis=0)
        result, extra = calibrate(rec, "triangular", means, rest.tolist())
        worse_cv = extra["cv_error_mg"] >= raw_error_mg(means, rec.gravity)
        worse_unseen = extra["holdout_error_after_mg"] > extra["holdout_error_before_mg"]
        verdict = []
        if result.ok and worse_cv:
            verdict.append("ok although cv >= raw")
        if result.ok and worse_unseen:
            verdict.append("ok although unseen poses get worse")
        print(
            f"{rec.name:22} {sl.start + 1:3d}-{sl.stop:<3d} {raw_error_mg(means, rec.gravity):8.2f} "
            f"{in_sample_mg(result, means, rec.gravity):10.3f} {extra['cv_error_mg']:8.2f} "
            f"{extra['cv_error_max_mg']:8.2f} {result.ok!s:>5} "
            f"{extra['holdout_error_before_mg']:7.2f} -> {extra['holdout_error_after_mg']:6.2f}  {'; '.join(verdict)}"
        )


if __name__ == "__main__":
    main()
