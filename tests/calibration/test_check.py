"""Checking a calibration on a new recording (app.calibration.check): seeded drifts with their truth, and the
real corpus's MPU-9250, whose four six-position sessions check one another's calibration."""

import dataclasses

import numpy as np
import pytest

from app.calibration.check import AGAIN, CANNOT, KEEP, MOVE, check, check_rest, check_turn
from app.calibration.compare import correction_half_widths
from app.calibration.magnetometer import fit_magnetometer
from app.calibration.shared.correction import AffineCorrection
from app.calibration.still.affine import fit_six_position
from app.calibration.still.triangular import fit_triangular
from simulations.drift import disturbed_turn, drifted_poses
from simulations.free_poses import free_pose_session
from simulations.magnetometer import EARTH_FIELD_UT, simulate_rests, simulate_session, simulate_turn
from tests.conftest import DATA
from tests.real_recordings import mpu6050_session1, mpu6050_session2, mpu9250_sessions

F = EARTH_FIELD_UT
SEEDS = 50


def phone(seed: int):
    """A phone calibrated on 24 free poses (in g), its truth, and the generator for its next session."""
    rng = np.random.default_rng(seed)
    p, means = free_pose_session(rng, 24)
    return rng, p, dataclasses.replace(fit_triangular(means, gravity=1.0), unit="g")


def accelerometer_decisions(**drift) -> list:
    out = []
    for seed in range(SEEDS):
        rng, p, cal = phone(seed)
        out.append(check(cal, still_means=drifted_poses(rng, p, 24, **drift)).sensors[0])
    return out


def test_without_drift_the_check_keeps_the_calibration_at_least_nine_times_in_ten():
    checks = accelerometer_decisions()
    kept = [c.verdict == KEEP for c in checks]
    assert np.mean(kept) >= 0.9, np.mean(kept)
    first = checks[0]
    assert first.current is not None and first.fresh is not None
    assert first.current.unit == "mg" and first.current.value_deg is not None
    assert first.current.low <= first.current.value <= first.current.high
    # a fresh calibration on 24 new poses reaches about the noise of the simulated poses (0.5 mg and the hand's 3 mg)
    assert 0.3 < first.fresh.value < 1.5


def test_an_offset_drift_is_told_to_calibrate_again_naming_the_offsets():
    # 6 mg along x: the norm error it adds on random poses (its projection, 3 mg on average) is about 3 times the
    # fresh calibration's error (0.8 mg)
    checks = accelerometer_decisions(offset_g=(0.006, 0.0, 0.0))
    again = [c.verdict == AGAIN and c.drifted[:1] == ("offsets",) for c in checks]
    assert np.mean(again) >= 0.9, np.mean(again)
    first = checks[0]
    assert first.current.low > first.fresh.high
    assert "offsets drifted" in first.reasons[0] and "calibrate again" in first.reasons[0]
    moved = {d.axis: d for d in first.drift.differences if d.group == "offsets"}
    assert moved["x"].real and moved["x"].value == pytest.approx(6.0, abs=1.5)


def test_a_scale_drift_is_told_to_calibrate_again_naming_the_scales():
    checks = accelerometer_decisions(scale=(1.006, 1.0, 1.0))
    again = [c.verdict == AGAIN and c.drifted[:1] == ("scales",) for c in checks]
    assert np.mean(again) >= 0.9, np.mean(again)
    scale_x = next(d for d in checks[0].drift.differences if d.group == "scales" and d.axis == "x")
    assert scale_x.unit == "ppm" and scale_x.value == pytest.approx(-6000, abs=1500)


def test_too_few_poses_cannot_tell_and_say_what_to_record():
    rng, p, cal = phone(1)
    out = check(cal, still_means=drifted_poses(rng, p, 8))
    assert out.verdict == CANNOT
    assert "8 still poses" in out.reasons[0] and "12 or more" in out.reasons[0]


def compass(seed: int):
    m, M, b = simulate_session(seed, n=300)
    return np.random.default_rng(1000 + seed), M, b, fit_magnetometer(m, field_ut=F, field_source="model")


@pytest.mark.parametrize(
    ("drift", "verdict", "named"),
    [
        ("none", KEEP, ()),
        ("hard_iron", AGAIN, ("hard iron",)),
        ("soft_iron", AGAIN, ("soft iron",)),
        ("disturbance", MOVE, ()),
    ],
)
def test_a_compass_turn_tells_keep_hard_iron_soft_iron_and_move_the_compass(drift, verdict, named):
    told = []
    for seed in range(8):
        rng, M, b, cal = compass(seed)
        if drift == "disturbance":
            turn = disturbed_turn(rng, M, b)
        else:
            shift = np.array([3.0, 0.0, 0.0]) if drift == "hard_iron" else np.zeros(3)
            gain = np.diag([1.04, 1.0, 1.0]) if drift == "soft_iron" else np.eye(3)
            turn = simulate_turn(rng, M @ gain, b + shift, n=300)
        out = check(cal, mag=turn, inclination_deg=64.0)
        told.append((out.verdict, out.sensors[0].drifted))
    right = [v == verdict and d[: len(named)] == named for v, d in told]
    assert np.mean(right) >= 7 / 8, told


