"""Which column is which in a table without a header row, from what the columns read: real recordings (an
MPU-6050 still and turned between rests, a QMC5883L turned over the sphere), then the file's name as the tie."""

from __future__ import annotations

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.readers import read_log
from app.io.readers.columns import ColumnsAmbiguous, name_sensor
from app.io.readers.read_options import ReadOptions
from tests.conftest import DATA

CORPUS = DATA / "real" / "corpus"
STILL = CORPUS / "mpu6050_still_gyro_counts_headerless" / "imu_static_test_cols456.csv"
TURNS = CORPUS / "mpu6050_session1_turns_headerless" / "example_data_calibration_rows3001_8000.csv"
QMC = CORPUS / "qmc5883l_turn_headerless" / "qmc5883l_turn.csv"
QMC_LSB_PER_GAUSS = 3000.0  # QMC5883L datasheet, ±8 G range (its field of 1107 counts is then 37 µT)


def _timed(tmp_path, name, values, rate, fmt="%.6f"):
    p = tmp_path / name
    np.savetxt(p, np.column_stack([np.arange(len(values)) / rate, values]), delimiter=",", fmt=fmt)
    return p


def test_a_still_mpu6050_gyroscope_in_deg_s_without_a_header_is_a_gyroscope(tmp_path):
    # The case: time, x, y, z of a still MPU-6050 in °/s rest at a norm of 3.5 — no accelerometer's
    # unit, no Earth's field: a gyroscope, in °/s.
    log = read_log(_timed(tmp_path, "log.csv", np.loadtxt(STILL, delimiter=",") / 131.0, 100.0))
    assert log.columns == ["time", "gyr_x", "gyr_y", "gyr_z"] and log.units["gyr"] == "deg/s"
    assert log.notes[0].startswith("no header row: 4 columns separated by commas, read from the data as gyroscope")


def test_a_compass_turned_over_the_sphere_in_gauss_without_a_header_is_a_magnetometer(tmp_path):
    # The case: time, x, y, z in gauss of a compass turned everywhere — not linear acceleration.
    gauss = np.loadtxt(QMC, delimiter=",") / QMC_LSB_PER_GAUSS
    log = read_log(_timed(tmp_path, "log.csv", gauss, 5.0))
    assert log.columns == ["time", "mag_x", "mag_y", "mag_z"] and log.units["mag"] == "uT"
    assert "magnetometer readings in gauss multiplied by 100 into µT" in log.notes


def test_a_real_compass_in_counts_without_a_header_is_a_magnetometer():
    log = read_log(QMC, ReadOptions(sampling_rate_hz=5))
    assert log.channels == ["mag"] and log.units["mag"] == "raw"
    assert "(and the file's name" not in log.notes[0]  # the data alone decided


def test_real_accelerometer_and_gyroscope_counts_turned_between_rests():
    log = read_log(TURNS, ReadOptions(sampling_rate_hz=100))
    assert log.columns == ["acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"]
    assert log.units == {"acc": "g", "gyr": "deg/s"}
    assert any("divided by 131 into deg/s" in w for w in log.warnings)


def test_real_still_counts_a_gyroscope_or_a_magnetometer_could_read_are_asked_about(tmp_path):
    with pytest.raises(ColumnsAmbiguous) as e:
        read_log(STILL, ReadOptions(sampling_rate_hz=100), name=STILL.name)
    assert e.value.code == "columns_ambiguous"
    assert e.value.candidates == [
        {"sensors": "gyroscope", "columns": "gyr_x,gyr_y,gyr_z"},
        {"sensors": "magnetometer", "columns": "mag_x,mag_y,mag_z"},
    ]
    assert e.value.preview[:2] == ["-480,193,-83", "-439,189,-56"]
    chosen = read_log(STILL, ReadOptions(sampling_rate_hz=100, columns=e.value.candidates[0]["columns"]))
    assert chosen.channels == ["gyr"]
    named = tmp_path / "mpu6050_gyro.csv"
    named.write_bytes(STILL.read_bytes())
    assert read_log(named, ReadOptions(sampling_rate_hz=100), name=named.name).channels == ["gyr"]


@pytest.mark.parametrize(
    "name, sensor",
    [
        ("gyro_log.csv", "gyr"),
        ("Gyroscope.txt", "gyr"),
        ("accel.csv", "acc"),
        ("acc_01.csv", "acc"),
        ("compass.csv", "mag"),
        ("hmc5883l.txt", "mag"),
        ("qmc_turn.csv", "mag"),
        ("ak8963.csv", "mag"),
        ("log.csv", None),
        ("accel_and_gyro.csv", None),
    ],
)
def test_the_file_name_says_a_sensor(name, sensor):
    assert name_sensor(name) == sensor


def test_a_first_line_with_text_in_a_number_column_is_named_as_a_bad_line(tmp_path):
    p = tmp_path / "b.csv"
    p.write_text("0.1,abc,9.8\n" + "0.1,0.2,9.8\n" * 20)
    with pytest.raises(LogFormatError, match="line 1, column 2: 'abc' is not a number") as e:
        read_log(p)
    assert e.value.code == "bad_line"
    q = tmp_path / "c.csv"
    q.write_text("acc_x,acc_y,acc_z\n0.1,0.2,9.8\n0.1,abc,9.8\n")
    with pytest.raises(LogFormatError, match="line 3, column 'acc_y': 'abc' is not a number") as e:
        read_log(q, ReadOptions(sampling_rate_hz=100))
    assert e.value.code == "bad_line"
