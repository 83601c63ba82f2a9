"""A figure in degrees (app.calibration.shared.angles): the worst angle a vector error of size e turns a vector of
size r by is asin(e/r), checked here against a brute-force search over the error's direction; a heading's r
is the horizontal component H = F cos I, checked against IGRF-14's own H (app.geomag)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.calibration.shared.angles import (
    ASSUMED_INCLINATION_DEG,
    compass_inclination,
    degrees_text,
    figure_degrees,
    heading_error_deg,
    horizontal_field,
    tilt_error_deg,
    worst_angle_deg,
)
from app.geomag import reference_field


def _worst_by_search(e: float, r: float) -> float:
    """The largest angle between r·z and r·z + e·u over unit vectors u, searched on a grid of u's polar angle
    and refined around the best (the angle does not depend on u's azimuth)."""
    lo, hi = 0.0, math.pi
    for _ in range(6):
        polar = np.linspace(lo, hi, 2001)
        v = np.stack([e * np.sin(polar), np.zeros_like(polar), r + e * np.cos(polar)], axis=1)
        angles = np.degrees(np.arccos(v[:, 2] / np.linalg.norm(v, axis=1)))
        k = int(np.argmax(angles))
        step = polar[1] - polar[0]
        lo, hi = max(0.0, polar[k] - step), min(math.pi, polar[k] + step)
    return float(angles[k])


@pytest.mark.parametrize("e", [0.48, 1.2, 32.1, 74.0, 500.0, 999.0])
def test_the_worst_tilt_of_an_error_is_asin_of_e_over_g(e):
    assert tilt_error_deg(e) == pytest.approx(_worst_by_search(e, 1000.0), abs=1e-9)
    assert tilt_error_deg(e) == pytest.approx(math.degrees(math.asin(e / 1000.0)), rel=1e-15)


def test_the_issue_s_figures_in_degrees():
    # "Apply it: 32.1 mg → 0.48 mg (a level off by 1.8° → 0.03°)"
    assert tilt_error_deg(32.1) == pytest.approx(1.83951052, abs=1e-8)
    assert tilt_error_deg(0.48) == pytest.approx(0.02750197, abs=1e-8)
    d = figure_degrees(32.1, 0.48, "mg", {})
    assert d["words"] == "a level off by 1.8° → 0.03°" and d["kind"] == "tilt" and d["inclination_deg"] is None


def test_an_error_as_large_as_the_vector_can_turn_it_all_the_way_to_ninety_degrees():
    assert worst_angle_deg(1000.0, 1000.0) == 90.0 and worst_angle_deg(2500.0, 1000.0) == 90.0
    assert worst_angle_deg(0.0, 1000.0) == 0.0
    with pytest.raises(ValueError):
        worst_angle_deg(1.0, 0.0)


def test_a_heading_error_is_told_against_the_horizontal_component_at_the_place_s_inclination():
    earth = reference_field("2024-06-01", 48.14, 11.58)  # Munich: about 48.5 µT, dipping 64°
    h = horizontal_field(earth.field_ut, earth.inclination_deg)
    assert h == pytest.approx(earth.horizontal_ut, rel=1e-12)
    # The worst heading error: an error of size e in the horizontal plane across H, found by search.
    for e in (0.5, 2.0, 10.0):
        assert heading_error_deg(e, earth.field_ut, earth.inclination_deg) == pytest.approx(
            _worst_by_search(e, h), abs=1e-9
        )
    # A compass error in 3D turns the heading (the horizontal components' angle) by at most asin(e/H).
    rng = np.random.default_rng(3)
    u = rng.normal(size=(200000, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    field = np.array([earth.north_ut, earth.east_ut, earth.down_ut])
    e = 2.0
    turned = field + e * u
    heading = np.degrees(np.abs(np.arctan2(turned[:, 1], turned[:, 0]) - math.atan2(field[1], field[0])))
    worst = heading_error_deg(e, earth.field_ut, earth.inclination_deg)
    assert heading.max() <= worst + 1e-9 and heading.max() > worst - 0.01


def test_the_inclination_comes_from_the_place_else_the_turn_else_an_assumption_said_in_words():
    assert compass_inclination({"inclination_deg": 64.2, "measured_inclination_deg": 61.0}) == (64.2, "model")
    assert compass_inclination({"inclination_deg": None, "measured_inclination_deg": 61.0}) == (61.0, "measured")
    assert compass_inclination({}) == (ASSUMED_INCLINATION_DEG, "assumed")
    d = figure_degrees(5.0, 0.5, "µT", {"field_ut": 48.0, "inclination_deg": -64.0})
    assert d["after_deg"] == pytest.approx(
        math.degrees(math.asin(0.5 / (48.0 * math.cos(math.radians(64))))), rel=1e-14
    )
    assert d["words"] == "a heading off by 14° → 1.4° (the field dips 64° at your place)"
    assumed = figure_degrees(5.0, 0.5, "counts", {"field_ut": 300.0})
    assert assumed["inclination_source"] == "assumed" and "assuming the field dips 60°" in assumed["words"]
    assert figure_degrees(4.0, 1.0, "°", {"field_ut": 48.0}) is None  # a flight compass speaks degrees already
    assert figure_degrees(4.0, 1.0, "°/s", {}) is None


def test_an_angle_is_told_with_about_two_digits():
    assert [degrees_text(v) for v in (12.4, 1.84, 0.0275, 0.004)] == ["12°", "1.8°", "0.03°", "<0.01°"]
