"""calibrate_cube end to end: segmentation, drift, sequence checks and the three sensors (Särkkä et al.)."""

import json
import sys

import numpy as np
import pytest

from app.calibration import CalibrationError, InsufficientDataError
from app.calibration.cube import CubeCalibration, calibrate_cube, check_sequence, explicit_protocol
from simulations.cube import FIELD_UT, GRAVITY, simulate_session, true_parameters
from tests.processes import run_ok

FS = 50.0


def _run(session, **kw):
    kw.setdefault("protocol", session.protocol)
    return calibrate_cube(
        session.acc,
        session.gyr,
        session.mag,
        sampling_rate_hz=session.sampling_rate_hz,
        gravity=GRAVITY,
        field_ut=FIELD_UT,
        **kw,
    )


@pytest.fixture(scope="module")
def good():
    s = simulate_session(
        np.random.default_rng(11),
        sampling_rate_hz=FS,
        return_to_start=True,
        drift_per_s={"acc": [2e-6, -1e-6, 3e-6], "gyr": [2e-5, 0, -1e-5]},
    )
    return s, _run(s)


def test_cube24_session_recovers_all_three_sensors(good):
    _s, r = good
    assert r.ok, r.reasons
    assert r.first_wrong_rotation is None and len(r.sequence) == 24  # 23 rotations + the return
    assert all(e["ok"] for e in r.sequence)
    assert r.metrics["n_positions_found"] == 25 and r.metrics["rotations_used"] == list(range(1, 24))
    assert r.drift["acc"].significant  # Särkkä et al. section II
    for name in ("acc", "gyr", "mag"):
        res = getattr(r, name)
        S, b = true_parameters(name)
        u = res.uncertainty()
        assert np.all(np.abs(res.S - S) <= 2.5 * np.array(u["S"])), name
        assert np.all(np.abs(res.b - b) <= 2.5 * np.array(u["b"])), name
    for name in ("acc", "mag"):
        res = getattr(r, name)
        u = res.uncertainty()
        assert abs(res.alpha_deg - 15.0) <= 2.5 * u["alpha_deg"] and abs(res.beta_deg - 10.0) <= 2.5 * u["beta_deg"]


def test_to_dict_has_the_design_model_and_round_trips(good):
    s, r = good
    d = r.to_dict()
    json.dumps(d)
    assert d["model"]["type"] == "cube"
    assert set(d["model"]["acc"]) == {"S", "b", "D", "misalignment", "alpha_deg", "beta_deg"}
    assert {"S", "b", "D", "misalignment"} <= set(d["model"]["gyr"])
    for name in ("acc", "gyr", "mag"):
        for key in ("S", "b", "D", "misalignment"):
            assert np.shape(d["uncertainty"][name][key]) == np.shape(d["model"][name][key])
    assert len(d["sequence"]) == 24 and d["sequence"][0]["rotation"] == 1
    back = CubeCalibration.from_dict(d)
    assert back.to_dict()["model"] == d["model"]
    np.testing.assert_allclose(back.apply(acc=s.acc[:5])["acc"], r.apply(acc=s.acc[:5])["acc"])


def test_wrong_axis_is_flagged_at_that_rotation_and_earlier_positions_still_calibrate():
    # Rotation 18 should turn the cube about the vertical (z+); here it tips it (y+) instead.
    s = simulate_session(np.random.default_rng(12), sampling_rate_hz=FS, wrong_rotations={18: "y+"})
    r = _run(s)
    assert not r.ok
    assert r.first_wrong_rotation == 18
    assert "rotation 18" in r.reasons[0] and "position 19" in r.reasons[0]
    assert r.sequence[17]["ok"] is False and all(e["ok"] for e in r.sequence[:17])
    assert r.metrics["n_positions_used"] == 18 and r.metrics["rotations_used"] == list(range(1, 18))
    _S, b = true_parameters("acc")
    assert np.all(np.abs(r.acc.b - b) <= 3 * np.array(r.acc.uncertainty()["b"]))
    assert r.gyr is not None and r.mag is not None


