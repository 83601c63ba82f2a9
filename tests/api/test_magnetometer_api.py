"""method magnetometer over real HTTP: inline readings and uploaded recordings, the errors, and the
exports applied by each target's own formula (written here, independently of app.io):

* ArduPilot (AP_Compass_Backend.cpp, ``correct_field``), milligauss: ``mag += COMPASS_OFS``, then
  ``mag = [[DIA_X, ODI_X, ODI_Y], [ODI_X, DIA_Y, ODI_Z], [ODI_Y, ODI_Z, DIA_Z]] · mag``;
* PX4 (sensor_calibration/Magnetometer.hpp, ``Correct``), gauss: ``S · (data − CAL_MAG0_OFF)``, S built
  from xSCALE and xODIAG the same way;
* the C header compiled and run, YAML, CSV and JSON read back.
"""

from __future__ import annotations

import csv
import io
import json
import re
import shutil

import numpy as np
import pytest

from simulations.magnetometer import simulate_rests, simulate_session
from tests.processes import run_ok

F = 48.0


@pytest.fixture(scope="module")
def turn():
    m, M, b = simulate_session(21, n=300, hard_iron_ut=80.0)
    return m, M, b


def _post(client, **body):
    return client.post("/api/v1/calibrations", json={"method": "magnetometer", **body})


@pytest.fixture()
def cal(client, turn):
    r = _post(client, mag=turn[0].tolist(), field_ut=F, device_id="phone-c")
    assert r.status_code == 201, r.text
    return r.json()


def _apply(client, cal, samples):
    r = client.post(
        f"/api/v1/calibrations/{cal['id']}/apply", json={"samples": np.asarray(samples).tolist(), "sensor": "mag"}
    )
    assert r.status_code == 200, r.text
    return np.array(r.json()["samples"])


def _params(text: str, pattern: str) -> dict:
    return {m.group(1): float(m.group(2)) for m in re.finditer(pattern, text, re.M)}


def _symmetric(diag, off) -> np.ndarray:
    return np.array([[diag[0], off[0], off[1]], [off[0], diag[1], off[2]], [off[1], off[2], diag[2]]])


def test_inline_readings_calibrate_with_intervals_and_the_figures(client, cal, turn):
    m, M, b = turn
    assert cal["method"] == "magnetometer" and cal["model"]["type"] == "magnetometer" and cal["ok"], cal["reasons"]
    assert cal["unit"] == cal["output_unit"] == "uT" and cal["device_id"] == "phone-c"
    np.testing.assert_allclose(cal["model"]["b"], b, atol=0.3)
    np.testing.assert_allclose(cal["model"]["M"], M, atol=0.01)
    u = cal["uncertainty"]
    assert np.shape(u["M"]) == (3, 3) and np.shape(u["b"]) == (3,) and u["confidence"] == 0.95
    metrics = cal["metrics"]
    assert metrics["field_source"] == "given" and metrics["field_ut"] == F and metrics["coverage"] == 1.0
    assert metrics["cv_error_ut"] < 0.4 < metrics["raw_error_ut"]
    assert cal["headline"].startswith("on new directions expect")
    assert len(cal["samples"]["raw_ut"]) == 300
    h = _apply(client, cal, m)
    np.testing.assert_allclose(np.linalg.norm(h, axis=1).mean(), F, rtol=2e-3)
    again = client.get(f"/api/v1/calibrations/{cal['id']}").json()
    assert again == cal


def test_without_a_field_the_magnitude_is_estimated(client, turn):
    r = _post(client, mag=turn[0].tolist())
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["metrics"]["field_source"] == "estimated"
    assert any("estimated" in w for w in body["warnings"])
    assert np.linalg.det(np.array(body["model"]["M"])) == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize(
    "body, code, words",
    [
        ({"mag": [[1.0, 2.0, 3.0]] * 10}, "insufficient_data", "at least 50"),
        ({"mag": [[1.0, 2.0, 3.0]] * 60, "latitude_deg": 48.0}, "invalid_request", "longitude_deg"),
        ({}, "invalid_request", "`mag` or `recording_id`"),
        ({"mag": [[1.0, 2.0]] * 60}, "invalid_request", "mag[0]"),
        ({"mag": [[1.0, 2.0, 3.0]] * 60, "field_ut": -3}, "invalid_request", "field_ut"),
    ],
)
def test_bad_requests_say_what_to_fix(client, body, code, words):
    r = _post(client, **body)
    assert 400 <= r.status_code < 500, r.text
    assert r.json()["code"] == code and words in r.json()["detail"], r.json()


def test_inline_readings_keep_the_device_they_came_from(client, turn):
    """The compass page says whose readings it sends (a board's, a phone's): the calibration keeps it as its
    source, so its own page later speaks of that device; a recording's source is its format's, not given."""
    r = _post(client, mag=turn[0].tolist(), field_ut=F, source="board")
    assert r.status_code == 201, r.text
    assert r.json()["source"] == "board"
    assert "source" not in _post(client, mag=turn[0].tolist(), field_ut=F).json()
    r = _post(client, recording_id="rec_" + "0" * 32, source="board")
    assert r.status_code == 422 and "`source` is for inline `mag` readings" in r.text, r.text


