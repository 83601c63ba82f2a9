"""Over HTTP, with real recordings: a headerless table's columns from its data (or a 422 asking which, with
the candidates), the gyroscope's unit from its data (or not ok, asking), a bad line named first."""

from __future__ import annotations

import io
import math

import numpy as np
import pytest

from tests.conftest import DATA

CORPUS = DATA / "real" / "corpus"
STILL = CORPUS / "mpu6050_still_gyro_counts_headerless" / "imu_static_test_cols456.csv"
QMC = CORPUS / "qmc5883l_turn_headerless" / "qmc5883l_turn.csv"
FS = 100.0


def _upload(client, name: str, content: bytes, **form):
    return client.post(
        "/api/v1/recordings", files={"file": (name, content, "text/csv")}, data={k: str(v) for k, v in form.items()}
    )


def _table(header: str | None, values: np.ndarray, rate: float) -> bytes:
    buf = io.StringIO()
    if header:
        buf.write(header + "\n")
    np.savetxt(buf, np.column_stack([np.arange(len(values)) / rate, values]), delimiter=",", fmt="%.6f")
    return buf.getvalue().encode()


def test_ambiguous_columns_are_a_422_naming_each_reading_and_its_columns(client):
    r = _upload(client, STILL.name, STILL.read_bytes(), sampling_rate_hz=100)
    assert r.status_code == 422
    body = r.json()
    assert body["code"] == "columns_ambiguous" and "can be read more than one way" in body["detail"]
    assert [c["columns"] for c in body["candidates"]] == ["gyr_x,gyr_y,gyr_z", "mag_x,mag_y,mag_z"]
    assert body["preview"][0] == "-480,193,-83"
    chosen = _upload(
        client, STILL.name, STILL.read_bytes(), sampling_rate_hz=100, columns=body["candidates"][0]["columns"]
    )
    assert chosen.status_code == 201, chosen.text
    assert chosen.json()["channels"] == ["gyr"] and chosen.json()["units"] == {"gyr": "raw"}


def test_the_issue_s_still_gyroscope_in_deg_s_is_calibrated_in_deg_s(client):
    # A still MPU-6050 logged in °/s (the real counts ÷ 131), header naming the axes, no unit: its bias is the
    # offset in °/s (3.5 °/s), not the same number in rad/s (200 °/s).
    dps = np.loadtxt(STILL, delimiter=",") / 131.0
    for header in ("t,gyr_x,gyr_y,gyr_z", None):
        r = _upload(client, "still.csv", _table(header, dps, FS))
        assert r.status_code == 201, r.text
        rec = r.json()
        assert rec["channels"] == ["gyr"] and rec["units"] == {"gyr": "deg/s"} and rec["questions"] == []
        cal = client.post("/api/v1/calibrations", json={"method": "noise", "recording_id": rec["id"]})
        assert cal.status_code == 201, cal.text
        gyr = cal.json()["model"]["gyr"]  # the noise method's figures are in SI units
        assert gyr["unit"] == "rad/s"
        np.testing.assert_allclose(gyr["bias"], np.radians(np.mean(dps, axis=0)), atol=2e-4)


def test_a_gyroscope_whose_unit_nothing_decides_is_not_ok_and_asked_about(client):
    rng = np.random.default_rng(8)
    gyr = np.array([0.2, -0.2, 0.1]) + rng.normal(0, 0.003 * math.sqrt(FS), (3000, 3))
    r = _upload(client, "g.csv", _table("t,gyr_x,gyr_y,gyr_z", gyr, FS))
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["questions"][0]["sensor"] == "gyr"
    cal = client.post("/api/v1/calibrations", json={"method": "noise", "recording_id": rec["id"]})
    assert cal.status_code == 201, cal.text
    body = cal.json()
    assert body["ok"] is False and body["reasons"][0].startswith("the gyroscope's unit is not evident from its data")
    said = _upload(client, "g.csv", _table("t,gyr_x,gyr_y,gyr_z", gyr, FS), gyr_unit="deg/s")
    assert said.json()["questions"] == [] and said.json()["units"] == {"gyr": "deg/s"}


