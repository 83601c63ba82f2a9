"""The icosahedron faces behind a compass recording's coverage (app.calibration.magnetometer.coverage)."""

import numpy as np
import pytest

from app.calibration.magnetometer.coverage import (
    FACE_CENTRES,
    FACE_NAMES,
    ICOSAHEDRON_FACES,
    ICOSAHEDRON_VERTICES,
    coverage,
    face_counts,
    face_of,
)


def test_a_regular_icosahedron_of_twenty_equal_faces():
    assert ICOSAHEDRON_VERTICES.shape == (12, 3) and ICOSAHEDRON_FACES.shape == (20, 3)
    np.testing.assert_allclose(np.linalg.norm(ICOSAHEDRON_VERTICES, axis=1), 1.0, atol=1e-12)
    # every face centre is the same angle from its vertices: 37.38° (circumradius of the face)
    angles = [np.degrees(np.arccos(ICOSAHEDRON_VERTICES[f] @ c)) for f, c in zip(ICOSAHEDRON_FACES, FACE_CENTRES)]
    np.testing.assert_allclose(angles, 37.377, atol=1e-3)
    # neighbouring centres are 41.81° apart: the size of a face as the page draws it
    dots = FACE_CENTRES @ FACE_CENTRES.T
    nearest = np.degrees(np.arccos(np.sort(dots, axis=1)[:, -2]))
    np.testing.assert_allclose(nearest, 41.810, atol=1e-3)


def test_names_are_unique_and_say_the_direction():
    assert len(set(FACE_NAMES)) == 20
    assert sum(len(n) == 6 for n in FACE_NAMES) == 8 and sum(len(n) == 4 for n in FACE_NAMES) == 12
    for name, centre in zip(FACE_NAMES, FACE_CENTRES):
        first = "xyz".index(name[1])
        assert np.sign(centre[first]) == (1 if name[0] == "+" else -1)
        assert abs(centre[first]) >= 0.57  # the first-named axis is the one it leans on most


def test_each_face_centre_falls_in_its_own_face():
    np.testing.assert_array_equal(face_of(FACE_CENTRES), np.arange(20))
    np.testing.assert_array_equal(face_of(3.7 * FACE_CENTRES), np.arange(20))  # length does not matter


def test_a_full_sphere_covers_all_and_a_hemisphere_half():
    rng = np.random.default_rng(7)
    v = rng.normal(size=(4000, 3))
    assert coverage(v) == (1.0, [])
    share, missing = coverage(v[v[:, 2] > 0.0])
    # the 8 faces whose centre lies below the equator are missed; the 4 centred on it are half covered
    assert share == pytest.approx(0.6) and len(missing) == 8 and all("-z" in n for n in missing)
    assert face_counts(v).sum() == 4000


def test_min_samples_per_face():
    v = np.repeat(FACE_CENTRES[:5], [1, 2, 3, 4, 5], axis=0)
    assert coverage(v)[0] == pytest.approx(5 / 20)
    assert coverage(v, min_samples=3)[0] == pytest.approx(3 / 20)
