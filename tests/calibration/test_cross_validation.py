"""The cross-validated error: what a calibration does on orientations it was not fitted on."""

from __future__ import annotations

import numpy as np
import pytest

from app.workflows.still import Reading, calibrate_known, calibrate_unknown
from simulations.free_poses import free_pose_session, fresh_error_mg
from simulations.triangular import draw_parameters, random_unit_vectors, uncalibrate
from tests.conftest import seed_table


def test_triangular_cv_error_on_seed_table_2_exceeds_the_in_sample_error():
    # Farago et al. Table 2-like readings: 20 positions; leave-one-out refits 20 times.
    result, _ = calibrate_unknown("triangular", seed_table(2)[:20], unit="m/s^2", gravity=9.806)
    assert result.metrics["cv_scheme"] == "leave-one-out"
    assert result.metrics["cv_error_mg"] > result.metrics["error_after_mg"]  # in-sample flatters
    assert result.metrics["cv_error_max_mg"] >= result.metrics["cv_error_mg"]
    # Reading 0 calibrated by the fit on the other 19, by hand.
    from app.calibration.still.triangular import fit_triangular

    m = seed_table(2)[:20]
    errors = [
        abs(np.linalg.norm(fit_triangular(np.delete(m, i, 0), gravity=9.806).apply(m[i])) - 9.806) / 9.806
        for i in range(20)
    ]
    assert abs(result.metrics["cv_error_mg"] - 1000 * np.mean(errors)) < 1e-9


def test_nine_positions_have_no_figure_and_say_how_to_get_one():
    result, _ = calibrate_unknown("triangular", seed_table(2)[:9], unit="m/s^2", gravity=9.806)
    assert result.metrics["cv_error_mg"] is None and "add poses" in result.metrics["cv_note"]


def test_six_position_has_no_redundancy():
    g = 9.81
    readings = [
        Reading(mean=tuple(v), up=u)
        for u, v in (
            ("+x", (g, 0, 0)),
            ("-x", (-g, 0, 0)),
            ("+y", (0, g, 0)),
            ("-y", (0, -g, 0)),
            ("+z", (0, 0, g)),
            ("-z", (0, 0, -g)),
        )
    ]
    result, _ = calibrate_known("six_position", readings, unit="m/s^2", gravity=g)
    assert result.metrics["cv_error_mg"] is None and "add poses" in result.metrics["cv_note"]


def _session(rng, n, noise_g):
    p = draw_parameters(rng)
    return p, uncalibrate(p, random_unit_vectors(rng, n)) + rng.normal(scale=noise_g, size=(n, 3))


def _fresh_error_mg(result, p, rng, noise_g=0.0) -> float:
    truth = uncalibrate(p, random_unit_vectors(rng, 1000))
    return 1000 * float(np.mean(np.abs(np.linalg.norm(result.apply(truth), axis=1) - 1.0)))


@pytest.mark.parametrize("n, scheme", [(20, "leave-one-out"), (120, "10-fold")])
def test_cv_error_tracks_the_error_on_fresh_poses(n, scheme):
    # Over 20 simulated sessions (Farago et al. eqs. (17)–(19), 3 mg noise), the cross-validated
    # error is within 30 % of the mean error on 1000 fresh noise-free poses, where the in-sample
    # error is not.
    rng = np.random.default_rng(11)
    cv, fresh, inside = [], [], []
    for _ in range(20):
        p, means = _session(rng, n, 0.003)
        result, _ = calibrate_unknown("triangular", means, unit="g", gravity=1.0)
        assert result.metrics["cv_scheme"] == scheme
        # The readings' own noise is in every cv figure: compare with fresh poses read with that noise.
        cv.append(result.metrics["cv_error_mg"])
        fresh.append(_fresh_error_mg(result, p, rng))
        inside.append(result.metrics["error_after_mg"])
    noise_floor = (
        np.mean(np.abs(np.linalg.norm(rng.normal(scale=0.003, size=(20000, 3)) + [0, 0, 1], axis=1) - 1)) * 1000
    )
    expected = np.hypot(np.mean(fresh), noise_floor)
    assert abs(np.mean(cv) / expected - 1) < 0.3, (np.mean(cv), expected, np.mean(inside))


@pytest.mark.parametrize("n", [12, 20, 30])
def test_cv_error_is_what_a_person_gets_on_fresh_poses_with_tremor_and_unit_errors(n):
    # Free-pose sessions of a phone with Farago et al.'s unit errors (scales 10 %, misalignments 5 %,
    # offsets 0.1 g) and hand tremor (a third of the poses off by 3 mg): the cross-validated error,
    # averaged over 30 sessions, is within 30 % of the error on 1000 fresh poses read the same way.
    rng = np.random.default_rng(20 + n)
    cv, fresh = [], []
    for _ in range(30):
        p, means = free_pose_session(rng, n)
        result, _ = calibrate_unknown("triangular", means, unit="g", gravity=1.0)
        cv.append(result.metrics["cv_error_mg"])
        fresh.append(fresh_error_mg(rng, p, result.apply)[0])
    assert abs(np.mean(cv) / np.mean(fresh) - 1) < 0.3, (np.mean(cv), np.mean(fresh))
