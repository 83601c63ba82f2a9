"""Write the upload fixture six_orientations_150hz.csv and its ground truth (.json).

A phone resting in the six canonical orientations in a non-canonical order, hand turns of 1–3 s
between them, a true affine error (Georgieva et al. Approach 2), white noise, one knock and a slow drift;
150 Hz, m/s², columns acc_x,acc_y,acc_z (no time column), 5 significant decimals.

Run from the repository root:  PYTHONPATH=. python tests/data/make_six_orientation_log.py
"""

import json
from pathlib import Path

import numpy as np

from simulations.logs import simulate_static_log

SEED = 20261123
PARAMS = dict(
    orientations=["+z", "-x", "+y", "-z", "+x", "-y"],  # not the canonical -x, +x, -y, +y, -z, +z
    sampling_rate_hz=150.0,
    rest_s=(7.0, 10.0),
    turn_s=(1.5, 3.0),
    noise_std=0.02,
    drift=0.05,
    n_bumps=1,
    bump_amplitude=3.0,
    tremor_deg=1.0,
    hand_acc=0.5,
)

HERE = Path(__file__).resolve().parent
CSV = HERE / "six_orientations_150hz.csv"
TRUTH = HERE / "six_orientations_150hz.json"


def main() -> None:
    log = simulate_static_log(np.random.default_rng(SEED), **PARAMS)
    with CSV.open("w", newline="\n") as fh:
        fh.write("acc_x,acc_y,acc_z\n")
        np.savetxt(fh, log.samples, fmt="%.5g", delimiter=",")
    truth = log.to_dict()
    truth.update(
        file=CSV.name,
        unit="m/s^2",
        seed=SEED,
        params=PARAMS,
        generator="simulations.logs.simulate_static_log",
        note="segments: true rests, sample indices (0 = first data row, line 2), end exclusive",
    )
    TRUTH.write_text(json.dumps(truth, indent=1) + "\n")
    print(
        f"{CSV.name}: {len(log.samples)} samples, {len(log.samples) / log.sampling_rate_hz:.1f} s, "
        f"{CSV.stat().st_size / 1e6:.2f} MB"
    )


if __name__ == "__main__":
    main()