def test_a_compass_without_a_header_is_read_as_a_magnetometer(client):
    r = _upload(client, "log.csv", _table(None, np.loadtxt(QMC, delimiter=",") / 3000.0, 5.0))
    assert r.status_code == 201, r.text
    assert r.json()["channels"] == ["mag"] and r.json()["units"] == {"mag": "uT"}


def test_a_bad_line_is_named_first_with_its_own_code(client):
    r = _upload(client, "b.csv", b"acc_x,acc_y,acc_z\n0.1,0.2,9.8\n0.1,abc,9.8\n", sampling_rate_hz=100)
    assert r.status_code == 422 and r.json()["code"] == "bad_line"
    assert "line 3, column 'acc_y': 'abc' is not a number" in r.json()["detail"]


def test_a_time_column_that_steps_back_once_is_still_the_time_column(client):
    """The real headerless IMU log of twelve poses (imu_bias_gravity_12_poses_headerless_ns) with its clock set back
    0.9 s after row 700, as an Android logger's clock adjusted while logging: the first column is still its time
    (named in a note with the step), and the poses calibrate as the unchanged log's do (o within 0.02 m/s²)."""
    lines = (CORPUS / "imu_bias_gravity_12_poses_headerless_ns" / "imu.csv").read_text().splitlines()
    stepped = [
        ",".join([str(int(line.split(",")[0]) - 900_000_000)] + line.split(",")[1:]) if i >= 700 else line
        for i, line in enumerate(lines)
    ]
    r = _upload(client, "imu.csv", ("\n".join(stepped) + "\n").encode())
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["channels"] == ["acc", "gyr"], rec
    said = "goes back 1 time(s), first after sample 700 (55.92 → 55.1 s)"
    assert any(said in note for note in rec["notes"]), rec["notes"]
    body = client.post("/api/v1/calibrations", json={"method": "auto", "recording_id": rec["id"]}).json()
    assert body["ok"] is True, body.get("reasons")
    np.testing.assert_allclose(body["model"]["o"], [0.1127, -0.0061, 0.0627], atol=0.02)


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("sketch.ino", "void setup() {\n  Serial.begin(115200);\n}\n\nvoid loop() {\n  Serial.println(1);\n}\n"),
        ("words.csv", "name,colour,size\nalpha,red,big\nbeta,blue,small\n"),
    ],
)
def test_a_file_of_words_is_told_it_holds_no_readings(client, name, text):
    """An Arduino sketch or a table of words uploaded by mistake: a 422 saying the file holds no readings and what to
    upload instead, not a question about which column is which (no mapping reads numbers that are not there)."""
    r = _upload(client, name, text.encode())
    assert r.status_code == 422, r.text
    detail = r.json()["detail"]
    assert detail.startswith(f"{name} holds no readings: not one number after its first line"), detail
    assert "columns" not in detail.split(":", 1)[1].replace("in columns", ""), detail


def test_without_a_time_or_a_rate_the_gyroscope_question_asks_for_the_rate_first(client):
    """A real Android phone's still accelerometer.txt and gyro.txt, headerless, without a time column
    (tests/data/real/corpus/android_still_headerless_per_sensor_no_time): the gyroscope's offset alone cannot
    tell rad/s from deg/s, and what is missing is the rate (its noise at rest is read over time), so the question
    asks for sampling_rate_hz first; given a rate, the phone's noise decides rad/s and nothing is asked."""
    folder = CORPUS / "android_still_headerless_per_sensor_no_time"
    files = [("file", (n, (folder / n).read_bytes(), "text/plain")) for n in ("accelerometer.txt", "gyro.txt")]
    rec = client.post("/api/v1/recordings", files=files).json()
    (question,) = [q for q in rec["questions"] if q["sensor"] == "gyr"]
    assert "without the sampling rate" in question["detail"]
    assert question["detail"].endswith(
        "give sampling_rate_hz, from which its data may show the unit, or gyr_unit (rad/s or deg/s)"
    )
    rec = client.post("/api/v1/recordings", files=files, data={"sampling_rate_hz": "50"}).json()
    assert rec["units"] == {"acc": "m/s^2", "gyr": "rad/s"} and not rec["questions"], rec["warnings"]
