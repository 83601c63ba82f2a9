"""Noise characterisation by the overlapping Allan deviation (app/calibration/noise/allan.py, noise.py):
equality with allantools (on the corpus's real still recordings first), the τ grid, recovery and coverage of
simulated N, B, K, nulls when too short."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import allantools
import numpy as np
import pytest

from app.calibration.noise.allan import (
    CHUNK,
    FLICKER,
    FUSED,
    NOT_BUILT,
    RANDOM_WALK,
    ROW,
    WHITE,
    chi2_interval,
    edf_simple,
    overlapping_adev,
    phase_of,
    second_difference_sums,
    second_difference_sums_fast,
    tau_grid,
)
from app.calibration.noise.characterise import NoiseResult, characterise_noise
from app.calibration.shared.errors import InsufficientDataError
from app.calibration.shared.result import CalibrationResult
from simulations.noise import simulate_still

FS = 100.0
TRUTH = {"noise_density": 0.01, "bias_instability": 0.015, "random_walk": 0.00224}
"""White noise meets the floor at τ ≈ 1 s, the floor meets the random walk at τ ≈ 60 s."""


def _simulate(seed, n=120_000, **kw):
    terms = dict(N=TRUTH["noise_density"], B=TRUTH["bias_instability"], K=TRUTH["random_walk"])
    terms.update(kw)
    return simulate_still(np.random.default_rng(seed), n_samples=n, sampling_rate_hz=FS, **terms)


def test_equals_allantools_oadev_on_the_same_taus():
    rng = np.random.default_rng(3)
    y = rng.normal(0.0, 0.02, (200_000, 3)) + np.cumsum(rng.normal(0.0, 1e-4, (200_000, 3)), axis=0) + [0.3, -9.8, 1.0]
    tau, adev, n_terms, mean = overlapping_adev(y, 200.0)
    assert np.allclose(mean, y.mean(axis=0))
    for k in range(3):
        taus, dev, _, ns = allantools.oadev(y[:, k], rate=200.0, data_type="freq", taus=tau)
        np.testing.assert_allclose(taus, tau, rtol=1e-12)
        np.testing.assert_allclose(adev[:, k], dev, rtol=1e-9)
        np.testing.assert_array_equal(n_terms, ns)


LOOPS = [pytest.param(True, id="fused"), pytest.param(False, id="numpy")]
"""A core's share summed by the compiled loop, and by numpy (its stand-in where it was not built)."""


def test_the_fused_loop_is_built():
    assert FUSED, NOT_BUILT


def test_the_fused_loop_refuses_what_it_cannot_sum():
    from app.calibration.noise.allan_fused import sums_of_share

    x = np.cumsum(np.random.default_rng(5).normal(size=1000))
    out = np.empty(2)
    for ms, share, shares, into, words in [
        ([0, 1], 0, 1, out, "averaging factor 0 outside 1 … 499"),
        ([1, 500], 0, 1, out, "averaging factor 500 outside 1 … 499 for 1000 phase points"),
        ([1, 2], 2, 2, out, "share 2 of 2"),
        ([1, 2], 0, 1, np.empty(3), "3 sums to write for 2 averaging factors"),
    ]:
        with pytest.raises(ValueError, match=words):
            sums_of_share(x, np.array(ms, dtype=np.int64), share, shares, into)
    with pytest.raises(ValueError, match="not C-contiguous"):
        sums_of_share(x[::2], np.array([1], dtype=np.int64), 0, 1, out[:1])


@pytest.mark.parametrize("fused", LOOPS)
@pytest.mark.parametrize("workers", [1, 2, 3])
def test_the_shared_sums_equal_the_plain_reference(workers, fused):
    """The shared sums against the plain loop, at every m of the grid, at a numpy block's length and on
    either side of it: the fused loop (eight running sums and a rest), and the numpy one (first
    differences reused for m up to a block, the three windows apart beyond, squared and summed in rows of
    dot products and a shorter rest)."""
    rng = np.random.default_rng(11)
    n = 4 * CHUNK + 3 * ROW + 17  # blocks that end in a partial row
    y = rng.normal(0.0, 0.02, n) + np.cumsum(rng.normal(0.0, 1e-4, n))
    x, _ = phase_of(y, 100.0)
    ms = np.unique(np.concatenate([tau_grid(len(y), 100.0), [CHUNK - 1, CHUNK, CHUNK + 1, 2 * CHUNK + 5]]))
    reference = second_difference_sums(x, ms)
    with ThreadPoolExecutor(max_workers=workers) as pool:
        shared = second_difference_sums_fast(x, ms, pool, workers, fused)
    np.testing.assert_allclose(shared, reference, rtol=1e-12)
    np.testing.assert_allclose(second_difference_sums_fast(x, ms, fused=fused), reference, rtol=1e-12)


