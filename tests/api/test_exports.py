"""GET /api/v1/calibrations/{id}/export for yaml, csv, ardupilot and px4.

Each test applies the exported numbers with the target's own formula, written here independently
of app.io, and compares with trical's calibrated output (POST .../apply):

* yaml, csv: the full matrix, reproduced to float64 rounding;
* ArduPilot ``a_i = INS_ACCSCAL_i (m_i − INS_ACCOFFS_i)`` (AP_InertialSensor_Backend.cpp,
  ``_rotate_and_correct_accel``) and PX4 ``a_i = CAL_ACC0_iSCALE (m_i − CAL_ACC0_iOFF)``
  (sensor_calibration/Accelerometer.hpp, ``Correct``): offset and scale only, so the norm error they reach on
  the calibration's readings, and over every direction of trical's model, must be the figures the export's
  header states.
"""

from __future__ import annotations

import csv
import io
import json
import re

import numpy as np
import pytest

from app.io.exports.exporters import EXPORTERS, FORMAT_NAMES
from tests.conftest import seed_table

G0 = 9.80665
CANONICAL = ["-x", "+x", "-y", "+y", "-z", "+z"]


def calibrate(client, table, unit="m/s^2", **extra):
    req = {
        "method": "six_position",
        "unit": unit,
        "readings": [{"up": lab, "mean": row.tolist()} for lab, row in zip(CANONICAL, table[:6])],
        **extra,
    }
    r = client.post("/api/v1/calibrations", json=req)
    assert r.status_code == 201, r.text
    return r.json()


def trical_apply(client, cal, samples):
    r = client.post(f"/api/v1/calibrations/{cal['id']}/apply", json={"samples": np.asarray(samples).tolist()})
    assert r.status_code == 200, r.text
    return np.array(r.json()["samples"])


def export(client, cal, fmt):
    return client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": fmt})


def tiny_yaml(text: str) -> dict:
    """The flat YAML trical writes: ``key: value`` lines whose values are JSON (flow sequences, strings)."""
    doc = {}
    for line in text.splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        key, _, value = line.partition(": ")
        doc[key] = json.loads(value)
    return doc


def sphere(n=2000, seed=3):
    v = np.random.default_rng(seed).normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def test_names_are_registered():
    assert {"ardupilot", "px4", "yaml", "csv"} <= set(EXPORTERS)
    assert [FORMAT_NAMES[k] for k in ("ardupilot", "px4", "yaml", "csv")] == ["ArduPilot", "PX4", "YAML", "CSV"]


def test_yaml_reproduces_the_calibration(client):
    t1 = seed_table(1)
    cal = calibrate(client, t1, gravity=9.81, device_id="phone-a")
    r = export(client, cal, "yaml")
    assert r.status_code == 200 and r.headers["content-type"].startswith("application/yaml")
    doc = tiny_yaml(r.text)
    assert doc["id"] == cal["id"] and doc["input_unit"] == "m/s^2" and doc["gravity"] == 9.81
    assert doc["device_id"] == "phone-a" and doc["formula"] == "a = M (m - o)"
    M, o = np.array(doc["matrix"]), np.array(doc["offset"])
    np.testing.assert_allclose((t1 - o) @ M.T, trical_apply(client, cal, t1), rtol=0, atol=1e-12)


def test_yaml_is_read_alike_by_a_yaml_parser(client):
    import yaml

    cal = calibrate(client, seed_table(1) / G0, unit="g")
    text = export(client, cal, "yaml").text
    assert yaml.safe_load(text) == tiny_yaml(text)


def test_csv_reproduces_the_calibration(client):
    t1 = seed_table(1)
    cal = calibrate(client, t1)
    r = export(client, cal, "csv")
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    rows = {
        row[0]: [float(v) for v in row[1:]]
        for row in csv.reader(line for line in io.StringIO(r.text) if not line.startswith("#"))
        if row[0] != "quantity"
    }
    o = np.array(rows["offset"])
    M = np.array([rows["M_x"], rows["M_y"], rows["M_z"]])
    np.testing.assert_allclose((t1 - o) @ M.T, trical_apply(client, cal, t1), rtol=0, atol=1e-12)


def _params(text: str, pattern: str) -> dict:
    return {m.group(1): float(m.group(2)) for m in re.finditer(pattern, text, re.M)}


def stated(text: str, key: str) -> float:
    """A figure the export's comment header states as ``# key: value``."""
    return float(re.search(rf"^# {key}: (\S+)", text, re.M).group(1))


def norm_error_mg(a, gravity) -> np.ndarray:
    return 1000 * np.abs(np.linalg.norm(a, axis=1) - gravity) / gravity


def ardupilot_apply(text: str, m_mps2: np.ndarray) -> np.ndarray:
    """ArduPilot: accel -= INS_ACCOFFS; accel.{x,y,z} *= INS_ACCSCAL_{X,Y,Z} (m/s/s)."""
    p = _params(text, r"^(INS_ACC(?:OFFS|SCAL)_[XYZ]) (\S+)$")
    off = np.array([p[f"INS_ACCOFFS_{a}"] for a in "XYZ"])
    scale = np.array([p[f"INS_ACCSCAL_{a}"] for a in "XYZ"])
    return (m_mps2 - off) * scale


