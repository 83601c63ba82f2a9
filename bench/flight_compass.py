"""The compass calibrated from a flight on seeded flights: coverage of the intervals, the mounting found,
the model chosen, the heading error, and the orientation step against a sphere fit followed by Wahba.

    PYTHONPATH=. python bench/flight_compass.py [--flights 200] [--seed 1000]

Each flight (simulations.flight_compass: 3 min at 25 Hz, a yaw turn a minute, ±20° of pitch
and roll, current 12–33 A, 0.3 µT of compass noise, the attitude off by 0.3° per axis wandering over 3 s,
mountings cycling through COMPASS_ORIENT 2, 8, 0, 4, 16, 25) is calibrated twice: with the model fixed to
the truth's (``soft_iron+motor``) for the coverage of the 95 % intervals, and with ``models="auto"``.
Beside it, the orientation from a sphere fit's centre and the SVD solution of Wahba's problem on the
readings centred there (the textbook start) against trical's (the regression on the expected field).

It prints figures only; nothing passes or fails.
"""

from __future__ import annotations

import argparse
import time
from collections import Counter

import numpy as np

from app.calibration.magnetometer.ellipsoid import fit_sphere
from app.calibration.magnetometer.flight import fit_flight_compass
from app.calibration.shared.rotations import angle_between, nearest_rotation
from simulations.flight_compass import simulate_flight

MOUNTINGS = (2, 8, 0, 4, 16, 25)


def fit_seeded(f, models):
    """trical's fit of a seeded flight (simulations.flight_compass) with the candidates ``models``."""
    return fit_flight_compass(
        f["mag_raw_ut"],
        f["expected_ut"],
        time_s=f["time_s"],
        power=f["current_a"],
        power_kind="current",
        firmware_field=f["mag_firmware_ut"],
        attitude=f["attitude_c_nb"],
        earth_ned=f["earth_ned"],
        models=models,
    )


def _sphere_wahba(mag, expected) -> np.ndarray:
    _, b0 = fit_sphere(mag)
    U, _, Vt = np.linalg.svd(expected.T @ (mag - b0))
    return U @ np.diag([1.0, 1.0, np.linalg.det(U @ Vt)]) @ Vt


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--flights", type=int, default=200)
    parser.add_argument("--seed", type=int, default=1000)
    args = parser.parse_args()
    hits = {"offsets": [], "matrix": [], "motor": []}
    found = found_sphere = 0
    angle, angle_sphere, chosen, ok, before, after, times = [], [], Counter(), 0, [], [], []
    upper = np.triu_indices(3)
    for i in range(args.flights):
        f = simulate_flight(args.seed + i, orientation=MOUNTINGS[i % len(MOUNTINGS)])
        truth = f["truth"]
        start = time.perf_counter()
        r = fit_seeded(f, "soft_iron+motor")
        times.append(time.perf_counter() - start)
        hits["offsets"] += list(np.abs(r.offsets_ut - truth["b"]) <= r.offsets_half_width_ut)
        hits["matrix"] += list((np.abs(r.matrix - truth["M"]) <= r.matrix_half_width)[upper])
        hits["motor"] += list(np.abs(r.motor_coefficients - truth["k"]) <= r.motor_half_width)
        found += r.rotation_nearest["ardupilot"] == truth["orientation"]
        angle.append(angle_between(r.rotation_found, truth["Q"]))
        Qs = _sphere_wahba(f["mag_raw_ut"], f["expected_ut"])
        found_sphere += nearest_rotation(Qs)[0] == truth["orientation"]
        angle_sphere.append(angle_between(Qs, truth["Q"]))
        auto = fit_seeded(f, "auto")
        chosen[auto.model + ("+motor" if auto.motor else "")] += 1
        ok += auto.ok
        before.append(auto.heading_error_deg["before"]["rms"])
        after.append(auto.heading_error_deg["after"]["rms"])
    n = args.flights
    rates = {k: f"{np.mean(v):.3f}" for k, v in hits.items()}
    print(
        f"{n} flights; 95 % intervals hold the truth: {rates}, "
        f"overall {np.mean([x for v in hits.values() for x in v]):.3f}"
    )
    print(
        f"mounting found: trical {found}/{n} (angle left to the truth median {np.median(angle):.2f}°, "
        f"95th {np.percentile(angle, 95):.2f}°); sphere + Wahba {found_sphere}/{n} "
        f"(median {np.median(angle_sphere):.2f}°, 95th {np.percentile(angle_sphere, 95):.2f}°)"
    )
    print(
        f"auto: models chosen {dict(chosen)}, ok {ok}/{n}; heading error on segments left out, median rms "
        f"before {np.median(before):.1f}°, after {np.median(after):.2f}°"
    )
    print(f"one fit (model fixed) {1000 * np.median(times):.0f} ms median")


if __name__ == "__main__":
    main()