def test_tau_grid_has_ten_points_per_decade_up_to_the_longest_tau():
    ms = tau_grid(2_160_000, 200.0)
    assert list(ms[:10]) == list(range(1, 11))
    assert ms[-1] == (2_160_000 - 1) // 2
    for k in range(1, 6):  # every full decade of m holds at least 10 points (m = 1 … 10 the first)
        assert np.count_nonzero((ms >= 10**k) & (ms < 10 ** (k + 1))) >= 10, k
    with pytest.raises(InsufficientDataError, match="too few"):
        tau_grid(10, 100.0)


def test_recovers_the_simulated_terms_in_their_units():
    r = characterise_noise(_simulate(1, n=360_000), FS, unit="rad/s")
    assert r["model"]["noise_density_unit"] == "rad/s/√Hz" and r["model"]["random_walk_unit"] == "rad/s²/√Hz"
    for name, truth in TRUTH.items():
        np.testing.assert_allclose(r["model"][name], truth, rtol=0.35, err_msg=name)
    assert r["warnings"] == []


def test_the_95_percent_intervals_cover_the_truth():
    # 40 simulations × 3 axes here; bench/noise_coverage.py runs the 200.
    hits = dict.fromkeys(TRUTH, 0)
    seen = dict.fromkeys(TRUTH, 0)
    for seed in range(40):
        r = characterise_noise(_simulate(100 + seed), FS, unit="rad/s")
        for name, truth in TRUTH.items():
            for interval in r["uncertainty"][name]:
                if interval is not None:
                    seen[name] += 1
                    hits[name] += interval[0] <= truth <= interval[1]
    for name in TRUTH:
        assert seen[name] >= 100, name
        assert 0.88 <= hits[name] / seen[name] <= 1.0, (name, hits[name] / seen[name])


def test_too_short_a_recording_gives_nulls_and_says_how_long_to_record():
    r = characterise_noise(_simulate(5, n=3_000), FS, unit="m/s^2", sensor="acc")  # 30 s
    assert r["model"]["random_walk"] == [None, None, None]
    assert r["uncertainty"]["random_walk"] == [None, None, None]
    assert all(v is not None for v in r["model"]["noise_density"])
    text = " ".join(r["warnings"])
    assert "acc x/y/z: random_walk is null" in text and "record the device still for at least" in text
    assert r["model"]["noise_density_unit"] == "m/s²/√Hz"


def test_result_round_trips_and_corrects_nothing():
    part = characterise_noise(_simulate(7, n=20_000), FS, unit="rad/s")
    result = NoiseResult(
        sensors={"gyr": {k: part[k] for k in ("model", "adev", "uncertainty", "metrics")}},
        sampling_rate_hz=FS,
        duration_s=part["duration_s"],
        unit="rad/s",
    )
    body = result.to_dict()
    assert body["model"]["type"] == "noise" and body["method"] == "noise"
    again = CalibrationResult.from_dict(body)
    assert isinstance(again, NoiseResult) and again.to_dict() == body
    assert again.corrections() == {}
    with pytest.raises(ValueError, match="corrects nothing"):
        again.apply(np.zeros((1, 3)))


def test_a_still_recording_that_drifts_is_still_from_end_to_end():
    # An accelerometer with 1 mg of bias instability and a strong random walk over 20 minutes: its
    # mean wanders by more than the orientation segments tolerate, yet it never moved.
    from app.calibration.noise.still_part import longest_still

    rng = np.random.default_rng(8)
    n = 120_000
    acc = np.array([0.0, 0.0, 9.80665]) + simulate_still(rng, n_samples=n, sampling_rate_hz=FS, N=0.02, B=0.01, K=4e-3)
    assert longest_still(acc, FS) == (0, n)
    # Handling for 3 s splits it (knocks up to a second are merged): the longer side is kept.
    acc[70_000:70_300] += rng.normal(scale=3.0, size=(300, 3))
    a, b = longest_still(acc, FS)
    assert a == 0 and 69_900 < b < 70_100  # to within a window (0.5 s)


def test_a_gyroscope_turned_at_a_steady_rate_between_rests_is_not_still():
    # Six rests of 20 s joined by 2 s turns at 45 °/s: the spread of a turn is as small as a rest's,
    # its level is not — six rests, and no stretch across a turn (the turns are stretches of their own).
    from app.calibration.noise.still_part import still_runs

    rng = np.random.default_rng(9)
    parts, starts = [], []
    for k in range(6):
        if k:
            parts.append(np.array([0.785, 0.0, 0.0]) + rng.normal(scale=0.01, size=(200, 3)))
        starts.append(sum(len(p) for p in parts))
        parts.append(simulate_still(rng, n_samples=2_000, sampling_rate_hz=FS, N=1e-3, B=0, K=0))
    runs = still_runs(np.vstack(parts), FS)
    rests = [r for r in runs if r[1] - r[0] > 1_000]
    assert len(rests) == 6
    for (a, b), start in zip(rests, starts):
        assert start - 50 <= a and b <= start + 2_000 + 50 and b - a > 1_900
    edges = [e for start in starts for e in (start, start + 2_000)][1:-1]
    assert not any(a + 50 < e < b - 50 for a, b in runs for e in edges)


