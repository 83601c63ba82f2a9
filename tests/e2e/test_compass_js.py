"""The compass page's bookkeeping (static/js/compass_flow.js), run as the page runs it: imported by
real Chromium from the real server, checked against app/calibration/magnetometer/coverage.py."""

from __future__ import annotations

import json

import numpy as np
import pytest

from app.calibration.magnetometer.coverage import FACE_NAMES, coverage, face_of
from simulations.magnetometer import directions

MODULE = "/static/js/compass_flow.js"
B = np.array([23.5, -41.2, 12.8])
F = 48.0


@pytest.fixture
def js(page, server):
    page.goto(server.url + "/wizard?protocol=compass")

    def run(body: str):
        return page.evaluate(f"async () => {{ const m = await import('{MODULE}'); {body} }}")

    return run


def feed(readings) -> str:
    return f"const c = new m.CompassCoverage(); for (const r of {json.dumps(np.asarray(readings).tolist())}) c.push(r);"


def test_the_faces_are_coverage_py_s(js):
    v = directions(np.random.default_rng(3), 500)
    assert js(f"return {json.dumps(v.tolist())}.map((d) => m.faceOf(d))") == face_of(v).tolist()


def test_a_hemisphere_keeps_the_running_centre_on_the_offset(js):
    # Half the sphere (the field within 90° of +z): the mid-point of each axis's extremes is half a
    # radius off on z, and the readings near the rim would then seem to fill the missing half.
    rng = np.random.default_rng(4)
    m = F * directions(rng, 300, max_polar_deg=90.0) + B + rng.normal(0.0, 0.3, (300, 3))
    midpoint = (m.min(axis=0) + m.max(axis=0)) / 2
    assert midpoint[2] - B[2] == pytest.approx(F / 2, abs=1.0)
    st = js(feed(m) + "return c.status();")
    np.testing.assert_allclose(st["centre"], B, atol=0.3)  # the sphere fit (Kåsa)
    assert st["radius"] == pytest.approx(F, abs=0.3)
    share, missing = coverage(m - B)
    assert st["coverage"] == pytest.approx(share) and [FACE_NAMES[k] for k in st["missing"]] == missing
    assert 0.4 <= share <= 0.7 and st["count"] == 300


def test_no_faces_before_the_phone_has_turned_and_repeats_are_dropped(js):
    rng = np.random.default_rng(5)
    m = F * directions(rng, 40, max_polar_deg=15.0) + B  # a 30° cap: the centre is not fixed yet
    st = js(feed(m) + "return c.status();")
    assert st["centre"] is None and st["coverage"] == 0 and len(st["missing"]) == 20
    assert js(
        "const c = new m.CompassCoverage(); "
        "return [c.push([1, 2, 3]), c.push([1, 2, 3]), c.push([1, 2, NaN]), c.count];"
    ) == [True, False, False, 1]
