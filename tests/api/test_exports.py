"""GET /api/v1/calibrations/{id}/export for yaml, csv, ardupilot and px4.

Each test applies the exported numbers with the target's own formula, written here independently
of app.io, and compares with trical's calibrated output (POST .../apply):

* yaml, csv: the full matrix, reproduced to float64 rounding;
* ArduPilot ``a_i = INS_ACCSCAL_i (m_i − INS_ACCOFFS_i)`` (AP_InertialSensor_Backend.cpp,
  ``_rotate_and_correct_accel``) and PX4 ``a_i = CAL_ACC0_iSCALE (m_i − CAL_ACC0_iOFF)``
  (sensor_calibration/Accelerometer.hpp, ``Correct``): offset and scale only, so the difference must
  stay within the residual the export's header reports, and reach it in the worst direction.
"""

from __future__ import annotations

import csv
import io
import json
import re

import numpy as np
import pytest

from app.io.exporters import EXPORTERS, FORMAT_NAMES
from tests.conftest import seed_table

G0 = 9.80665
CANONICAL = ["-x", "+x", "-y", "+y", "-z", "+z"]


def calibrate(client, table, unit="m/s^2", **extra):
    req = {"method": "six_position", "unit": unit,
           "readings": [{"up": lab, "mean": row.tolist()} for lab, row in zip(CANONICAL, table[:6])], **extra}
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
    rows = {row[0]: [float(v) for v in row[1:]]
            for row in csv.reader(line for line in io.StringIO(r.text) if not line.startswith("#"))
            if row[0] != "quantity"}
    o = np.array(rows["offset"])
    M = np.array([rows["M_x"], rows["M_y"], rows["M_z"]])
    np.testing.assert_allclose((t1 - o) @ M.T, trical_apply(client, cal, t1), rtol=0, atol=1e-12)


def _params(text: str, pattern: str) -> dict:
    return {m.group(1): float(m.group(2)) for m in re.finditer(pattern, text, re.M)}


def _reported_residual(text: str) -> tuple[float, np.ndarray]:
    worst = float(re.search(r"^# dropped_terms_residual_max: (\S+)", text, re.M).group(1))
    axis = re.search(r"^# dropped_terms_residual_per_axis: x (\S+), y (\S+), z (\S+)", text, re.M)
    return worst, np.array([float(v) for v in axis.groups()])


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
def test_offset_scale_targets_within_the_reported_residual(client, fmt, apply, unit):
    t1 = seed_table(1)
    to_unit = 1.0 if unit == "m/s^2" else 1 / G0
    cal = calibrate(client, t1 * to_unit, unit=unit)
    r = export(client, cal, fmt)
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/plain"), r.text
    worst, per_axis = _reported_residual(r.text)
    gravity = cal["gravity"]
    # Readings of every direction that calibrate to magnitude g, in the calibration's input unit.
    M = np.array(json.loads(export(client, cal, "json").text)["correction"]["M"])
    o = np.array(json.loads(export(client, cal, "json").text)["correction"]["o"])
    a_true = sphere() * gravity
    m = a_true @ np.linalg.inv(M).T + o
    trical = trical_apply(client, cal, m)
    firmware = apply(r.text, m / to_unit) * to_unit  # firmware works in m/s²; back to the output unit
    diff = trical - firmware
    norms = np.linalg.norm(diff, axis=1)
    assert norms.max() <= worst * (1 + 1e-5)
    assert norms.max() >= 0.98 * worst  # the bound is the worst case, reached on a dense sphere
    assert np.all(np.abs(diff).max(axis=0) <= per_axis * (1 + 1e-5))
    # The seed's calibration has cross-axis terms of about 1 %: the residual is tens of mg, not zero.
    assert 0.005 * gravity < worst < 0.1 * gravity
    # With the off-diagonal terms removed from the same correction, the target reproduces it.
    D = np.diag(np.diag(M))
    np.testing.assert_allclose(firmware, (m - o) @ D.T, rtol=0, atol=1e-6 * gravity)


def test_ardupilot_refuses_out_of_range_values_with_the_reason(client):
    shifted = seed_table(1) + [5.0, 0.0, 0.0]  # a 5 m/s² x offset: ArduPilot accepts ±3.5
    r = export(client, calibrate(client, shifted), "ardupilot")
    assert r.status_code == 422
    detail = r.json()["detail"]
    assert "INS_ACCOFFS_X = 5.35" in detail and "outside -3.5…3.5 m/s/s" in detail
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
    worst, _ = _reported_residual(text)
    diff = np.linalg.norm(expected - px4_apply(text, t), axis=1)
    # The seed's readings are near |a| = g, so the bound holds up to their norm error (well under 1 %).
    assert diff.max() <= worst * 1.01
