"""The trust gates (app.calibration.still.trust): every one fires on the session it is for, and a good
session passes."""

from __future__ import annotations

import numpy as np

from app.calibration.still.trust import HALF_WIDTH_LIMITS
from app.workflows.still import Reading, calibrate_known, calibrate_unknown
from simulations.triangular import draw_parameters, random_unit_vectors, uncalibrate

G = 9.80665
AXES = {"+x": (1, 0, 0), "-x": (-1, 0, 0), "+y": (0, 1, 0), "-y": (0, -1, 0), "+z": (0, 0, 1), "-z": (0, 0, -1)}


def tilted(v, degrees, rng):
    """v turned by `degrees` about a random axis perpendicular to it."""
    v = np.asarray(v, dtype=float)
    a = rng.normal(size=3)
    a -= a.dot(v) * v / v.dot(v)
    a /= np.linalg.norm(a)
    t = np.radians(degrees)
    return v * np.cos(t) + np.cross(a, v) * np.sin(t)


def labelled(vectors_by_label, gravity=G):
    return [Reading(mean=tuple(gravity * np.asarray(v)), up=u) for u, v in vectors_by_label]


def magnitude(means, unit="g", gravity=1.0):
    result, _ = calibrate_unknown("triangular", means, unit=unit, gravity=gravity)
    return result


def test_a_good_session_passes_and_the_cv_error_is_its_headline():
    rng = np.random.default_rng(3)
    p = draw_parameters(rng)
    means = uncalibrate(p, random_unit_vectors(rng, 24)) + rng.normal(scale=0.0005, size=(24, 3))
    result = magnitude(means)
    assert result.ok, result.reasons
    m = result.metrics
    assert m["cv_error_mg"] < m["error_before_mg"] / 5 and m["error_after_mg"] < m["cv_error_mg"]


def test_six_poses_tilted_3_degrees_fail_on_the_growth_of_the_norm_error():
    # The case: an ideal sensor, six poses each 3° off their axis. Raw norms are exact (0.06 %
    # of g of noise in the issue's; none here); six_position puts the tilts into X and the norms grow.
    rng = np.random.default_rng(1)
    readings = labelled((u, tilted(v, 3.0, rng)) for u, v in AXES.items())
    result, _ = calibrate_known("six_position", readings, unit="m/s^2", gravity=G)
    assert not result.ok
    assert result.metrics["norm_error_max_raw"] < 1e-12 and result.metrics["norm_error_max"] > 0.01
    assert "not on the axes their labels say" in result.reasons[0] and "magnitude model" in result.reasons[0]
    # The same six poses on their axes pass.
    exact, _ = calibrate_known("six_position", labelled(AXES.items()), unit="m/s^2", gravity=G)
    assert exact.ok, exact.reasons


def test_non_axis_aligned_orientations_are_refused():
    # 12 poses within 20° of an axis (so they get labels) but 6–10° off it: a person's phone on its
    # rounded edges. The sensor is ideal: any change is harm.
    rng = np.random.default_rng(5)
    poses = [(u, tilted(v, rng.uniform(6, 10), rng)) for u, v in list(AXES.items()) * 2]
    result, _ = calibrate_known("orientations", labelled(poses), unit="m/s^2", gravity=G)
    assert not result.ok
    m = result.metrics
    assert m["error_after_mg"] > m["error_before_mg"] and m["cv_error_mg"] > m["error_before_mg"]
    assert any("not on the axes their labels say" in r for r in result.reasons)
    assert any("would make new orientations worse" in r for r in result.reasons)


def test_a_calibration_worse_than_none_on_new_poses_fails():
    # An ideal sensor read with 2 mg of noise in 12 poses: the fit follows the noise, so that poses
    # left out come out worse than raw.
    rng = np.random.default_rng(1)
    means = random_unit_vectors(rng, 12) + rng.normal(scale=0.002, size=(12, 3))
    result = magnitude(means)
    m = result.metrics
    assert m["error_after_mg"] < m["error_before_mg"] < m["cv_error_mg"]  # in-sample would say "better"
    assert not result.ok
    assert any("would make new orientations worse" in r and "keep the sensor as it is" in r for r in result.reasons)


def test_nine_poses_fit_exactly_fail_and_have_no_ratio():
    rng = np.random.default_rng(2)
    means = uncalibrate(draw_parameters(rng), random_unit_vectors(rng, 9))
    result = magnitude(means)
    assert not result.ok
    m = result.metrics
    assert m["dof"] == 0 and m["improvement"] is None and m["error_after_mg"] < 1e-6
    assert any("no residual degrees of freedom" in r for r in result.reasons)


def test_an_undetermined_parameter_is_named_with_the_pose_that_determines_it():
    # 14 poses within 10° of the xz plane: k_yy is not determined.
    rng = np.random.default_rng(1)
    theta, elevation = rng.uniform(0, 2 * np.pi, 14), np.radians(rng.uniform(-10, 10, 14))
    up = np.c_[np.cos(theta) * np.cos(elevation), np.sin(elevation), np.sin(theta) * np.cos(elevation)]
    result = magnitude(uncalibrate(draw_parameters(rng), up) + rng.normal(scale=0.001, size=(14, 3)))
    assert not result.ok
    reason = next(r for r in result.reasons if r.startswith("not determined by these poses"))
    assert "k_yy ±" in reason and "add poses with +y up and −y up" in reason
    hw = float(reason.split("k_yy ± ")[1].split(",")[0].split(";")[0])
    assert hw > HALF_WIDTH_LIMITS["scale"]


def test_raw_units_skip_the_comparisons_with_the_raw_norm():
    # Counts are not comparable with g: only the fit's own gates speak.
    rng = np.random.default_rng(4)
    counts = 4096 * (
        uncalibrate(draw_parameters(rng), random_unit_vectors(rng, 20)) + rng.normal(scale=5e-4, size=(20, 3))
    )
    result, _ = calibrate_unknown("triangular", counts, unit="raw", gravity=G)
    assert not any("without it" in r or "norms of its own readings" in r for r in result.reasons)