def test_wrong_direction_about_the_right_axis_is_caught_by_the_gyroscope():
    # z− instead of z+: the same face stays up, only the integrated attitude tells (VII-A-1).
    s = simulate_session(np.random.default_rng(13), sampling_rate_hz=FS, wrong_rotations={2: "z-"})
    r = _run(s)
    assert r.first_wrong_rotation == 2
    e = r.sequence[1]
    assert e["observed_up"] == e["expected_up"] and e["max_element_difference"] > 0.1
    assert r.gyr is None and r.acc is None and not r.ok  # positions 1-2 cannot calibrate anything


def test_full_turn_is_told_apart_from_no_turn():
    protocol = explicit_protocol(["z+360", "x+"], ups=["+z", "+z", "+y"])
    fs = 100.0
    t = np.arange(int(2 * fs)) / fs
    spin = np.c_[np.zeros_like(t), np.zeros_like(t), np.pi * (1 - np.cos(np.pi * t / 2))]  # ∫ = 2π
    acc_means = np.array([[0, 0, 9.8], [0, 0, 9.8], [0, 9.8, 0]])
    still = np.zeros((int(fs), 3))
    tip = np.c_[np.pi / 4 * (1 - np.cos(np.pi * t / 2)), np.zeros_like(t), np.zeros_like(t)]
    for first, expect_ok in ((spin, True), (np.zeros_like(spin), False)):
        gyr = np.vstack([still, first, still, tip, still])
        n0 = len(still)
        rots = ((n0, n0 + len(t)), (2 * n0 + len(t), 2 * n0 + 2 * len(t)))
        chk = check_sequence(gyr, acc_means, rots, protocol, sampling_rate_hz=fs, gyro_bias=np.zeros(3), gravity=9.8)
        assert chk.rotations[0]["ok"] is expect_ok
        assert (chk.first_wrong == 1) is (not expect_ok)


def test_rotations_beyond_the_gyroscope_range():
    s = simulate_session(np.random.default_rng(14), sampling_rate_hz=FS, with_mag=False)
    clipped = np.clip(s.gyr, -0.9, 0.9)
    r = calibrate_cube(s.acc, clipped, sampling_rate_hz=FS, protocol="cube24", gravity=GRAVITY)
    assert not r.ok
    assert any("range" in x for x in r.reasons)
    assert r.gyr is None and r.acc is not None
    assert any(e["saturated"] for e in r.sequence)


def test_ferraris_protocol_calibrates_acc_and_gyro_without_field_direction():
    # Full turns about a fixed axis: the assumption of the rotation-vector (Ferraris) method.
    s = simulate_session(
        np.random.default_rng(15), "ferraris", sampling_rate_hz=FS, alpha_deg=0.0, beta_deg=0.0, wander_deg=0.0
    )
    r = _run(s)
    assert r.ok, r.reasons
    assert r.mag is None and any("mag not calibrated" in w for w in r.warnings)
    assert r.acc.alpha_deg == 0.0 and r.acc.uncertainty()["alpha_deg"] is None
    S, b = true_parameters("gyr")
    u = r.gyr.uncertainty()
    assert np.all(np.abs(r.gyr.S - S) <= 3 * np.array(u["S"]))
    assert np.all(np.abs(r.gyr.b - b) <= 3 * np.array(u["b"]))