def test_apply_asks_for_the_magnetometer(client, cal):
    r = client.post(f"/api/v1/calibrations/{cal['id']}/apply", json={"samples": [[1.0, 2.0, 3.0]]})
    assert r.status_code == 422 and 'sensor: "mag"' in r.json()["detail"]


def test_an_uploaded_turn_with_rests_checks_the_dip(client):
    """A recording of acc and mag at 50 Hz: rests of 2 s between turns, the dip measured at the rests."""
    rng = np.random.default_rng(22)
    m, M, b = simulate_session(22, n=1500, hard_iron_ut=40.0)
    rests = simulate_rests(rng, M, b, inclination_deg=64.0, n=4)
    rows, acc_turning = [], np.array([0.3, -0.2, 9.4])  # while turning the accelerometer reads no rest
    for k, (acc, mag) in enumerate(rests):
        rows += [np.r_[acc + rng.normal(0, 0.01, 3), mag + rng.normal(0, 0.2, 3)] for _ in range(100)]
        rows += [np.r_[acc_turning + rng.normal(0, 2.0, 3), v] for v in m[k * 375 : (k + 1) * 375]]
    data = np.array(rows)
    buf = io.StringIO()
    np.savetxt(
        buf,
        np.column_stack([np.arange(len(data)) / 50.0, data]),
        delimiter=",",
        fmt="%.6f",
        comments="",
        header="time_s,acc_x,acc_y,acc_z,mag_x,mag_y,mag_z",
    )
    up = client.post(
        "/api/v1/recordings", files={"file": ("turn.csv", buf.getvalue().encode(), "text/csv")}, data={"mag_unit": "uT"}
    )
    assert up.status_code == 201, up.text
    r = _post(client, recording_id=up.json()["id"], field_ut=F)
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["recording_id"] == up.json()["id"] and body["metrics"]["rests"] >= 4
    assert body["metrics"]["measured_inclination_deg"] == pytest.approx(64.0, abs=1.0)
    assert body["metrics"]["count"] == len(data)


def test_a_recording_without_a_magnetometer_is_refused_by_name(client):
    buf = io.StringIO()
    np.savetxt(
        buf,
        np.random.default_rng(1).normal(size=(200, 3)) + [0, 0, 9.8],
        delimiter=",",
        fmt="%.5f",
        comments="",
        header="acc_x,acc_y,acc_z",
    )
    up = client.post(
        "/api/v1/recordings",
        files={"file": ("still.csv", buf.getvalue().encode(), "text/csv")},
        data={"sampling_rate_hz": "100"},
    )
    assert up.status_code == 201, up.text
    r = _post(client, recording_id=up.json()["id"])
    assert r.status_code == 422 and "no magnetometer columns" in r.json()["detail"]


def _export(client, cal, fmt):
    r = client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": fmt})
    assert r.status_code == 200, r.text
    return r.text


def test_ardupilot_compass_parameters_apply_by_ardupilot_s_formula(client, cal, turn):
    m = turn[0]
    p = _params(_export(client, cal, "ardupilot"), r"^(COMPASS_\w+) (\S+)$")
    offsets = np.array([p[f"COMPASS_OFS_{a}"] for a in "XYZ"])
    mat = _symmetric([p[f"COMPASS_DIA_{a}"] for a in "XYZ"], [p[f"COMPASS_ODI_{a}"] for a in "XYZ"])
    field_mgauss = 10.0 * m + offsets  # the driver's reading in mGauss, plus the offsets
    ardupilot_ut = (field_mgauss @ mat.T) / 10.0
    np.testing.assert_allclose(ardupilot_ut, _apply(client, cal, m), atol=1e-5)
    assert p["COMPASS_SCALE"] == 1.0
    np.testing.assert_allclose(offsets, -10.0 * np.array(cal["model"]["b"]), rtol=1e-8)


def test_px4_compass_parameters_apply_by_px4_s_formula(client, cal, turn):
    m = turn[0]
    p = _params(_export(client, cal, "px4"), r"^param set (CAL_MAG0_\w+) (\S+)$")
    off = np.array([p[f"CAL_MAG0_{a}OFF"] for a in "XYZ"])
    S = _symmetric([p[f"CAL_MAG0_{a}SCALE"] for a in "XYZ"], [p[f"CAL_MAG0_{a}ODIAG"] for a in "XYZ"])
    px4_ut = ((m / 100.0 - off) @ S.T) * 100.0
    np.testing.assert_allclose(px4_ut, _apply(client, cal, m), atol=1e-5)


def test_a_failed_compass_calibration_is_not_written_to_firmware(client):
    m, _, _ = simulate_session(23, n=300, max_polar_deg=80.0)  # a hemisphere: refused
    body = _post(client, mag=m.tolist(), field_ut=F).json()
    assert body["ok"] is False
    for fmt in ("ardupilot", "px4"):
        r = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": fmt})
        assert r.status_code == 422 and "must not be written" in r.json()["detail"]


