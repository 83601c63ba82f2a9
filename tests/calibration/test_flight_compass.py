"""The compass calibrated from a flight (app/calibration/magnetometer/flight.py) on seeded flights, and the
firmwares' rotation tables (app/calibration/shared/rotations.py) against their sources."""

import json
import time

import numpy as np
import pytest

from app.calibration.magnetometer.flight import fit_flight_compass
from app.calibration.shared.errors import CalibrationError, InsufficientDataError
from app.calibration.shared.rotations import (
    ARDUPILOT_ROTATIONS,
    PX4_ROTATIONS,
    ardupilot_matrix,
    euler_matrix,
    nearest_rotation,
    px4_matrix,
)
from simulations.flight_compass import simulate_flight

S = np.sqrt(0.5)


def _apply(R, v):
    return tuple(np.round(R @ np.asarray(v, dtype=float), 6))


# Each firmware's own code for a few entries, by hand: (x, y, z) → the vector the code leaves.
@pytest.mark.parametrize(
    "number, by_hand",
    [
        # ArduPilot AP_Math/vector3.cpp Vector3<T>::rotate and PX4 conversion/rotation.cpp rotate_3f
        (2, lambda x, y, z: (-y, x, z)),  # YAW_90: tmp = x; x = -y; y = tmp
        (8, lambda x, y, z: (x, -y, -z)),  # ROLL_180: y = -y; z = -z
        (16, lambda x, y, z: (x, -z, y)),  # ROLL_90: tmp = z; z = y; y = -tmp
        (18, lambda x, y, z: (z, x, y)),  # ROLL_90_YAW_90 (PX4: x = z; z = y; y = tmp)
        (24, lambda x, y, z: (z, y, -x)),  # PITCH_90: tmp = z; z = -x; x = tmp
        (26, lambda x, y, z: (-y, -x, -z)),  # PITCH_180_YAW_90: z = -z; tmp = -x; x = -y; y = tmp
        (39, lambda x, y, z: (S * x - S * z, y, S * z + S * x)),  # PITCH_315 (PX4 rotate_3f)
        (40, lambda x, y, z: (S * x - S * y, -z, S * x + S * y)),  # ROLL_90_PITCH_315 (PX4 rotate_3f's literal)
    ],
)
def test_the_rotation_table_matches_the_firmwares_code(number, by_hand):
    v = (0.3, -1.7, 2.9)
    assert _apply(ardupilot_matrix(number), v) == pytest.approx(by_hand(*v), abs=1e-6)
    assert _apply(px4_matrix(number), v) == pytest.approx(by_hand(*v), abs=1e-6)


def test_the_two_enums_agree_up_to_40_and_part_after():
    for n in range(41):
        assert ARDUPILOT_ROTATIONS[n][0] == PX4_ROTATIONS[n][0]
        if n != 38:
            assert np.allclose(ardupilot_matrix(n), px4_matrix(n))
    # 38: ArduPilot's literal matrix (vector3.cpp) against PX4's Euler (90, 68, 293): under a degree apart
    assert np.allclose(ardupilot_matrix(38), px4_matrix(38), atol=0.02)
    assert [ARDUPILOT_ROTATIONS[n][0] for n in (41, 42, 43)] == ["PITCH_7", "ROLL_45", "ROLL_315"]
    assert [PX4_ROTATIONS[n][0] for n in (41, 44, 45)] == ["ROLL_270_YAW_180", "PITCH_9_YAW_180", "PITCH_45"]
    # the same rotation under two names: the lowest number is returned
    assert nearest_rotation(ardupilot_matrix(26))[:3] == (14, 14, "ROLL_180_YAW_270")
    assert nearest_rotation(px4_matrix(41))[:3] == (31, 31, "ROLL_90_PITCH_180")
    assert nearest_rotation(px4_matrix(45))[:3] == (None, 45, "PITCH_45")
    assert nearest_rotation(ardupilot_matrix(42))[:3] == (42, None, "ROLL_45")
    ap, px4, name, angle = nearest_rotation(euler_matrix(2.0, -1.0, 91.5))
    assert (ap, px4, name) == (2, 2, "YAW_90") and 1.5 < angle < 3.0


def _fit(f, **kw):
    args = dict(
        time_s=f["time_s"],
        power=f["current_a"],
        power_kind="current",
        firmware_field=f["mag_firmware_ut"],
        attitude=f["attitude_c_nb"],
        earth_ned=f["earth_ned"],
    )
    args.update(kw)
    return fit_flight_compass(f["mag_raw_ut"], f["expected_ut"], **args)


@pytest.mark.parametrize("orientation", [2, 8])
def test_a_seeded_flight_gives_back_every_parameter_and_the_orientation(orientation):
    f = simulate_flight(7, orientation=orientation)
    truth = f["truth"]
    r = _fit(f)
    assert r.ok, r.reasons
    assert (r.model, r.motor) == ("soft_iron", "current")
    assert r.rotation_nearest["ardupilot"] == orientation and np.allclose(r.rotation, truth["Q"])
    assert r.angle_left_deg < 2.0 and not r.orientation_agrees  # the firmware applies none (identity)
    assert np.abs(r.offsets_ut - truth["b"]).max() < 0.6
    assert np.abs(r.matrix - truth["M"]).max() < 0.01
    assert np.abs(r.motor_coefficients - truth["k"]).max() < 0.03
    assert np.all(r.offsets_half_width_ut < 2.5) and np.all(r.matrix_half_width < 0.05)  # the gates: 5 % of F, 0.05
    # the heading: the firmware's field (wrong orientation, stale offsets) against the fit, on segments left out
    assert r.heading_error_deg["before"]["rms"] > 50.0
    assert r.heading_error_deg["after"]["rms"] < 1.5 and r.heading_error_deg["after"]["p95"] < 3.0
    assert r.models["soft_iron+motor"]["rms"] < r.models["offsets"]["rms"]
    # correct() is the model; to_dict() is plain JSON; the series is thinned
    h = r.correct(f["mag_raw_ut"], f["current_a"])
    expected_h = (f["mag_raw_ut"] @ truth["Q"].T - truth["b"] - np.outer(f["current_a"], truth["k"])) @ truth["M"].T
    assert np.sqrt(np.mean((h - expected_h) ** 2)) < 0.5
    d = json.loads(json.dumps(r.to_dict()))
    assert len(d["series"]["time_s"]) == 600 and len(d["series"]["heading_error_after"]) == 600
    assert d["rotation_nearest"] == {"ardupilot": orientation, "px4": orientation, "name": r.rotation_nearest["name"]}


