"""The result decides: every result type answers ``figure()``, ``apply(samples, sensor)`` and ``corrects`` from its
own fields, and its headline (app/headlines.py, by its class) is told from them, each figure recomputed here from
the readings or the metrics it stands on."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from app.calibration import CalibrationError, fit_six_position, registry
from app.calibration.autocal import AutoCalibration
from app.calibration.cube.calibrate import calibrate_cube
from app.calibration.magnetometer.fit import fit_magnetometer
from app.calibration.noise.characterise import NoiseResult
from app.calibration.shared.result import CORRECTION, DRIFT, FIGURES, NO_FIGURE, CalibrationResult, Figure
from app.calibration.still.nonorthogonal import fit_nonorthogonal
from app.calibration.still.triangular import fit_triangular
from app.calibration.still.trust import review
from app.calibration.temperature import calibrate_temperature
from app.headlines import headline, verdict_note
from simulations import cube as cube_sim
from simulations.magnetometer import simulate_session
from simulations.temperature import simulate_warm_up
from tests.conftest import seed_table

G = 9.806
SIX = {
    "+x": [G + 0.1, 0.05, -0.02],
    "-x": [-G + 0.12, 0.03, 0.01],
    "+y": [0.02, G - 0.05, 0.1],
    "-y": [0.01, -G - 0.02, 0.08],
    "+z": [0.05, 0.02, G + 0.2],
    "-z": [0.04, 0.01, -G + 0.15],
}


def _raw_mg(means, g) -> float:
    return 1000.0 * float(np.mean(np.abs(np.linalg.norm(means, axis=1) - g) / g))


@pytest.fixture(scope="module")
def triangular():
    return fit_triangular(seed_table(2)[:20], gravity=G)


@pytest.fixture(scope="module")
def cube():
    s = cube_sim.simulate_session(np.random.default_rng(21), sampling_rate_hz=100.0)
    return calibrate_cube(s.acc, s.gyr, None, sampling_rate_hz=100.0, protocol="cube24", gravity=9.80665)


@pytest.fixture(scope="module")
def compass():
    m, _, _ = simulate_session(21, n=300, hard_iron_ut=80.0)
    return fit_magnetometer(m, field_ut=48.0), m


# -- still readings: holdout, then cross-validated, then in-sample -------------------------------------


def test_a_still_readings_fit_stands_on_held_out_readings_then_new_orientations_then_the_poses_fitted(triangular):
    metrics = {
        "holdout_error_before_mg": 41.5,
        "holdout_error_after_mg": 1.25,
        "cv_error_mg": 2.5,
        "cv_error_max_mg": 6.0,
        "cv_scheme": "leave one out",
        "error_before_mg": 40.0,
        "error_after_mg": 0.75,
        "count": 20,
    }
    r = dataclasses.replace(triangular, metrics=metrics)
    assert r.figure() == Figure(41.5, 1.25, "mg", "error on the readings you held out")
    r = dataclasses.replace(triangular, metrics={k: v for k, v in metrics.items() if not k.startswith("holdout")})
    assert r.figure() == Figure(40.0, 2.5, "mg", "error on new orientations")
    assert headline(r) == (
        "on new orientations expect 2.50 mg of g, a level off by 0.14° at most (up to 6.00 mg; leave one out); "
        "on the poses fitted (in-sample) 0.75 mg, raw 40.00 mg"
    )
    r = dataclasses.replace(triangular, metrics={**r.metrics, "cv_error_mg": None, "cv_note": "too few poses"})
    assert r.figure() == Figure(40.0, 0.75, "mg", "error on the 20 poses fitted")
    assert headline(r) == "too few poses; on the poses fitted (in-sample) 0.75 mg, raw 40.00 mg"
    assert dataclasses.replace(triangular, metrics={}).figure() == NO_FIGURE
    assert headline(dataclasses.replace(triangular, metrics={})) is None  # no cross-validated figure asked for


def test_a_stored_body_rebuilds_with_its_metrics_as_stored_so_the_request_s_holdout_decides(triangular):
    body = triangular.to_dict()
    holdout = triangular.evaluate(seed_table(2)[20:])
    body["metrics"].update({f"holdout_{k}": v for k, v in holdout.items()})  # as workflow.holdout_metrics adds them
    legacy = {k: v for k, v in body.items() if k != "schema_version"}  # stored before the version field
    for stored in (body, legacy):
        again = CalibrationResult.from_dict(stored)
        assert again.metrics == body["metrics"]
        assert again.figure() == Figure(
            holdout["error_before_mg"], holdout["error_after_mg"], "mg", "error on the readings you held out"
        )
    rest = seed_table(2)[20:]
    assert holdout["error_after_mg"] == pytest.approx(_raw_mg(triangular.apply(rest), G), rel=1e-12)


def test_the_figure_of_a_fit_is_its_own_metrics_recomputed_from_the_readings(triangular):
    means = seed_table(2)[:20]
    f = triangular.figure()  # the fit alone reports its in-sample error
    assert f.unit == "mg" and f.basis == "error on the 20 poses fitted"
    assert f.before == pytest.approx(_raw_mg(means, G), rel=1e-12)
    assert f.after == pytest.approx(_raw_mg(triangular.apply(means), G), rel=1e-12)
    assert triangular.corrects and triangular.KIND == CORRECTION


def test_six_poses_are_in_sample_and_say_how_to_measure_new_orientations():
    r = review(
        fit_six_position(list(SIX.values()), list(SIX), gravity=G),
        {"cv_error_mg": None, "cv_error_max_mg": None, "cv_note": "six poses leave none out"},
    )
    f = r.figure()
    means = np.array(list(SIX.values()))
    assert f.basis == "error on the 6 poses fitted" and f.before == pytest.approx(_raw_mg(means, G), rel=1e-12)
    assert f.after == pytest.approx(_raw_mg(r.apply(means), G), rel=1e-9)
    assert headline(r) == (
        f"six poses leave none out; on the poses fitted (in-sample) {f.after:.2f} mg, raw {f.before:.2f} mg"
    )
    assert verdict_note(type(r), "six_position", f).startswith("Six poses leave none out to test on")
    assert verdict_note(type(r), "orientations", f) == ""


@pytest.mark.parametrize(
    "fit",
    [
        lambda: fit_six_position(list(SIX.values()), list(SIX), gravity=G),
        lambda: fit_nonorthogonal(seed_table(1)[:20], gravity=G),
        lambda: fit_triangular(seed_table(2)[:20], gravity=G),
    ],
    ids=["affine", "nonorthogonal", "triangular"],
)
def test_apply_is_the_accelerometer_s_correction_and_refuses_another_sensor(fit):
    r = fit()
    raw = np.random.default_rng(5).normal(scale=G, size=(30, 3))
    c = r.corrections()["acc"]
    np.testing.assert_allclose(r.apply(raw, "acc"), (raw - c.o) @ c.M.T, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(r.apply(raw), r.apply(raw, "acc"))
    assert r.apply(raw[0]).shape == (3,)
    with pytest.raises(
        CalibrationError, match=f"a {r.MODEL_TYPE} calibration has only an accelerometer model; drop `sensor`"
    ):
        r.apply(raw, "gyr")


# -- autocal: its control points ----------------------------------------------------------------------


def test_autocal_stands_on_its_control_points_and_says_so_in_its_headline(triangular):
    metrics = {
        "count": 20,
        "count_control": 9,
        "error_before_mg": 30.0,
        "error_after_mg": 1.5,
        "cv_error_mg": 2.0,
        "cv_error_max_mg": 4.0,
        "cv_scheme": "leave one out",
    }
    r = AutoCalibration(
        calibration=triangular,
        gravity=G,
        points=triangular.means,
        control=np.empty((0, 3)),
        point_starts=np.arange(20),
        control_starts=np.empty(0, dtype=np.int64),
        selection={},
        control_selection={},
        detection={},
        comparison={},
        solver="lm",
        metrics=metrics,
        unit="m/s^2",
    )
    assert r.figure() == Figure(30.0, 1.5, "mg", "error on control points held out of the fit")
    assert headline(r) == (
        "on new orientations expect 2.00 mg of g, a level off by 0.11° at most (up to 4.00 mg; leave one out); "
        "on the control points (held out) 1.50 mg, raw 30.00 mg"
    )
    no_control = dataclasses.replace(r, metrics={**metrics, "error_after_mg": None})
    assert no_control.figure() == Figure(30.0, 2.0, "mg", "error on new orientations")
    raw = np.random.default_rng(6).normal(scale=G, size=(10, 3))
    np.testing.assert_allclose(r.apply(raw), triangular.apply(raw), rtol=1e-15)
    with pytest.raises(CalibrationError, match="a triangular calibration has only an accelerometer model"):
        r.apply(raw, "mag")


# -- the compass ----------------------------------------------------------------------------------------


def test_the_compass_stands_on_the_field_strength_on_new_directions_in_microtesla(compass):
    r, m = compass
    f = r.figure()
    assert f == Figure(
        r.metrics["raw_error_ut"], r.metrics["cv_error_ut"], "µT", "error of the field strength on new directions"
    )
    h = r.M @ (m - r.b).T
    rms = float(np.sqrt(np.mean((np.linalg.norm(h, axis=0) - 48.0) ** 2)))
    assert r.metrics["fit_error_ut"] == pytest.approx(rms, rel=1e-9)  # the in-sample figure, recomputed
    assert headline(r).startswith(f"on new directions expect {r.metrics['cv_error_ut']:.2f} µT of the 48.0 µT field")
    fitted = dataclasses.replace(r, metrics={**r.metrics, "cv_error_ut": None})
    assert fitted.figure() == Figure(
        r.metrics["raw_error_ut"], r.metrics["fit_error_ut"], "µT", "error of the field strength on the readings fitted"
    )
    assert type(r).figures_from(r.metrics, "raw")[0].unit == "counts"  # a magnetometer left in counts


def test_the_compass_applies_its_magnetometer_correction_only(compass):
    r, m = compass
    np.testing.assert_allclose(r.apply(m[:7], "mag"), (m[:7] - r.b) @ r.M.T, rtol=1e-15)
    np.testing.assert_array_equal(r.apply(m[:7]), r.apply(m[:7], "mag"))
    with pytest.raises(
        CalibrationError, match='a magnetometer calibration has only a magnetometer model: send `sensor: "mag"`'
    ):
        r.apply(m[:7], "acc")


# -- the cube: its positions ----------------------------------------------------------------------------


def test_the_cube_stands_on_its_accelerometer_positions_recomputed_with_s_inverse(cube):
    means, S, b = cube.acc.means, cube.acc.S, cube.acc.b
    calibrated = np.linalg.solve(S, (means - b).T).T
    f = cube.figure()
    assert f.basis == f"accelerometer error on the {len(means)} positions fitted" and f.unit == "mg"
    assert f.before == pytest.approx(_raw_mg(means, 9.80665), rel=1e-12)
    assert f.after == pytest.approx(_raw_mg(calibrated, 9.80665), rel=1e-12)
    assert headline(cube) is None and cube.PER_SENSOR
    again = CalibrationResult.from_dict(cube.to_dict())
    assert again.figure() == f


def test_the_cube_applies_each_sensor_s_correction_and_refuses_one_it_has_not(cube):
    raw = np.random.default_rng(7).normal(size=(12, 3))
    for sensor, c in cube.corrections().items():
        np.testing.assert_allclose(cube.apply(raw, sensor), (raw - c.o) @ c.M.T, rtol=1e-10, atol=1e-12)
    np.testing.assert_array_equal(cube.apply(raw), cube.apply(acc=raw)["acc"])
    assert cube.mag is None
    with pytest.raises(CalibrationError, match="this calibration has no mag model"):
        cube.apply(raw, "mag")


# -- noise and temperature --------------------------------------------------------------------------------


def test_a_noise_characterisation_corrects_nothing_and_has_no_figure():
    r = NoiseResult(
        sensors={"gyr": {"model": {"unit": "rad/s"}, "adev": {}, "uncertainty": {}, "metrics": {}}},
        sampling_rate_hz=200.0,
        duration_s=600.0,
    )
    assert not r.corrects and r.KIND == FIGURES
    assert r.figure() == NO_FIGURE and r.figures() == (NO_FIGURE,) and headline(r) is None
    with pytest.raises(CalibrationError, match="corrects nothing"):
        r.apply(np.zeros((2, 3)), "gyr")


def test_a_temperature_calibration_stands_on_each_sensor_s_drift_on_bands_left_out():
    w = simulate_warm_up(np.random.default_rng(3), duration_s=1800)
    r = calibrate_temperature(w.temperature_c, acc=w.acc, gyr=w.gyr, sampling_rate_hz=50.0, time_s=w.time_s)
    assert r.corrects and r.KIND == DRIFT
    acc, gyr = r.figures()
    basis = "offset drift over the temperature range, on bands of temperature left out"
    assert acc == Figure(r.metrics["acc"]["drift_raw_max"], r.metrics["acc"]["drift_cv_max"], "mg", basis)
    assert gyr == Figure(r.metrics["gyr"]["drift_raw_max"], r.metrics["gyr"]["drift_cv_max"], "°/s", basis)
    assert r.figure() == acc
    lo = min(r.model_dict()[s]["t_min_c"] for s in ("acc", "gyr"))
    assert headline(r).startswith(f"offset drift over {lo:.0f}–") and "accelerometer " in headline(r)
    with pytest.raises(CalibrationError, match="needs each sample's temperature"):
        r.apply(w.acc[:3], "acc")


def test_a_body_cut_short_is_still_told_apart_by_its_class():
    assert registry.class_of({"method": "noise"}).KIND == FIGURES
    assert registry.class_of({"method": "six_position", "model": {"type": "affine"}}).KIND == CORRECTION
    metrics = {"cv_error_mg": 3.0, "error_before_mg": 2.0, "error_after_mg": 1.0}
    f = registry.class_of({"method": "triangular"}).figures_from(metrics, None)[0]
    assert f == Figure(2.0, 3.0, "mg", "error on new orientations") and f.grew