def test_c_header_json_yaml_and_csv_carry_the_compass(client, cal, turn, tmp_path):
    m = turn[0][:20]
    expected = _apply(client, cal, m)
    doc = json.loads(_export(client, cal, "json"))
    assert doc["sensor"] == "magnetometer" and doc["correction"]["formula"].startswith("h = M (m - o)")
    np.testing.assert_allclose((m - doc["correction"]["o"]) @ np.array(doc["correction"]["M"]).T, expected, atol=1e-12)
    yaml_text = _export(client, cal, "yaml")
    assert "mag_matrix:" in yaml_text and "mag_offset:" in yaml_text
    rows = list(csv.reader(line for line in io.StringIO(_export(client, cal, "csv")) if not line.startswith("#")))
    assert any(row and row[0].startswith("mag") for row in rows)
    cc = shutil.which("cc") or shutil.which("gcc")
    assert cc, "a C compiler (gcc) is needed to test the C header export"
    (tmp_path / "cal.h").write_text(_export(client, cal, "c"))
    raw = ",".join("{{{!r},{!r},{!r}}}".format(*r) for r in m.tolist())
    (tmp_path / "main.c").write_text(
        '#include <stdio.h>\n#include "cal.h"\n'
        f"static const float raw[{len(m)}][3] = {{{raw}}};\n"
        "int main(void){float h[3];for(int i=0;i<%d;++i){trical_mag_apply(raw[i],h);"
        'printf("%%.7g %%.7g %%.7g\\n",h[0],h[1],h[2]);}return 0;}\n' % len(m)
    )
    run_ok(
        [cc, "-std=c99", "-Wall", "-Werror", "-o", str(tmp_path / "apply"), str(tmp_path / "main.c")],
        timeout_s=120,
        cwd=tmp_path,
    )
    out = run_ok([str(tmp_path / "apply")], timeout_s=30).stdout
    np.testing.assert_allclose(np.loadtxt(out.splitlines()), expected, atol=2e-4)  # float32 of ~100 µT values


def test_a_place_and_day_reference_the_earth_s_field(client):
    from app.geomag import reference_field

    earth = reference_field("2026-12-02", 60.17, 24.94, 20.0)  # Helsinki
    m, M, _b = simulate_session(24, n=400, field_ut=earth.field_ut)
    r = _post(client, mag=m.tolist(), date="2026-12-02", latitude_deg=60.17, longitude_deg=24.94, height_m=20.0)
    assert r.status_code == 201, r.text
    metrics = r.json()["metrics"]
    assert metrics["field_source"] == "model" and metrics["field_model"] == "IGRF-14"
    assert metrics["field_date"] == "2026-12-02"
    assert metrics["field_ut"] == pytest.approx(earth.field_ut, rel=1e-12)
    assert metrics["inclination_deg"] == pytest.approx(earth.inclination_deg, rel=1e-12)
    assert metrics["declination_deg"] == pytest.approx(earth.declination_deg, rel=1e-12)
    np.testing.assert_allclose(r.json()["model"]["M"], M, atol=0.006)
    given = _post(client, mag=m.tolist(), field_ut=30.0, latitude_deg=60.17, longitude_deg=24.94).json()
    assert given["metrics"]["field_source"] == "given" and any("more than 10 %" in w for w in given["warnings"])
    old = _post(client, mag=m.tolist(), date="1890-01-01", latitude_deg=60.17, longitude_deg=24.94)
    assert old.status_code == 422 and "from 1900 to 2030" in old.json()["detail"] and "field_ut" in old.json()["detail"]


def test_over_http_a_magnetometer_log_calibrates_and_the_accelerometer_methods_refuse_it(client):
    from tests.io.test_magnetometer_only_logs import CASES

    filename, content, _, _ = CASES["Sensor Logger CSV"]
    up = client.post("/api/v1/recordings", files={"file": (filename, content.encode(), "text/csv")})
    assert up.status_code == 201, up.text
    rec = up.json()
    assert rec["channels"] == ["mag"] and rec["segments"] == [] and rec["units"] == {"mag": "uT"}
    ok = client.post("/api/v1/calibrations", json={"method": "magnetometer", "recording_id": rec["id"], "field_ut": 48})
    assert ok.status_code == 201 and ok.json()["ok"], ok.text
    auto = client.post("/api/v1/calibrations", json={"method": "auto", "recording_id": rec["id"]})
    assert auto.status_code == 201 and auto.json()["method"] == "magnetometer", auto.text
    assert auto.json()["choice"]["method"] == "magnetometer" and auto.json()["metrics"]["field_source"] == "estimated"
    for method in ("six_position", "triangular", "cube", "autocal"):
        r = client.post("/api/v1/calibrations", json={"method": method, "recording_id": rec["id"]})
        assert r.status_code == 422, (method, r.text)
        assert "no accelerometer columns" in r.json()["detail"] and "method magnetometer" in r.json()["detail"]
    noise = client.post("/api/v1/calibrations", json={"method": "noise", "recording_id": rec["id"]})
    assert noise.status_code == 201 and list(noise.json()["model"]) == ["type", "mag"]