@pytest.mark.parametrize("dtype", [np.float64, np.float32, np.int16])
@pytest.mark.parametrize("axes", [2, 3, 4])
def test_the_blocks_laid_across_give_numpy_s_spreads_and_means_to_the_last_bit(dtype, axes):
    """still_runs sums each chunk's blocks laid across (app.calibration.noise.still_part._block_spreads_across):
    the same figures as numpy's mean and variance of each block (_block_spreads), bit for bit, so the
    still runs are those numpy's sums give."""
    from app.calibration.noise.still_part import _block_spreads, _block_spreads_across

    rng = np.random.default_rng(axes)
    for blocks, w in [(327, 100), (50, 17), (3, 250), (1, 2)]:
        rows = rng.normal(size=(blocks * w, axes + 1)) * rng.uniform(1e-3, 1e3) + rng.normal() * 100
        samples = rows[:, 1:].astype(dtype)  # a view with the time column beside it, as an N×4 .npy's
        part = np.asarray(samples, dtype=float).reshape(blocks, w, axes)
        expected = np.empty(blocks), np.empty((blocks, axes))
        got = np.empty(blocks), np.empty((blocks, axes))
        _block_spreads(part, *expected)
        _block_spreads_across(part, *got)
        assert np.array_equal(got[0], expected[0]) and np.array_equal(got[1], expected[1])
        # In part of a larger buffer (a thread's, reused chunk after chunk), the same.
        _block_spreads_across(part, *got, across=np.empty((w, axes, blocks + 5))[..., :blocks])
        assert np.array_equal(got[0], expected[0]) and np.array_equal(got[1], expected[1])


def test_the_three_term_nnls_equals_scipy_s():
    from scipy.optimize import nnls

    from app.calibration.noise.characterise import _nnls

    rng = np.random.default_rng(3)
    for _ in range(500):
        a, b = rng.random((25, 3)), rng.normal(size=25)
        np.testing.assert_allclose(_nnls(a, b), nnls(a, b)[0], atol=1e-12)


def test_an_axis_that_never_changes_is_refused_in_words():
    """A magnetometer column printing one value (a board without one prints zeros) has no noise: a
    refusal naming the axis, not a failed decomposition of an all-zero Allan variance."""
    x = np.random.default_rng(7).normal(0.0, 0.05, size=(20_000, 3))
    x[:, 2] = 0.0
    with pytest.raises(InsufficientDataError, match=r"the magnetometer's z axis readings do not change"):
        characterise_noise(x, 100.0, unit="uT", sensor="mag")


def _real_still_logs():
    """The corpus's real still recordings that trical characterises (tests/data/real/corpus, method noise):
    a BNO055 on a Raspberry Pi's serial port, an HMC5883L on an ESP32, a phone's LSM6DS3, an MPU-6050's gyroscope
    in counts, a PX4 flight controller's gyroscope after landing — read as their upload form says."""
    from app.io.readers import read_log
    from app.io.readers.read_options import ReadOptions, units_named
    from tests import real_corpus

    for case in real_corpus.cases():
        if case.spec.get("calibrate", {}).get("method") != "noise" or case.spec["expect"].get("status") != 201:
            continue
        form = case.form
        options = ReadOptions(
            sampling_rate_hz=float(form["sampling_rate_hz"]) if "sampling_rate_hz" in form else None,
            columns=form.get("columns"),
            lsb_per_g=float(form["lsb_per_g"]) if "lsb_per_g" in form else None,
            units=units_named(form.get("acc_unit"), form.get("gyr_unit"), form.get("mag_unit")),
        )
        log = read_log(case.files[0], options, name=case.files[0].name)
        for sensor in ("acc", "gyr", "mag"):
            if getattr(log, sensor) is not None:
                yield pytest.param(getattr(log, sensor), log.sampling_rate_hz, id=f"{case.name}-{sensor}")


REAL_STILL = list(_real_still_logs())


def test_the_corpus_holds_real_still_recordings_of_every_kind():
    assert len(REAL_STILL) >= 12 and {p.id.rsplit("-", 1)[1] for p in REAL_STILL} == {"acc", "gyr", "mag"}


