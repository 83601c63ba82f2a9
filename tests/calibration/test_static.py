"""Static-segment detection on simulated raw logs (app.calibration.segments.static, simulations.logs)."""

import numpy as np
import pytest

from app.calibration import CANONICAL_SIX, fit_six_position
from app.calibration.segments.static import StaticSegment, _trim, detect_static_segments
from app.calibration.shared.errors import CalibrationError, InsufficientDataError
from app.calibration.shared.gravity import STANDARD_GRAVITY
from simulations.logs import simulate_static_log

BOUNDARY_TOL_S = 0.4
"""Detected boundaries must lie within this many seconds of the true ones."""


def _match(segs, log, tol_s=BOUNDARY_TOL_S):
    """Assert one detected segment per true rest, same label, boundaries within tol_s."""
    fs = log.sampling_rate_hz
    assert [s.up for s in segs] == [lab for _, _, lab in log.segments], (
        [(s.start, s.end, s.up) for s in segs],
        log.segments,
    )
    errors = []
    for seg, (start, end, _) in zip(segs, log.segments):
        errors += [(seg.start - start) / fs, (seg.end - end) / fs]
    assert max(abs(e) for e in errors) <= tol_s, errors
    return errors


@pytest.mark.parametrize("fs", [100.0, 200.0])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_six_rests_found_and_labelled(fs, seed):
    log = simulate_static_log(np.random.default_rng(seed), sampling_rate_hz=fs)
    assert sorted(lab for _, _, lab in log.segments) == sorted(CANONICAL_SIX)
    segs = detect_static_segments(log.samples, fs)
    _match(segs, log)
    for seg in segs:
        assert isinstance(seg, StaticSegment)
        assert seg.count == seg.end - seg.start and seg.gaps == ()
        assert np.all(seg.std < 0.05)  # noise 0.02 m/s² per axis
        assert seg.duration_s(fs) > 4.0


def test_same_result_with_gravity_given_and_in_g():
    log = simulate_static_log(np.random.default_rng(5), sampling_rate_hz=100.0)
    ref = detect_static_segments(log.samples, 100.0)
    given = detect_static_segments(log.samples, 100.0, gravity=STANDARD_GRAVITY)
    in_g = detect_static_segments(log.samples / STANDARD_GRAVITY, 100.0)
    assert [(s.start, s.end, s.up) for s in given] == [(s.start, s.end, s.up) for s in ref]
    assert [(s.start, s.end, s.up) for s in in_g] == [(s.start, s.end, s.up) for s in ref]


def test_raw_counts_with_offset():
    log = simulate_static_log(np.random.default_rng(6), sampling_rate_hz=100.0)
    raw = np.round(log.samples / STANDARD_GRAVITY * 16384.0 + 250.0)  # ±2 g, 16 bits, offset
    _match(detect_static_segments(raw, 100.0), log)


def test_repeated_orientations():
    log = simulate_static_log(np.random.default_rng(7), sampling_rate_hz=150.0, repeats=3)
    assert len(log.segments) == 9
    _match(detect_static_segments(log.samples, 150.0), log)


def _sweep_log(rate_deg_s, fs=100.0, seed=2):
    """Rest at +y, then a steady sweep at rate_deg_s from 30° before +z to 30° past it, rest at -y."""
    a = np.array([np.sin(np.radians(-30)), 0.0, np.cos(np.radians(-30))])
    b = np.array([np.sin(np.radians(30)), 0.0, np.cos(np.radians(30))])
    return simulate_static_log(
        np.random.default_rng(seed),
        orientations=["+y", a, b, "-y"],
        rest_s=[6.0, 0.0, 0.0, 6.0],
        turn_s=[2.0, 2.0, 60.0 / rate_deg_s, 2.0, 2.0],
        turn_profile=["smooth", "smooth", "constant", "smooth", "smooth"],
        tremor_deg=0.0,  # a steady (worst-case) sweep: nothing but the drift gives it away
        sampling_rate_hz=fs,
    )


@pytest.mark.parametrize("rate", [0.5, 1.0, 3.0])
def test_slow_rotation_through_a_pose_is_not_a_position(rate):
    log = _sweep_log(rate)
    assert [lab for *_, lab in log.segments] == ["+y", "-y"]
    # The sweep is quiet enough to pass the stillness test: only the drift check rejects it.
    lenient = detect_static_segments(log.samples, 100.0, max_drift_deg_per_s=1e9)
    assert any(s.up == "+z" or s.up is None for s in lenient[1:-1])
    segs = detect_static_segments(log.samples, 100.0)
    _match(segs, log)


