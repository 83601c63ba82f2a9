"""How closely each firmware, fed the numbers of a flight compass's export, reproduces trical's correction.

    PYTHONPATH=. python bench/flight_compass_exports.py [--bodies 100] [--readings 2000] [--seed 1]

For each scenario, ``--bodies`` seeded calibration bodies (a random symmetric soft iron about I, offsets and
motor coefficients) are exported (app.io.exports.compass); the numbers are read back from the file's text and
put into the firmware's own formula (ArduPilot's rotate_field and correct_field, PX4's Magnetometer::Correct,
written in tests/io/test_export_flight_compass.py from the firmware sources) over ``--readings`` random raw
readings and currents or throttles. Printed: the largest |h_firmware − h_trical| in µT over every body and
reading, per scenario. It prints figures only; the test holds the bound (1e-4 µT).
"""

from __future__ import annotations

import argparse

import numpy as np

from app.io.exports.compass import export_flight_compass
from tests.io.test_export_flight_compass import (
    YAW_90,
    ap_rotate,
    ardupilot_correct,
    flight_body,
    parse_ardupilot,
    parse_px4,
    px4_correct,
    px4_rotation,
    soft_iron,
    trical,
)


def _ardupilot(rng, n, motor, Q, stored):
    body = flight_body(
        Q=Q,
        M=soft_iron(rng),
        b=rng.normal(scale=20, size=3),
        k=rng.normal(scale=0.5, size=3),
        motor=motor,
        orientation=stored,
        params={"COMPASS_EXTERNAL": 1},
    )
    sensor = rng.normal(scale=35.0, size=(n, 3))
    p = rng.uniform(0, 1, n) if motor == "throttle" else rng.uniform(0, 40, n)
    params = parse_ardupilot(export_flight_compass(body, "ardupilot").content)
    h = ardupilot_correct(params, 0, stored, sensor, p, {"current": 2, "throttle": 1}.get(motor, 0))
    return np.abs(h - trical(body, ap_rotate(stored, sensor), p)).max()


def _px4(rng, n, motor, Q, stored):
    R = px4_rotation(stored)
    body = flight_body(
        "px4",
        Q=Q,
        frame_to_body=R,
        M=soft_iron(rng),
        b=rng.normal(scale=20, size=3),
        k=rng.normal(scale=0.5, size=3),
        motor=motor,
        orientation=stored,
        params={"CAL_MAG0_ID": 1, "CAL_MAG0_ROT": stored},
    )
    sensor = rng.normal(scale=35.0, size=(n, 3))
    p = rng.uniform(0, 1, n) if motor == "throttle" else rng.uniform(0, 40, n)
    params = parse_px4(export_flight_compass(body, "px4").content)
    h = px4_correct(params, 0, stored, sensor, p * (0.001 if motor == "current" else 1.0))
    return np.abs(h - trical(body, sensor, p)).max()


SCENARIOS = {
    "ArduPilot, current, orientation kept": (_ardupilot, "current", np.eye(3), 0),
    "ArduPilot, throttle, orientation kept": (_ardupilot, "throttle", np.eye(3), 0),
    "ArduPilot, no motors, orientation kept": (_ardupilot, None, np.eye(3), 0),
    "ArduPilot, current, ORIENT 8 -> 10": (_ardupilot, "current", YAW_90, 8),
    "PX4, current (kA), ROT 8 kept": (_px4, "current", px4_rotation(8), 8),
    "PX4, throttle, ROT 8 kept": (_px4, "throttle", px4_rotation(8), 8),
    "PX4, current (kA), ROT 0 -> 6": (_px4, "current", px4_rotation(6), 0),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bodies", type=int, default=100)
    ap.add_argument("--readings", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    print(f"{'scenario':42s} max |h_firmware - h_trical| (uT) over {args.bodies} bodies x {args.readings} readings")
    for name, (run, motor, Q, stored) in SCENARIOS.items():
        worst = max(run(rng, args.readings, motor, Q, stored) for _ in range(args.bodies))
        print(f"{name:42s} {worst:.2e}")


if __name__ == "__main__":
    main()