def test_the_compass_check_tells_the_heading_and_names_the_cause_of_a_disturbance():
    rng, M, b, cal = compass(3)
    kept = check_turn(cal.correction, simulate_turn(rng, M, b, n=300), field_ut=F, inclination_deg=64.0)
    assert kept.angle_kind == "heading" and kept.current.unit == "µT"
    assert kept.current.value_deg == pytest.approx(
        np.degrees(np.arcsin(kept.current.value / (F * np.cos(np.radians(64)))))
    )
    moved = check_turn(cal.correction, disturbed_turn(rng, M, b), field_ut=F)
    assert moved.verdict == MOVE and "move it away" in moved.reasons[0]


def test_a_turn_that_misses_directions_cannot_tell():
    rng, M, b, cal = compass(4)
    out = check_turn(cal.correction, simulate_turn(rng, M, b, n=300, max_polar_deg=80.0), field_ut=F)
    assert out.verdict == CANNOT and "turn the device slowly through all directions" in out.reasons[0]


def test_a_gyroscope_at_rest_keeps_a_small_bias_and_names_a_drifted_one():
    gyro = AffineCorrection(np.eye(3), np.array([0.5, -0.2, 0.1]), "°/s", "°/s", sensor="gyr")
    rng = np.random.default_rng(5)
    rest = gyro.o + rng.normal(0.0, 0.05, (1000, 3))
    assert check_rest(gyro, rest).verdict == KEEP
    drifted = check_rest(gyro, rest + [0.4, 0.0, 0.0])
    assert drifted.verdict == AGAIN and drifted.drifted == ("biases",)
    assert check_rest(gyro, rest[:20]).verdict == CANNOT


def test_real_mpu9250_sessions_check_one_another_s_calibration():
    """Each of the four sessions' six-position calibration checked on each other session's six poses (the fresh
    fit is then the affine model of known orientations on the six axis poses)."""
    sessions = mpu9250_sessions()
    verdicts = {}
    for a, (ups_a, means_a) in sessions.items():
        cal = dataclasses.replace(fit_six_position(means_a, ups_a, gravity=1.0), unit="g")
        for b, (ups_b, means_b) in sessions.items():
            if a != b:
                out = check(cal, still_means=means_b, labels=ups_b).sensors[0]
                verdicts[a, b] = out.verdict
                assert out.current.value < 3.0 and out.fresh.value < 3.0  # mg: the board holds its calibration
    assert set(verdicts.values()) == {KEEP}, verdicts


def test_real_qmc5883l_turn_halves_check_one_another_s_calibration():
    """The QMC5883L board of tests/data/real/magnetometer, turned by hand for 395 s (after 60 s at rest): the
    calibration of each half of the turn checked on the other half. Its readings are counts, and so are the
    figures; the board's own noise leaves 2.9 % of the field on any fit, which both halves reach."""
    counts = np.loadtxt(
        DATA / "real" / "magnetometer" / "tomisuarez2_qmc5883l_turn_every10.csv", delimiter=",", skiprows=4
    )
    turn = counts[300:]
    halves = turn[: len(turn) // 2], turn[len(turn) // 2 :]
    for mine, other in (halves, halves[::-1]):
        cal = dataclasses.replace(fit_magnetometer(mine, raw_comparable=False, label="counts"), unit="raw")
        out = check(cal, mag=other).sensors[0]
        assert out.verdict == KEEP, out.reasons
        assert out.current.unit == "counts" and out.current.low <= out.fresh.high
        assert out.current.value < 0.04 * cal.metrics["field_ut"]


def test_real_mpu6050_calibration_checked_on_its_one_pose_validation_session_cannot_tell():
    cal = dataclasses.replace(fit_triangular(mpu6050_session1(), gravity=1.0), unit="g")
    out = check(cal, still_means=mpu6050_session2())
    assert out.verdict == CANNOT and out.sensors[0].count == 1


def test_a_calibration_without_intervals_is_checked_through_its_correction_alone():
    """A calibration read from a firmware's file has a correction and no intervals: the check needs no more, and
    the drift's intervals are then the fresh fit's alone."""
    rng, M, b, cal = compass(6)
    bare = dataclasses.replace(cal, covariance=None)
    assert correction_half_widths(bare) == {"mag": (None, None)}
    out = check(bare, mag=simulate_turn(rng, M, b + np.array([0.0, 3.0, 0.0]), n=300))
    assert out.verdict == AGAIN and out.sensors[0].drifted == ("hard iron",)


def test_a_recording_of_a_sensor_the_calibration_does_not_correct_is_refused():
    cal = compass(1)[3]
    with pytest.raises(Exception, match="corrects mag"):
        check(cal, still_means=np.ones((12, 3)))


def test_a_compass_turned_against_the_accelerometer_is_named_by_the_dip_where_it_rested():
    """The turn alone cannot see the compass's orientation; its rests beside the accelerometer can: the field dips
    64° at the place, and a compass remounted 20° off reads another dip."""
    rng, M, b, cal = compass(9)
    turn = simulate_turn(rng, M, b, n=300)
    level = check(cal, mag=turn, rests=simulate_rests(rng, M, b, n=8), inclination_deg=64.0).sensors[0]
    assert level.verdict == KEEP, level.reasons
    angle = np.radians(20.0)
    remount = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(angle), -np.sin(angle)], [0.0, np.sin(angle), np.cos(angle)]])
    rests = [(acc, np.linalg.solve(M, remount @ (M @ (mag - b))) + b) for acc, mag in simulate_rests(rng, M, b, n=8)]
    turned = check(cal, mag=turn, rests=rests, inclination_deg=64.0).sensors[0]
    assert turned.verdict == AGAIN and turned.drifted == ("orientation",)
    assert "turned against the accelerometer" in turned.reasons[-1]