def px4_apply(text: str, m_mps2: np.ndarray) -> np.ndarray:
    """PX4: (data - thermal_offset - offset).emult(scale), thermal offset 0 (m/s²)."""
    p = _params(text, r"^param set (CAL_ACC0_[XYZ](?:OFF|SCALE)) (\S+)$")
    off = np.array([p[f"CAL_ACC0_{a}OFF"] for a in "XYZ"])
    scale = np.array([p[f"CAL_ACC0_{a}SCALE"] for a in "XYZ"])
    return (m_mps2 - off) * scale


@pytest.mark.parametrize("fmt, apply", [("ardupilot", ardupilot_apply), ("px4", px4_apply)])
@pytest.mark.parametrize("unit", ["m/s^2", "g"])
def test_offset_scale_targets_reach_the_stated_figures(client, fmt, apply, unit):
    t1 = seed_table(1)
    to_unit = 1.0 if unit == "m/s^2" else 1 / G0
    cal = calibrate(client, t1 * to_unit, unit=unit)
    r = export(client, cal, fmt)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/plain"), r.text
    gravity = cal["gravity"]
    means = np.array([x["mean"] for x in cal["readings"]])
    firmware = apply(r.text, means / to_unit) * to_unit  # firmware works in m/s²; back to the output unit
    # Six readings, six numbers: the firmware's formula meets g on every one; raw and trical's as stated.
    assert norm_error_mg(firmware, gravity).max() < 1e-5 and stated(r.text, "firmware_norm_error_max_mg") == 0
    assert norm_error_mg(means, gravity).max() == pytest.approx(stated(r.text, "raw_norm_error_max_mg"), abs=6e-4)
    trical = trical_apply(client, cal, means)
    assert norm_error_mg(trical, gravity).max() == pytest.approx(stated(r.text, "trical_norm_error_max_mg"), abs=6e-4)
    # Over every direction, on readings trical's model puts at magnitude g: the firmware's worst is the one stated.
    doc = json.loads(export(client, cal, "json").text)["correction"]
    M, o = np.array(doc["M"]), np.array(doc["o"])
    m = sphere(20000) * gravity @ np.linalg.inv(M).T + o
    worst = norm_error_mg(apply(r.text, m / to_unit) * to_unit, gravity).max()
    assert 0.99 * stated(r.text, "firmware_norm_error_any_direction_mg") <= worst
    assert worst <= stated(r.text, "firmware_norm_error_any_direction_mg") + 6e-4
    # The rotation of M = R P, from its singular value decomposition (R = U Vᵀ), as stated.
    U, _, Vt = np.linalg.svd(M)
    angle = np.degrees(np.arccos((np.trace(U @ Vt) - 1) / 2))
    assert angle == pytest.approx(stated(r.text, "rotation_deg"), abs=6e-4)


def test_ardupilot_refuses_out_of_range_values_with_the_reason(client):
    shifted = seed_table(1) + [5.0, 0.0, 0.0]  # a 5 m/s² x offset: ArduPilot accepts ±3.5
    r = export(client, calibrate(client, shifted), "ardupilot")
    assert r.status_code == 422
    detail = r.json()["detail"]
    assert "INS_ACCOFFS_X = 5.299" in detail and "outside -3.5…3.5 m/s/s" in detail
    assert "AP_InertialSensor_Params" in detail


def test_raw_calibrations_are_not_exported_to_firmware_parameters(client):
    counts = seed_table(1) / G0 * 4096
    cal = calibrate(client, counts, unit="raw")
    for fmt in ("ardupilot", "px4"):
        r = export(client, cal, fmt)
        assert r.status_code == 422 and "counts" in r.json()["detail"] and "lsb_per_g" in r.json()["detail"]
    for fmt in ("yaml", "csv"):
        assert export(client, cal, fmt).status_code == 200


@pytest.mark.parametrize("method, table", [("nonorthogonal", 1), ("triangular", 2)])
def test_unknown_orientation_models_export_alike(client, method, table):
    t = seed_table(table)
    r = client.post("/api/v1/calibrations", json={"method": method, "means": t[:20].tolist(), "gravity": 9.806})
    assert r.status_code == 201, r.text
    cal = r.json()
    expected = trical_apply(client, cal, t)
    doc = tiny_yaml(export(client, cal, "yaml").text)
    M, o = np.array(doc["matrix"]), np.array(doc["offset"])
    np.testing.assert_allclose((t - o) @ M.T, expected, rtol=0, atol=1e-12)
    text = export(client, cal, "px4").text
    # Twenty readings for six numbers: the figure the firmware reaches on them is a fit's, not an exact one's.
    gravity = cal["gravity"]
    firmware = norm_error_mg(px4_apply(text, t[:20]), gravity)
    assert firmware.max() == pytest.approx(stated(text, "firmware_norm_error_max_mg"), abs=6e-4)
    assert firmware.mean() == pytest.approx(stated(text, "firmware_norm_error_mean_mg"), abs=6e-4)
    assert norm_error_mg(t[:20], gravity).max() == pytest.approx(stated(text, "raw_norm_error_max_mg"), abs=6e-4)
    assert 0 < firmware.max() < stated(text, "raw_norm_error_max_mg")
