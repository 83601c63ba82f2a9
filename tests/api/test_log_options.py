"""POST /api/v1/recordings with a logger's own files: `columns`, `sign`, the iOS sign, and what is stored.

Uploads go through the application over HTTP (TestClient) into a fresh SQLite file per test, as in
tests/api/test_formats.py; the samples are those of tests/data/formats (make_format_samples.py).
"""

from __future__ import annotations

import io
import json

import numpy as np
import pytest

from app.api.schemas.recordings import RecordingOut
from app.workflows.recordings import RecordingSource
from simulations.cube import FIELD_UT, simulate_session
from tests.api.test_typed_contract import undescribed
from tests.conftest import DATA

SAMPLES = DATA / "formats"
TRUTH = json.loads((SAMPLES / "format_samples.json").read_text())
IMU = SAMPLES / "headerless_imu_comma.csv"
IMU_COLUMNS = "t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z"


def upload(client, name: str, content: bytes, **form):
    return client.post(
        "/api/v1/recordings", files={"file": (name, content, "text/csv")}, data={k: str(v) for k, v in form.items()}
    )


def test_columns_name_the_gyroscope_too(client):
    r = upload(client, IMU.name, IMU.read_bytes(), columns=IMU_COLUMNS)
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["channels"] == ["acc", "gyr"] and rec["units"] == {"acc": "g", "gyr": "rad/s"}
    assert rec["columns"] == IMU_COLUMNS.split(",") and rec["sampling_rate_hz"] == pytest.approx(50.0)
    assert rec["read_with"]["columns"] == IMU_COLUMNS and rec["sign"] == 1
    assert [s["up"] for s in rec["segments"]] == TRUTH["labels"]
    assert undescribed(RecordingOut.model_validate(rec)) == []
    assert client.get(f"/api/v1/recordings/{rec['id']}").json() == rec


def test_seven_headerless_columns_are_named_from_the_data(client):
    # time, an accelerometer resting in g between turns, a gyroscope in rad/s swinging between rests.
    r = upload(client, IMU.name, IMU.read_bytes())
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["columns"] == ["time", *IMU_COLUMNS.split(",")[1:]] and rec["units"] == {"acc": "g", "gyr": "rad/s"}
    assert any(
        n.startswith("no header row: 7 columns separated by commas, read from the data as accelerometer, gyroscope")
        for n in rec["notes"]
    )


@pytest.mark.parametrize(
    "columns, fragment",
    [
        ("t,acc_x,acc_y,acc_z", "columns names 4 columns (t, acc_x, acc_y, acc_z) but headerless_imu_comma.csv has 7"),
        ("t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_w", "'gyr_w', which trical does not know"),
        ("t,acc_x,acc_y,acc_z,gyr_x,-,-", "names gyr_x but not gyr_y, gyr_z"),
        ("t,acc_x,acc_x,acc_z,-,-,-", "names acc_x more than once"),
    ],
)
def test_bad_columns_are_a_422_naming_the_problem(client, columns, fragment):
    r = upload(client, IMU.name, IMU.read_bytes(), **({"columns": columns} if columns else {}))
    assert r.status_code == 422 and r.json()["code"] == "unreadable_log"
    assert fragment in r.json()["detail"]


def test_sign_minus_one_flips_an_upload(client):
    log = SAMPLES / "headerless_spaces_ms.txt"
    kept = upload(client, log.name, log.read_bytes()).json()
    flipped = upload(client, log.name, log.read_bytes(), sign=-1).json()
    assert kept["sign"] == 1 and flipped["sign"] == -1 and flipped["read_with"]["sign"] == -1
    opposite = {"+": "-", "-": "+"}
    assert [s["up"] for s in flipped["segments"]] == [opposite[u[0]] + u[1] for u in TRUTH["labels"]]
    np.testing.assert_allclose(
        [s["acc_mean"] for s in flipped["segments"]], -np.array([s["acc_mean"] for s in kept["segments"]])
    )


@pytest.mark.parametrize(
    "sign, fragment",
    [("0", "give 1 (keep the file's accelerations) or -1"), ("2", "give 1"), ("minus", "valid integer")],
)
def test_a_bad_sign_is_a_422(client, sign, fragment):
    r = upload(client, "x.txt", b"0 0 9.8\n" * 100, sign=sign, sampling_rate_hz=50)
    assert r.status_code == 422 and r.json()["code"] == "invalid_request" and fragment in r.json()["detail"]


def test_an_ios_header_is_detected_flipped_and_said_so(client):
    log = SAMPLES / "sensorlog_ios.csv"
    rec = upload(client, log.name, log.read_bytes()).json()
    assert rec["format"] == "sensorlog" and rec["sign"] == -1
    note = next(n for n in rec["notes"] if n.startswith("this looks like an iOS Core Motion log"))
    assert "accelerometerAccelerationX(G)" in note and note.endswith("pass sign=1 to keep them")
    assert [s["up"] for s in rec["segments"]] == TRUTH["labels"]
    kept = upload(client, log.name, log.read_bytes(), sign=1).json()
    assert kept["sign"] == 1 and not any("looks like an iOS" in n for n in kept["notes"])
    assert kept["segments"][0]["up"] == "-" + TRUTH["labels"][0][1]


def test_a_stored_recording_is_read_again_as_it_was_told(client, settings):
    log = SAMPLES / "sensorlog_ios.csv"
    rec = upload(client, log.name, log.read_bytes(), sign=1).json()
    again = RecordingSource(meta=rec, path=settings.recordings_dir / f"{rec['id']}.csv").read()
    assert again.sign == 1
    for seg in rec["segments"]:
        np.testing.assert_allclose(again.acc[seg["start"] : seg["end"]].mean(axis=0), seg["acc_mean"], atol=1e-9)


def test_a_cube_calibration_of_a_headerless_recording(client):
    # The cube method reads the stored file again (gyroscope and magnetometer): with the columns it was given.
    s = simulate_session(np.random.default_rng(21), sampling_rate_hz=100.0)
    buf = io.StringIO()
    np.savetxt(buf, np.hstack([s.acc, s.gyr, s.mag]), delimiter="\t", fmt="%.9g")
    names = "acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z,mag_x,mag_y,mag_z"
    rec = upload(client, "cube.txt", buf.getvalue().encode(), columns=names, sampling_rate_hz=100)
    assert rec.status_code == 201, rec.text
    cal = client.post(
        "/api/v1/calibrations",
        json={"method": "cube", "recording_id": rec.json()["id"], "protocol": "cube24", "field_ut": FIELD_UT},
    )
    assert cal.status_code == 201, cal.text
    assert set(cal.json()["model"]) >= {"acc", "gyr", "mag"}