@pytest.mark.parametrize(("samples", "fs"), REAL_STILL)
def test_real_still_recordings_give_allantools_oadev_and_the_reference_sums(samples, fs):
    """On real sensors' readings (counts that repeat, a quantised compass, a phone's irregular clock, a
    flight controller ringing), the shared sums of both loops equal the plain reference, and the Allan
    deviation allantools' oadev at every τ; a board's integer counts saved as int16 give the same figures."""
    tau, adev, n_terms, mean = overlapping_adev(samples, fs)
    for k in range(3):
        _, dev, _, ns = allantools.oadev(np.ascontiguousarray(samples[:, k]), rate=fs, data_type="freq", taus=tau)
        np.testing.assert_allclose(adev[:, k], dev, rtol=1e-9)
        np.testing.assert_array_equal(n_terms, ns)
        x, _ = phase_of(samples[:, k], fs)
        ms = np.round(tau * fs).astype(np.int64)
        reference = second_difference_sums(x, ms)
        with ThreadPoolExecutor(max_workers=2) as pool:
            for fused in (True, False):
                np.testing.assert_allclose(second_difference_sums_fast(x, ms, pool, 2, fused), reference, rtol=1e-12)
    if np.array_equal(samples, np.rint(samples)) and np.abs(samples).max() < 2**15:
        counts = overlapping_adev(samples.astype(np.int16), fs)
        np.testing.assert_allclose(counts[1], adev, rtol=1e-12)
        np.testing.assert_allclose(counts[3], mean, rtol=1e-12)


@pytest.mark.parametrize(("samples", "fs"), REAL_STILL)
def test_real_still_recordings_intervals_are_scipy_s(samples, fs):
    """The χ² factors of every τ's interval on a real recording (its edf for each noise type) are scipy's."""
    from scipy.stats import chi2

    ms = tau_grid(len(samples), fs)
    for alpha in (WHITE, FLICKER, RANDOM_WALK):
        edf = edf_simple(len(samples) + 1, ms, alpha)
        lo, hi = chi2_interval(edf, 0.95)
        np.testing.assert_allclose(lo, edf / chi2.ppf(0.975, edf), rtol=1e-12)
        np.testing.assert_allclose(hi, edf / chi2.ppf(0.025, edf), rtol=1e-12)


def test_a_periodic_disturbance_is_named_and_the_density_read_on_the_white_noise_line():
    """A still gyroscope beside a fan (seeded: white noise 1e-3 rad/s/√Hz and a 3.7 Hz sinusoid of 0.01 rad/s on
    x, half that on y): the hump at τ ≈ 0.13 s is named with its frequency, and the noise density read on the
    white-noise line within 3 % (read through the hump it was 2.5× too high on x)."""
    from simulations.noise import simulate_still

    rng = np.random.default_rng(3)
    fs, n = 100.0, 60_000
    still = simulate_still(rng, n_samples=n, sampling_rate_hz=fs, N=1e-3, B=1e-4, K=1e-5)
    t = np.arange(n)[:, None] / fs
    fan = 0.01 * np.sin(2 * np.pi * 3.7 * t + rng.uniform(0, 6, 3)) * np.array([1.0, 0.5, 0.0])
    r = characterise_noise(still + fan, fs, unit="rad/s")
    np.testing.assert_allclose(r["model"]["noise_density"], 1e-3, rtol=0.03)
    assert (
        r["metrics"]["hump_tau_s"][:2] == [pytest.approx(0.13, abs=0.01)] * 2 and r["metrics"]["hump_tau_s"][2] is None
    )
    np.testing.assert_allclose(r["metrics"]["hump_hz"][:2], 3.7, rtol=0.05)
    (said,) = [w for w in r["warnings"] if "hump" in w]
    assert said.startswith("gyr x/y: a hump in the Allan deviation at τ ≈ 0.13 s")
    assert f"near {r['metrics']['hump_hz'][0]:.2g} Hz" in said


def test_no_hump_is_named_in_clean_still_recordings():
    """Forty seeded still recordings of every length, rate and mix of terms: not one hump (each test compares
    some twenty points of the curve, at 99.9 %)."""
    from simulations.noise import simulate_still

    for seed in range(40):
        rng = np.random.default_rng(100 + seed)
        n, fs = int(rng.choice([3000, 20000, 60000])), float(rng.choice([50, 100, 400]))
        b, k = float(rng.choice([0, 1e-4, 1e-3])), float(rng.choice([0, 1e-5, 1e-4]))
        x = simulate_still(rng, n_samples=n, sampling_rate_hz=fs, N=1e-3, B=b, K=k)
        assert characterise_noise(x, fs, unit="rad/s")["metrics"]["hump_tau_s"] == [None] * 3, seed
