"""POST /api/v1/recordings with every log format: the sample files of tests/data/formats end to end.

The samples are written by tests/data/formats/make_format_samples.py (one simulated recording of six
rests in each app's layout); each upload must find the six rests with the right `up` labels, which
also checks the sign (a flipped log would label +z as -z).
"""

from __future__ import annotations

import json
import typing

import numpy as np
import pytest

from app.api.schemas.recordings import UploadOptions
from app.io.readers import FORMATS
from tests.conftest import DATA

SAMPLES = DATA / "formats"
TRUTH = json.loads((SAMPLES / "format_samples.json").read_text())
G0 = 9.80665


def upload(client, path, **form):
    media = "application/zip" if path.suffix == ".zip" else "text/csv"
    return client.post(
        "/api/v1/recordings",
        files={"file": (path.name, path.read_bytes(), media)},
        data={k: str(v) for k, v in form.items()},
    )


@pytest.mark.parametrize(
    "filename, fmt, unit, form",
    [
        ("phyphox_comma.csv", "phyphox", "m/s^2", {}),
        ("phyphox_tab.csv", "phyphox", "m/s^2", {}),
        ("phyphox_semicolon_decimal_comma.csv", "phyphox", "m/s^2", {}),
        ("phyphox_export.zip", "phyphox", "m/s^2", {}),
        ("sensor_logger_android.zip", "sensor_logger", "m/s^2", {}),
        ("sensor_logger_ios.zip", "sensor_logger", "g", {}),
        ("sensor_logger_TotalAcceleration.csv", "sensor_logger", "m/s^2", {}),
        ("physics_toolbox_gforce.csv", "physics_toolbox", "g", {}),
        ("gnss_logger.txt", "gnss_logger", "m/s^2", {}),
        ("arduino_serial_plotter.txt", "arduino", "g", {"sampling_rate_hz": 50}),
        ("arduino_lsb.csv", "arduino", "g", {}),
        ("generic_g.csv", "csv", "g", {}),
        ("headerless_spaces_ms.txt", "csv", "m/s^2", {}),
        ("headerless_semicolon_decimal_comma.csv", "csv", "m/s^2", {}),
        ("headerless_tab_xyz_g.txt", "csv", "g", {"sampling_rate_hz": 50}),
        ("headerless_imu_comma.csv", "csv", "g", {"columns": "t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z"}),
        ("sensorlog_ios.csv", "sensorlog", "g", {}),
    ],
)
def test_each_format_finds_the_six_rests(client, filename, fmt, unit, form):
    r = upload(client, SAMPLES / filename, **form)
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["format"] == fmt and rec["units"]["acc"] == unit
    assert rec["n_samples"] == TRUTH["n_samples"] and rec["sampling_rate_hz"] == pytest.approx(50.0, rel=1e-3)
    assert [s["up"] for s in rec["segments"]] == TRUTH["labels"]
    # The sign: the up axis reads about +1 g in every rest.
    g = 1.0 if unit == "g" else G0
    axis = {"x": 0, "y": 1, "z": 2}
    for seg in rec["segments"]:
        up = seg["up"]
        value = seg["acc_mean"][axis[up[1]]] * (1 if up[0] == "+" else -1)
        assert abs(value / g - 1.0) < 0.08, (up, seg["acc_mean"])
    for s, t in zip(rec["segments"], TRUTH["segments"]):
        assert abs(s["start"] - t["start"]) < 0.4 * 50 and abs(s["end"] - t["end"]) < 0.4 * 50


def test_ios_sign_is_flipped_and_said_so(client):
    rec = upload(client, SAMPLES / "sensor_logger_ios.zip").json()
    assert "iOS sign flipped to +g on the up axis" in rec["notes"]
    android = upload(client, SAMPLES / "sensor_logger_android.zip").json()
    assert not any("flipped" in n for n in android["notes"])
    np.testing.assert_allclose(
        np.array([s["acc_mean"] for s in rec["segments"]]) * G0, [s["acc_mean"] for s in android["segments"]], atol=1e-4
    )
    assert android["channels"] == ["acc", "gyr"]


def test_six_position_calibration_from_a_zip(client):
    rec = upload(client, SAMPLES / "phyphox_export.zip").json()
    cal = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]})
    assert cal.status_code == 201, cal.text
    np.testing.assert_allclose(cal.json()["model"]["X"], TRUTH["model"]["X"], atol=5e-3)


@pytest.mark.parametrize(
    "filename, fragment",
    [
        ("phyphox_linear.csv", "linear acceleration (gravity removed"),
        ("sensor_logger_ios_linear_only.zip", "acceleration without gravity (linear acceleration)"),
    ],
)
def test_linear_acceleration_is_refused(client, filename, fragment):
    r = upload(client, SAMPLES / filename)
    assert r.status_code == 422 and fragment in r.json()["detail"]