@pytest.mark.parametrize("fs", [100.0, 200.0])
def test_bump_in_a_rest_is_not_an_orientation(fs):
    log = simulate_static_log(np.random.default_rng(11), sampling_rate_hz=fs, n_bumps=3, bump_amplitude=4.0)
    assert len(log.bumps) == 3
    segs = detect_static_segments(log.samples, fs)
    _match(segs, log)
    bumped = [s for s in segs if s.gaps]
    assert bumped, "the knocks should split and re-merge their rests"
    for seg in bumped:
        assert seg.count < seg.end - seg.start
        for g0, g1 in seg.gaps:
            assert seg.start < g0 < g1 < seg.end
    # Every knock's strongest part is left out of the statistics.
    for b0, _b1 in log.bumps:
        seg = next(s for s in segs if s.start <= b0 < s.end)
        assert any(g0 <= b0 + 1 and b0 + 3 <= g1 for g0, g1 in seg.gaps)
    # The means are unaffected: within 0.02 m/s² of the clean values.
    for seg, (_s, _e, _), d in zip(segs, log.segments, log.directions):
        truth = log.X @ (log.gravity * d) + log.y
        assert np.linalg.norm(seg.mean - truth) < 0.02


def test_slow_drift_does_not_split_or_reject():
    # 0.5 m/s² of warm-up drift over the log: far more than a phone's, still one rest each.
    log = simulate_static_log(np.random.default_rng(12), sampling_rate_hz=100.0, drift=0.5, rest_s=(10.0, 15.0))
    segs = detect_static_segments(log.samples, 100.0)
    _match(segs, log)
    assert all(s.drift_deg_per_s < 0.2 for s in segs)


@pytest.mark.parametrize("fs", [100.0, 200.0])
def test_quantised_browser_data(fs):
    log = simulate_static_log(
        np.random.default_rng(13), sampling_rate_hz=fs, quantisation_step=0.1, n_bumps=1, drift=0.1
    )
    # 0.1 m/s² steps: many windows of a rest have a spread of exactly 0.
    segs = detect_static_segments(log.samples, fs)
    _match(segs, log)


def test_to_dict():
    log = simulate_static_log(np.random.default_rng(3), sampling_rate_hz=100.0)
    d = detect_static_segments(log.samples, 100.0)[0].to_dict()
    assert set(d) == {"start", "end", "acc_mean", "acc_std", "up"}
    assert isinstance(d["start"], int) and len(d["acc_mean"]) == 3 and len(d["acc_std"]) == 3
    assert d["up"] == log.segments[0][2]


@pytest.mark.parametrize("fs", [100.0, 200.0])
def test_six_position_fit_on_first_segment_of_each_orientation(fs):
    log = simulate_static_log(np.random.default_rng(21), sampling_rate_hz=fs, repeats=2, n_bumps=1)
    segs = detect_static_segments(log.samples, fs)
    first = {}
    for seg in segs:
        first.setdefault(seg.up, seg)
    assert sorted(first) == sorted(CANONICAL_SIX)
    ups = list(first)
    means = np.array([first[u].mean for u in ups])
    cal = fit_six_position(means, ups, gravity=STANDARD_GRAVITY)
    assert cal.ok
    norms = np.linalg.norm(cal.apply(np.array([s.mean for s in segs])), axis=1)
    assert np.max(np.abs(norms / STANDARD_GRAVITY - 1.0)) < 0.002
    np.testing.assert_allclose(cal.X, log.X, atol=2e-3)
    np.testing.assert_allclose(cal.y, log.y, atol=0.01)


def test_nothing_still():
    rng = np.random.default_rng(0)
    samples = rng.normal(0, 3.0, size=(2000, 3)) + [0, 0, 9.8]
    assert detect_static_segments(samples, 100.0, gravity=9.80665) == []


@pytest.mark.parametrize(
    "samples, fs, exc, words",
    [
        (np.zeros((100, 2)), 100.0, CalibrationError, "N×3"),
        (np.array([[0.0, 0.0, np.nan]] * 100), 100.0, CalibrationError, "NaN"),
        (np.ones((100, 3)), 0.0, CalibrationError, "sampling_rate_hz"),
        (np.ones((100, 3)), -5.0, CalibrationError, "sampling_rate_hz"),
        (np.ones((100, 3)), float("nan"), CalibrationError, "sampling_rate_hz"),
        (np.ones((10, 3)), 100.0, InsufficientDataError, "window"),
        ("abc", 100.0, CalibrationError, "[x, y, z]"),
    ],
)
def test_input_errors(samples, fs, exc, words):
    with pytest.raises(exc, match=None) as info:
        detect_static_segments(samples, fs)
    assert words in str(info.value)


