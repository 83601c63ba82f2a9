"""The verdict a person reads first (app.verdict), over the API: a good, a useless and a harmful
calibration in words, each figure recomputed here from the readings.

- good: Georgieva et al.'s (ESGI'95) Table 1 phone, 27 real poses: apply it, 74.0 mg → 1.20 mg on new
  orientations (the leave-one-out error, refitted here without each pose);
- useless: the same phone's poses once calibrated by that calibration, calibrated again: a second fit
  only follows the noise, and new orientations come out (a little) worse: "don't apply it: your
  sensor is already better than this";
- harmful: an ideal sensor read in 12 poses with 2 mg of noise (seeded): the fit follows the noise and
  poses left out come out worse than raw, although in-sample it looks better;
- too small to matter: a sensor off by a fraction of a mg (seeded): "no need to apply it";
- failed: the real MPU-6050's ten poses, which fail their checks (tests/api/test_real_recordings.py).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from app.calibration.still.triangular import fit_triangular
from app.geomag import reference_field
from app.verdict import verdict
from simulations.magnetometer import simulate_session
from simulations.triangular import random_unit_vectors
from tests.api.test_real_recordings import leave_one_out_mg
from tests.real_recordings import by_name

RECS = by_name()


def _post(client, means, unit="g", gravity=None, method="triangular") -> dict:
    body = {"method": method, "unit": unit, "means": np.asarray(means).tolist()}
    if gravity is not None:
        body["gravity"] = gravity
    r = client.post("/api/v1/calibrations", json=body)
    assert r.status_code == 201, r.text
    return r.json()


def _raw_error_mg(means, gravity) -> float:
    return 1000.0 * float(np.mean(np.abs(np.linalg.norm(means, axis=1) / gravity - 1.0)))


def _figures(words: str) -> tuple[float, float]:
    before, after = re.search(r"([\d.]+)\u00a0(?:mg|µT) → ([\d.]+)\u00a0(?:mg|µT)", words).groups()
    return float(before), float(after)


def test_a_good_calibration_says_apply_it_with_the_error_on_new_orientations(client):
    rec = RECS["georgieva-table1"]
    body = _post(client, rec.means, unit=rec.unit, gravity=rec.gravity)
    v = body["verdict"]
    assert body["ok"] and v["apply"] is True and v["kind"] == "apply"
    # no-break spaces; the figure as a level's tilt, asin(e/g) (app.calibration.shared.angles)
    assert (
        v["words"] == "Apply it: error on new orientations 74.0\u00a0mg → 1.20\u00a0mg (a level off by 4.2° → 0.07°)."
    )
    raw = _raw_error_mg(rec.means, rec.gravity)
    cv, _ = leave_one_out_mg(lambda keep: fit_triangular(rec.means[keep], gravity=rec.gravity), rec.means, rec.gravity)
    assert v["before"] == pytest.approx(raw, rel=1e-9) and v["after"] == pytest.approx(cv, rel=1e-6)
    assert _figures(v["words"]) == (round(raw, 1), round(cv, 2))
    assert v["unit"] == "mg" and v["basis"] == "error on new orientations"
    # The tilt a level reads with that error, at worst: asin(e/g) (app.calibration.shared.angles, docs/methods.md).
    d = v["degrees"]
    assert d["kind"] == "tilt" and d["before_deg"] == pytest.approx(np.degrees(np.arcsin(raw / 1000)), rel=1e-9)
    assert d["after_deg"] == pytest.approx(np.degrees(np.arcsin(cv / 1000)), rel=1e-6)
    assert client.get(f"/api/v1/calibrations/{body['id']}").json()["verdict"] == v


def test_a_calibration_of_an_already_calibrated_sensor_says_the_sensor_is_already_better(client):
    rec = RECS["georgieva-table1"]
    first = _post(client, rec.means, unit=rec.unit, gravity=rec.gravity)
    r = client.post(f"/api/v1/calibrations/{first['id']}/apply", json={"samples": np.asarray(rec.means).tolist()})
    assert r.status_code == 200, r.text
    calibrated = np.array(r.json()["samples"])
    body = _post(client, calibrated, unit=rec.unit, gravity=rec.gravity)
    v = body["verdict"]
    assert v["apply"] is False and v["kind"] == "worse"
    assert v["words"].startswith("Don't apply it: your sensor is already better than this (error on new orientations ")
    before, after = _figures(v["words"])
    assert before == round(_raw_error_mg(calibrated, rec.gravity), 2) < 1.5  # what the first calibration left
    assert after == round(body["metrics"]["cv_error_mg"], 2) > before  # a second one gains nothing on new ones


def test_a_harmful_calibration_says_do_not_apply_it(client):
    rng = np.random.default_rng(1)
    means = random_unit_vectors(rng, 12) + rng.normal(scale=0.002, size=(12, 3))
    body = _post(client, means)
    v = body["verdict"]
    m = body["metrics"]
    assert m["error_after_mg"] < m["error_before_mg"]  # in-sample it looks better …
    assert v["apply"] is False and v["kind"] == "worse"  # … on new orientations it is worse
    assert v["words"].startswith("Don't apply it: your sensor is already better than this (error on new orientations ")
    before, after = _figures(v["words"])
    assert before == round(_raw_error_mg(means, 1.0), 2) and after == round(m["cv_error_mg"], 2) and after > before
    assert v["why"].startswith("It would make your sensor worse; keep it as it is.")


def test_a_gain_too_small_to_matter_says_there_is_no_need(client):
    # A sensor off by 0.4 mg in offset and 0.03 % in scale, read in 24 poses with 0.05 mg of noise.
    rng = np.random.default_rng(7)
    up = random_unit_vectors(rng, 24)
    means = up * np.array([1.0003, 0.9997, 1.0002]) + 0.0004 + rng.normal(scale=0.00005, size=(24, 3))
    body = _post(client, means)
    v = body["verdict"]
    assert body["ok"] and v["apply"] is False and v["kind"] == "no_gain"
    assert v["words"].startswith("No need to apply it: it changes too little to matter (error on new orientations ")
    before, after = _figures(v["words"])
    assert after < before and before - after < 0.5  # app.verdict.MIN_GAIN_MG


def test_a_calibration_that_failed_its_checks_says_so_with_its_first_reason(client):
    rec = RECS["mpu6050-session1"]
    body = _post(client, rec.means, unit=rec.unit, gravity=rec.gravity)
    v = body["verdict"]
    assert body["ok"] is False and v["apply"] is False
    assert v["words"].startswith("Don't apply it: ")
    assert v["why"].lower() == body["reasons"][0].lower()  # the first reason, which says what to do


def test_a_compass_calibration_s_verdict_is_in_microtesla_on_new_directions(client):
    m, _, _ = simulate_session(21, n=300, hard_iron_ut=80.0)
    r = client.post("/api/v1/calibrations", json={"method": "magnetometer", "mag": m.tolist(), "field_ut": 48.0})
    assert r.status_code == 201, r.text
    body = r.json()
    v = body["verdict"]
    assert v["apply"] and v["unit"] == "µT" and v["basis"] == "error of the field strength on new directions"
    assert v["words"].startswith("Apply it: error of the field strength on new directions ")
    before, after = _figures(v["words"])
    assert (before, after) == (round(body["metrics"]["raw_error_ut"], 1), round(body["metrics"]["cv_error_ut"], 2))
    # No place: the heading error at the inclination measured in the turn, else an assumed one, said so.
    assert v["degrees"]["kind"] == "heading" and v["degrees"]["inclination_source"] in ("measured", "assumed")
    assert "a heading off by " in v["words"] and "dips" in v["words"]


def test_a_compass_verdict_tells_its_heading_error_at_the_place_s_inclination(client):
    m, _, _ = simulate_session(21, n=300, hard_iron_ut=80.0)
    place = {"latitude_deg": 48.14, "longitude_deg": 11.58, "date": "2024-06-01"}
    r = client.post("/api/v1/calibrations", json={"method": "magnetometer", "mag": m.tolist(), **place})
    assert r.status_code == 201, r.text
    body = r.json()
    earth = reference_field(place["date"], place["latitude_deg"], place["longitude_deg"])
    d, metrics = body["verdict"]["degrees"], body["metrics"]
    assert d["inclination_source"] == "model" and d["inclination_deg"] == pytest.approx(earth.inclination_deg, abs=1e-9)
    h = earth.horizontal_ut  # IGRF-14's H at the place
    assert d["after_deg"] == pytest.approx(np.degrees(np.arcsin(metrics["cv_error_ut"] / h)), rel=1e-6)
    assert d["before_deg"] == pytest.approx(np.degrees(np.arcsin(min(1.0, metrics["raw_error_ut"] / h))), rel=1e-6)
    assert f"(the field dips {earth.inclination_deg:.0f}° at your place)" in body["verdict"]["words"]
    assert "a heading off by " in body["headline"] and f"dip of {earth.inclination_deg:.0f}°" in body["headline"]


def test_ok_never_carries_an_apply_verdict_when_the_figure_grew():
    # Whatever the gates said, a grown error is "worse": the verdict does not pass a bug on.
    body = {
        "method": "triangular",
        "ok": True,
        "reasons": [],
        "metrics": {"cv_error_mg": 3.0, "error_before_mg": 2.0, "error_after_mg": 1.0},
    }
    assert verdict(body)["kind"] == "worse" and verdict(body)["apply"] is False


def test_a_noise_characterisation_offers_figures_not_a_correction():
    assert verdict({"method": "noise", "ok": True})["kind"] == "figures"
    assert verdict({"method": "noise", "ok": False, "reasons": ["too short"]})["apply"] is False