def test_invalid_input_and_mismatched_protocols():
    s = simulate_session(np.random.default_rng(16), sampling_rate_hz=FS, with_mag=False)
    with pytest.raises(CalibrationError, match="needs the gyroscope"):
        calibrate_cube(s.acc, None, sampling_rate_hz=FS, protocol="cube24", gravity=GRAVITY)
    with pytest.raises(InsufficientDataError, match="no full turn about x, y, z was found"):
        calibrate_cube(s.acc, s.gyr, sampling_rate_hz=FS, protocol="ferraris", gravity=GRAVITY)
    n = s.static_segments[3][1]  # only the first four positions were recorded
    with pytest.raises(CalibrationError, match="found 4 still positions"):
        calibrate_cube(s.acc[:n], s.gyr[:n], sampling_rate_hz=FS, protocol="cube24", gravity=GRAVITY)
    with pytest.raises(InsufficientDataError, match="still"):
        calibrate_cube(s.acc[500:560], s.gyr[500:560] + 1.0, sampling_rate_hz=FS, protocol="cube24", gravity=GRAVITY)
    with pytest.raises(CalibrationError, match="field_ut"):
        calibrate_cube(s.acc, s.gyr, s.acc, sampling_rate_hz=FS, protocol="cube24", gravity=GRAVITY)
    with pytest.raises(CalibrationError, match="sampled together"):
        calibrate_cube(s.acc, s.gyr[:-1], sampling_rate_hz=FS, protocol="cube24", gravity=GRAVITY)


def test_core_does_not_import_the_web_stack():
    code = (
        "import sys, app.calibration.cube as c; "
        "print(any(m.split('.')[0] in ('fastapi', 'pydantic') for m in sys.modules))"
    )
    out = run_ok([sys.executable, "-c", code], timeout_s=120)
    assert out.stdout.strip() == "False"


def test_segmentation_finds_the_still_positions_inside_the_true_ones(good):
    s, r = good
    seg = r.segmentation
    assert len(seg.static) == len(s.static_segments) == 25
    for (a, b), (ta, tb) in zip(seg.static, s.static_segments):
        assert ta <= a < b <= tb and (b - a) >= 0.8 * (tb - ta) - 2 * 0.3 * FS
    for (a, b), (_, tb), (ta1, _) in zip(seg.rotations, s.static_segments[:-1], s.static_segments[1:]):
        assert a <= tb and b >= ta1  # each rotation is integrated from rest to rest


def test_drift_from_the_return_to_position_1():
    from app.calibration.cube.drift import estimate_drift

    fs = 10.0
    rng = np.random.default_rng(0)
    raw = rng.normal(0, 1e-3, (1000, 3)) + np.arange(1000)[:, None] / fs * np.array([1e-3, 0, -2e-3])
    d = estimate_drift(raw, (0, 50), (950, 1000), sampling_rate_hz=fs)
    np.testing.assert_allclose(d.rate, [1e-3, 0, -2e-3], atol=5e-6)
    assert d.significant
    fixed = d.remove(raw, fs)
    assert abs(fixed[950:].mean(0) - fixed[:50].mean(0)).max() < 1e-12


def test_cube24_pauses_and_hand_moves_that_are_not_a_quarter_turn_are_handling():
    # A hand nudges the cube in positions 3 and 10: 8° there and back, 1 s, splitting each rest in two.
    s = simulate_session(np.random.default_rng(17), sampling_rate_hz=FS, with_mag=False)
    gyr = s.gyr.copy()
    t = np.arange(int(FS)) / FS
    nudge = np.radians(8.0) * np.pi * np.sin(2 * np.pi * t)  # ∫ over the second = 0: back where it was
    for k in (2, 9):
        a, b = s.static_segments[k]
        mid = (a + b) // 2 - len(t) // 2
        gyr[mid : mid + len(t), 0] += nudge
    r = calibrate_cube(s.acc, gyr, sampling_rate_hz=FS, protocol="cube24", gravity=GRAVITY)
    assert r.ok, r.reasons
    assert (r.metrics["n_still_found"], r.metrics["n_positions_found"]) == (26, 24)
    assert sorted(h["kind"] for h in r.segmentation.handling) == ["move", "move", "pause", "pause"]
    assert r.metrics["rotations_used"] == list(range(1, 24))
    assert any(w.startswith("treated as handling") and "+z stayed up" in w for w in r.warnings)
    S, b = true_parameters("gyr")
    u = r.gyr.uncertainty()
    assert np.all(np.abs(r.gyr.S - S) <= 3 * np.array(u["S"]))