def test_zero_stream_is_refused():
    with pytest.raises(CalibrationError, match="no gravity"):
        detect_static_segments(np.zeros((500, 3)), 100.0)


def test_simulator_is_seeded():
    a = simulate_static_log(np.random.default_rng(9), n_bumps=1, drift=0.1)
    b = simulate_static_log(np.random.default_rng(9), n_bumps=1, drift=0.1)
    np.testing.assert_array_equal(a.samples, b.samples)
    assert a.segments == b.segments and a.bumps == b.bumps
    d = a.to_dict()
    assert d["model"]["type"] == "affine" and len(d["segments"]) == 6


def test_fixture_csv_matches_its_truth():
    import json
    from pathlib import Path

    data = Path(__file__).resolve().parents[1] / "data"
    truth = json.loads((data / "six_orientations_150hz.json").read_text())
    samples = np.loadtxt(data / "six_orientations_150hz.csv", delimiter=",", skiprows=1)
    assert samples.shape == (truth["n_samples"], 3)
    segs = detect_static_segments(samples, truth["sampling_rate_hz"])
    assert [s.up for s in segs] == [t["up"] for t in truth["segments"]]
    assert [s.up for s in segs] != list(CANONICAL_SIX)
    for seg, t in zip(segs, truth["segments"]):
        assert abs(seg.start - t["start"]) <= 0.4 * 150 and abs(seg.end - t["end"]) <= 0.4 * 150
    assert any(s.gaps for s in segs)  # the knock


def test_a_rest_is_still_on_every_sensor_a_ringing_gyroscope_and_a_turning_compass_cut_it():
    # 30 s on a table at 100 Hz: the accelerometer never moves; the gyroscope rings at 8 Hz (0.08 rad/s,
    # decaying) for 1.5 s after a touch at 10 s; the compass turns about gravity (the accelerometer sees
    # nothing) from 20 to 22 s. Its gyroscope is quantised to 0.01 rad/s, coarser than its noise.
    rng = np.random.default_rng(31)
    fs, n = 100.0, 3000
    t = np.arange(n) / fs
    acc = np.array([0.0, 0.0, 9.80665]) + rng.normal(scale=0.02, size=(n, 3))
    gyr = rng.normal(scale=0.003, size=(n, 3))
    ring = (t >= 10) & (t < 11.5)
    ringing = np.zeros(n)
    ringing[ring] = 0.08 * np.exp(-(t[ring] - 10) / 0.5) * np.sin(2 * np.pi * 8 * (t[ring] - 10))
    gyr[:, 0] += ringing
    gyr = np.round(gyr, 2)
    heading = np.clip((t - 20) / 2, 0, 1) * np.pi / 2
    mag = np.column_stack([30 * np.cos(heading), 30 * np.sin(heading), np.full(n, -40.0)])
    mag += rng.normal(scale=0.3, size=(n, 3))
    assert len(detect_static_segments(acc, fs)) == 1  # the accelerometer alone: one rest, end to end
    segs = detect_static_segments(acc, fs, others=[gyr, mag])
    used = np.zeros(n, dtype=bool)  # the samples the rests' statistics take: their gaps (knocks) left out
    for s in segs:
        used[s.start : s.end] = True
        for a, b in s.gaps:
            used[a:b] = False
    assert len(segs) == 2, [(s.start / fs, s.end / fs, s.gaps) for s in segs]
    assert not used[np.abs(ringing) > 0.04].any()  # none takes the ringing above 4 × the windows' noise floor
    assert not used[(t >= 20.2) & (t < 21.8)].any()  # nor the compass's turn, but for its first and last degrees
    assert used.mean() > 0.8 and used[0] and used[-1]


def test_a_run_too_short_to_have_an_inside_is_left_as_it_is_without_a_warning():
    """A still run of two samples (seen on a real compass turned by hand, its units mislabelled) has no
    inside to compare its edges with: it is not cut, and no division by zero is announced."""
    import warnings

    x = np.random.default_rng(4).normal(size=(40, 3))
    csum = np.zeros((41, 3))
    np.cumsum(x, axis=0, out=csum[1:])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        a, b = _trim(x, csum, np.array([3, 10]), np.array([5, 40]), 5, 2, 0.5)
    assert (a[0], b[0]) == (3, 5)
    assert 10 <= a[1] < b[1] <= 40