def test_linear_acceleration_found_from_the_data(client):
    # Physics Toolbox 'Linear Accelerometer' layout: the generic reader maps ax, ay, az, the data say no gravity.
    rng = np.random.default_rng(1)
    noise = rng.normal(0, 0.05, (300, 3))
    rows = "\n".join(f"{i / 100:.2f};{a:.4f};{b:.4f};{c:.4f};0" for i, (a, b, c) in enumerate(noise))
    content = f"time;ax;ay;az;aT\n{rows}\n".encode()
    r = client.post("/api/v1/recordings", files={"file": ("lin.csv", content, "text/csv")})
    assert r.status_code == 422, r.text
    assert "linear acceleration (gravity removed)" in r.json()["detail"]


def test_unrecognised_columns_are_listed_with_how_to_map_them(client):
    r = client.post(
        "/api/v1/recordings",
        files={"file": ("x.csv", b"when,north,east,down\n0,1,2,3\n", "text/csv")},
        data={"sampling_rate_hz": "100"},
    )
    assert r.status_code == 422
    detail = r.json()["detail"]
    assert "'when', 'north', 'east', 'down'" in detail and "acc_x, acc_y, acc_z" in detail


def test_explicit_format_that_does_not_match(client):
    r = upload(client, SAMPLES / "generic_g.csv", format="phyphox")
    assert r.status_code == 422 and "does not look like a phyphox file" in r.json()["detail"]
    r = upload(client, SAMPLES / "phyphox_export.zip", format="gnss_logger")
    assert r.status_code == 415 and "zip archive" in r.json()["detail"]


def test_other_zips_are_refused_with_their_contents(client):
    import io
    import zipfile

    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        zf.writestr("photo.jpg", b"\xff\xd8")
    r = client.post("/api/v1/recordings", files={"file": ("x.zip", buf.getvalue(), "application/zip")})
    assert r.status_code == 415 and "photo.jpg" in r.json()["detail"]


def test_excel_workbooks_are_refused_with_the_fix(client):
    import io
    import zipfile

    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        zf.writestr("[Content_Types].xml", "<Types/>")
        zf.writestr("xl/workbook.xml", "<workbook/>")
    r = client.post("/api/v1/recordings", files={"file": ("data.xlsx", buf.getvalue(), "application/zip")})
    assert r.status_code == 415 and "Excel workbook" in r.json()["detail"]


def test_lsb_per_g_form_field(client):
    r = upload(client, SAMPLES / "arduino_lsb.csv", lsb_per_g=4096)
    assert r.status_code == 201 and r.json()["units"]["acc"] == "g"
    r = upload(client, SAMPLES / "generic_g.csv", lsb_per_g=4096, acc_unit="g")
    assert r.status_code == 422 and "converts counts of the accelerometer, but acc_unit says" in r.json()["detail"]


def test_the_upload_field_offers_every_format():
    assert set(typing.get_args(UploadOptions.model_fields["format"].annotation)) == set(FORMATS)


def test_unrecognised_columns_mapped_with_the_columns_field(client):
    text = (SAMPLES / "generic_g.csv").read_text().replace("time_ms,acc_x,acc_y,acc_z", "stamp,north,east,down")
    files = {"file": ("mine.csv", text.encode(), "text/csv")}
    # Named from the data: a time rising at every line, and an accelerometer resting at 1 g.
    guessed = client.post("/api/v1/recordings", files=files)
    assert guessed.status_code == 201, guessed.text
    assert guessed.json()["columns"] == ["time", "acc_x", "acc_y", "acc_z"]
    assert guessed.json()["notes"][0].startswith("the header's columns (stamp, north, east, down) name no sensor")
    assert [s["up"] for s in guessed.json()["segments"]] == TRUTH["labels"]
    r = client.post(
        "/api/v1/recordings", files=files, data={"columns": "acc_x:north,acc_y:east,acc_z:down,time_ms:stamp"}
    )
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["units"]["acc"] == "g" and rec["sampling_rate_hz"] == pytest.approx(50.0)
    assert [s["up"] for s in rec["segments"]] == TRUTH["labels"]
    bad = client.post("/api/v1/recordings", files=files, data={"columns": "acc_x:nord,acc_y:east,acc_z:down"})
    assert bad.status_code == 422 and "'nord', which is not a column" in bad.json()["detail"]
    bad = client.post("/api/v1/recordings", files=files, data={"columns": "accel_x:north"})
    assert bad.status_code == 422 and "trical does not know" in bad.json()["detail"]
