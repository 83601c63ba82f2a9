"""The check's decisions (app.calibration.check) on seeded drifts and on the real corpus's pairs of sessions.

    PYTHONPATH=. python bench/check_decisions.py [--seeds 50]

Seeded (simulations.drift): a phone calibrated on 24 free poses, checked on 24 new ones with no drift, a 6 mg
offset, a 0.6 % scale; a compass calibrated on a 300-reading turn, checked on a new turn with no drift, a 3 µT
hard-iron shift, a 4 % gain, a field disturbed near one direction. Each row: how often each verdict, and how
often the first thing named drifted is the one simulated.

Real (tests/data/real): the MPU-9250's four six-position sessions, each calibration checked on the other three;
the QMC5883L board's hand turn in halves, each half's calibration checked on the other; the MPU-6050's ten-pose
calibration on its one-pose validation session. Each pair: the verdict, the error now and a fresh one's.

It prints figures only; nothing passes or fails.
"""

from __future__ import annotations

import argparse
import collections
import dataclasses

import numpy as np

from app.calibration.check import check
from app.calibration.magnetometer import fit_magnetometer
from app.calibration.still.affine import fit_six_position
from app.calibration.still.triangular import fit_triangular
from simulations.drift import disturbed_turn, drifted_poses
from simulations.free_poses import free_pose_session
from simulations.magnetometer import simulate_session, simulate_turn
from tests.conftest import DATA
from tests.real_recordings import mpu6050_session1, mpu6050_session2, mpu9250_sessions


def row(name: str, outs: list, expected: str) -> None:
    verdicts = collections.Counter(o.verdict for o in outs)
    named = sum(1 for o in outs if o.drifted[:1] == (expected,)) if expected else None
    told = ", ".join(f"{v} {n}" for v, n in verdicts.most_common())
    print(f"{name:<28} {told:<60} {'' if named is None else f'named {expected}: {named}/{len(outs)}'}")


def seeded(seeds: int) -> None:
    print("seeded accelerometer (24 poses, 24 new)")
    for name, drift, expected in (
        ("no drift", {}, ""),
        ("offset 6 mg", {"offset_g": (0.006, 0.0, 0.0)}, "offsets"),
        ("scale 0.6 %", {"scale": (1.006, 1.0, 1.0)}, "scales"),
    ):
        outs = []
        for seed in range(seeds):
            rng = np.random.default_rng(seed)
            p, means = free_pose_session(rng, 24)
            cal = dataclasses.replace(fit_triangular(means, gravity=1.0), unit="g")
            outs.append(check(cal, still_means=drifted_poses(rng, p, 24, **drift)).sensors[0])
        row(name, outs, expected)
    print("seeded compass (300 readings)")
    for name, expected in (
        ("no drift", ""),
        ("hard iron 3 µT", "hard iron"),
        ("gain 4 %", "soft iron"),
        ("disturbed", ""),
    ):
        outs = []
        for seed in range(max(10, seeds // 3)):
            m, M, b = simulate_session(seed, n=300)
            cal = fit_magnetometer(m, field_ut=48.0)
            rng = np.random.default_rng(1000 + seed)
            if name == "disturbed":
                turn = disturbed_turn(rng, M, b)
            else:
                shift = [3.0, 0.0, 0.0] if expected == "hard iron" else [0.0, 0.0, 0.0]
                gain = np.diag([1.04, 1.0, 1.0]) if expected == "soft iron" else np.eye(3)
                turn = simulate_turn(rng, M @ gain, b + np.asarray(shift), n=300)
            outs.append(check(cal, mag=turn, inclination_deg=64.0).sensors[0])
        row(name, outs, expected)


def told(out) -> str:
    s = out.sensors[0]
    now = "—" if s.current is None else f"{s.current.value:.2f} {s.current.unit}"
    fresh = "—" if s.fresh is None else f"{s.fresh.value:.2f} {s.fresh.unit}"
    return f"{out.verdict:<16} now {now:<14} fresh {fresh}"


def real() -> None:
    print("real pairs")
    sessions = mpu9250_sessions()
    for a, (ups_a, means_a) in sessions.items():
        cal = dataclasses.replace(fit_six_position(means_a, ups_a, gravity=1.0), unit="g")
        for b, (ups_b, means_b) in sessions.items():
            if a != b:
                print(f"  MPU-9250 {a} on {b:<12} {told(check(cal, still_means=means_b, labels=ups_b))}")
    counts = np.loadtxt(
        DATA / "real" / "magnetometer" / "tomisuarez2_qmc5883l_turn_every10.csv", delimiter=",", skiprows=4
    )
    turn = counts[300:]
    halves = {"first half": turn[: len(turn) // 2], "second half": turn[len(turn) // 2 :]}
    for a, b in (("first half", "second half"), ("second half", "first half")):
        cal = dataclasses.replace(fit_magnetometer(halves[a], raw_comparable=False, label="counts"), unit="raw")
        print(f"  QMC5883L {a} on {b:<12} {told(check(cal, mag=halves[b]))}")
    cal = dataclasses.replace(fit_triangular(mpu6050_session1(), gravity=1.0), unit="g")
    print(f"  MPU-6050 session 1 on 2      {told(check(cal, still_means=mpu6050_session2()))}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=50)
    args = parser.parse_args()
    seeded(args.seeds)
    real()


if __name__ == "__main__":
    main()