def test_a_firmware_that_applies_the_mounting_agrees_and_throttle_is_a_power():
    f = simulate_flight(9, orientation=16)
    r = _fit(f, frame_to_body=f["truth"]["Q"], power=f["throttle"], power_kind="throttle")
    assert r.orientation_agrees and r.rotation_nearest["name"] == "ROLL_90"
    assert not any("mounted as" in w for w in r.warnings)
    assert r.motor == "throttle" and r.ok, r.reasons
    # the simulated attitude's angles are those of its matrices (what a log's ATT would hold)
    assert np.allclose(
        euler_matrix(f["roll_deg"][100], f["pitch_deg"][100], f["yaw_deg"][100]), f["attitude_c_nb"][100], atol=1e-9
    )


def test_the_intervals_hold_the_truth_at_their_rate_over_200_flights():
    """200 seeded flights of 3 minutes at 25 Hz (0.3 µT of compass noise, the attitude off by 0.3° per axis
    wandering over 3 s, six mountings): every parameter against its 95 % interval."""
    start = time.perf_counter()
    hits = {"offsets": [], "matrix": [], "motor": []}
    found = 0
    mountings = (2, 8, 0, 4, 16, 25)
    upper = np.triu_indices(3)
    for seed in range(200):
        f = simulate_flight(1000 + seed, orientation=mountings[seed % len(mountings)])
        r = _fit(f, models="soft_iron+motor")
        truth = f["truth"]
        found += r.rotation_nearest["ardupilot"] == truth["orientation"]
        hits["offsets"] += list(np.abs(r.offsets_ut - truth["b"]) <= r.offsets_half_width_ut)
        hits["matrix"] += list((np.abs(r.matrix - truth["M"]) <= r.matrix_half_width)[upper])
        hits["motor"] += list(np.abs(r.motor_coefficients - truth["k"]) <= r.motor_half_width)
    rates = {k: float(np.mean(v)) for k, v in hits.items()}
    overall = float(np.mean([x for v in hits.values() for x in v]))
    print(f"coverage per class {rates}, overall {overall:.3f}, in {time.perf_counter() - start:.1f} s")
    assert found == 200
    assert 0.93 <= overall <= 0.97, rates
    assert all(0.90 <= v <= 0.98 for v in rates.values()), rates


def test_a_flight_without_turns_is_not_ok():
    r = _fit(simulate_flight(3, turns=0))
    assert not r.ok
    assert any("too few headings" in reason for reason in r.reasons)


def test_a_fit_that_does_not_beat_the_firmware_is_not_ok():
    f = simulate_flight(4)
    r = _fit(f, firmware_field=f["expected_ut"])  # a firmware whose field is exactly the expected one
    assert not r.ok
    assert any("does not lower the heading error" in reason for reason in r.reasons)


def test_without_attitude_or_power_varying_it_says_so():
    f = simulate_flight(5)
    r = _fit(f, attitude=None)
    assert not r.ok and any("no attitude" in reason for reason in r.reasons)
    assert r.heading_error_deg == {"before": None, "after": None}
    steady = _fit(f, power=np.full(len(f["time_s"]), 15.0))
    assert steady.motor is None and any("hardly varied" in w for w in steady.warnings)


def test_an_orientation_no_firmware_names_and_an_implausible_offset_are_not_ok():
    f = simulate_flight(6, orientation=0)
    f["mag_raw_ut"] = f["mag_raw_ut"] @ euler_matrix(0, 0, 22.5)  # mounted half way between yaw 0 and 45
    r = _fit(f)
    assert not r.ok and r.angle_left_deg > 15 and any("unresolved" in reason for reason in r.reasons)
    big = _fit(simulate_flight(6, hard_iron_ut=900.0))
    assert not big.ok and any("beyond 300 µT" in reason for reason in big.reasons)


def test_too_few_samples():
    f = simulate_flight(8, duration_s=30.0, rate_hz=10.0, turns=1.0)
    r = _fit(f)
    assert not r.ok and any("only 300 samples" in reason for reason in r.reasons)
    short = simulate_flight(8, duration_s=4.0, rate_hz=10.0)
    with pytest.raises(InsufficientDataError):
        _fit(short)
    with pytest.raises(CalibrationError, match="unknown compass model"):
        _fit(f, models="ellipsoid")


def test_a_turned_compass_stored_as_a_calibration_stays_ok():
    """The stored calibration's scale is its soft iron M's, not the diagonal of M Q (zeros at yaw 90°)."""
    from app.calibration.magnetometer import FlightCompassCalibration

    f = simulate_flight(7, orientation=2)
    cal = FlightCompassCalibration.from_fit(_fit(f), flight={}, metrics={})
    assert cal.ok, cal.reasons
    assert not any("scale" in reason for reason in cal.reasons)
