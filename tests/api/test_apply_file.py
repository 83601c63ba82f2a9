"""POST /api/v1/calibrations/{id}/apply-file: a stored calibration (the MPU-6050 board's fit on its ten real still
poses) applied to the board's real 30 s still recording, the rows streamed back as CSV, Parquet or .npy; bad input is
a 4xx naming the API's fields. Over a live server (real HTTP, the answer read as it streams) and TestClient."""

from __future__ import annotations

import io

import httpx
import numpy as np
import pyarrow.parquet as pq

from app.io.readers import read_log
from tests.live_server import live_server
from tests.real_recordings import REAL, mpu6050_session1

STILL = REAL / "mpu6050_session2_still_30s.csv"
HYPERIMU = REAL / "corpus" / "hyperimu_lsm6ds3_phone_still" / "imu.csv"


def _calibrate(http) -> dict:
    r = http.post(
        "/api/v1/calibrations", json={"method": "triangular", "unit": "g", "means": mpu6050_session1().tolist()}
    )
    assert r.status_code == 201, r.text
    return r.json()


def _apply(http, cal_id: str, path=STILL, **form):
    with open(path, "rb") as f:
        return http.post(f"/api/v1/calibrations/{cal_id}/apply-file", files={"file": (path.name, f)}, data=form)


def test_the_rows_stream_back_over_http_equal_to_applying_the_stored_samples_endpoint(tmp_path):
    with (
        live_server({"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}"}) as server,
        httpx.Client(base_url=server.url, timeout=30) as http,
    ):
        body = _calibrate(http)
        with (
            open(STILL, "rb") as f,
            http.stream(
                "POST",
                f"/api/v1/calibrations/{body['id']}/apply-file",
                files={"file": (STILL.name, f)},
                data={"output_format": "npy"},
            ) as r,
        ):
            assert r.status_code == 200, r.read()
            assert r.headers["content-type"] == "application/octet-stream"
            assert r.headers["x-trical-rows"] == "3000" and r.headers["x-trical-corrected"] == "acc"
            assert f'filename="{body["id"]}-calibrated.npy"' in r.headers["content-disposition"]
            blocks = list(r.iter_bytes())
        # The samples endpoint beside it: the same calibration on the same samples, as JSON.
        acc = read_log(STILL).acc
        same = http.post(f"/api/v1/calibrations/{body['id']}/apply", json={"samples": acc.tolist()}).json()
    arr = np.load(io.BytesIO(b"".join(blocks)))
    assert arr.dtype.names == ("acc_x (g)", "acc_y (g)", "acc_z (g)")
    got = np.column_stack([arr[n] for n in arr.dtype.names])
    assert np.max(np.abs(got - np.array(same["samples"]))) <= 1e-9 and same["unit"] == "g"


def test_csv_by_default_with_its_units_and_what_passed_through(client):
    body = _calibrate(client)
    columns = (
        "acc_x:accelerometer_lsm6ds3_c.x,acc_y:accelerometer_lsm6ds3_c.y,acc_z:accelerometer_lsm6ds3_c.z,"
        "gyr_x:gyroscope_lsm6ds3_c.x,gyr_y:gyroscope_lsm6ds3_c.y,gyr_z:gyroscope_lsm6ds3_c.z,"
        "mag_x:akm_akm09918.x,mag_y:akm_akm09918.y,mag_z:akm_akm09918.z,time_ms:timestamp"
    )
    r = _apply(client, body["id"], HYPERIMU, columns=columns)
    assert r.status_code == 200, r.text
    assert r.headers["content-type"].startswith("text/csv")
    assert r.headers["x-trical-passed-through"] == "gyr,mag"
    lines = r.text.splitlines()
    assert (
        lines[1]
        == "# acc: corrected, m/s^2 -> g (read in m/s^2, times 0.101971621298 into the calibration's unit first)"
    )
    assert lines[4].startswith("time (s),acc_x (g),acc_y (g),acc_z (g),gyr_x (rad/s)")


def test_parquet_fields_say_their_unit(client):
    body = _calibrate(client)
    r = _apply(client, body["id"], output_format="parquet")
    assert r.status_code == 200, r.text
    table = pq.read_table(io.BytesIO(r.content))
    assert table.num_rows == 3000
    assert table.schema.field("acc_x (g)").metadata == {b"unit": b"g", b"corrected": b"true"}


def test_bad_input_is_a_4xx_naming_the_fields(client):
    body = _calibrate(client)
    r = _apply(client, body["id"], output_format="hdf5")
    assert r.status_code == 422 and r.json()["code"] == "invalid_request" and "output_format" in r.text
    r = _apply(client, body["id"], acc_unit="raw")
    assert r.status_code == 422 and r.json()["code"] == "calibration_refused"
    assert "gives its accelerometer in counts (raw), which cannot be converted" in r.json()["detail"]
    assert "(chip or lsb_per_g)" in r.json()["detail"]
    r = _apply(client, "cal_0000")
    assert r.status_code == 404
    mag_only = REAL / "corpus" / "hmc5883l_esp32_still_counts" / "mag_data.csv"
    r = _apply(client, body["id"], mag_only)
    assert (
        r.status_code == 422
        and "the calibration corrects accelerometer, and mag_data.csv holds magnetometer" in (r.json()["detail"])
    )
