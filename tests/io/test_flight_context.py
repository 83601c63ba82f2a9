"""A simulated flight written as both firmwares' logs (tests/flight_logs.py write_flight_logs) and read back by
read_flight_compass: the raw compass, the attitude, the current and throttle, the place and date, and the
stored calibrations come back as written; layouts trical cannot read are refused naming message and field."""

from __future__ import annotations

import numpy as np
import pytest

from app.calibration.shared.rotations import px4_matrix
from app.io.errors import LogFormatError
from app.io.flight.compass import read_flight_compass
from app.io.flight.px4 import px4_rotation
from app.io.readers import read_log
from tests.flight_logs import (
    ardupilot_flight_messages,
    ardupilot_imu,
    px4_flight_topics,
    simulated_flight,
    ulog_bytes,
    write_dataflash,
    write_flight_logs,
)

RAW_ATOL_UT = 1e-3
"""The raw field read back: float32 in the logs (MagX… of the simulated DataFlash, sensor_mag's x…)."""


def _rotation_z(deg):
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _check_common(r, flight, *, current_atol=1e-5, throttle_atol=1e-6):
    np.testing.assert_allclose(r.time_s, flight["time_s"], atol=1e-6)
    np.testing.assert_allclose(r.mag_raw_ut, flight["mag_raw_ut"], atol=RAW_ATOL_UT)
    np.testing.assert_allclose(r.attitude_time_s, flight["time_s"], atol=1e-6)
    np.testing.assert_allclose(r.attitude_c_nb, flight["attitude_c_nb"], atol=1e-5)
    np.testing.assert_allclose(r.power_time_s, flight["time_s"], atol=1e-6)
    np.testing.assert_allclose(r.current_a, flight["current_a"], atol=current_atol)
    np.testing.assert_allclose(r.throttle, flight["throttle"], atol=throttle_atol)
    assert (r.latitude_deg, r.longitude_deg) == pytest.approx((flight["lat"], flight["lon"]), abs=1e-7)
    assert r.altitude_m == pytest.approx(flight["alt_m"], abs=0.01)
    assert abs((r.utc - flight["utc"]).total_seconds()) < 1e-3


@pytest.mark.parametrize("generation", ["new", "old"])
def test_ardupilot_log_of_a_flight_reads_back_what_was_written(tmp_path, generation):
    flight = simulated_flight(3)
    bin_path, _ = write_flight_logs(tmp_path, flight, ardupilot_generation=generation)
    r = read_flight_compass(bin_path)
    cal = flight["stored"]["ardupilot"]
    assert r.firmware == "ardupilot" and r.instance == 0
    assert r.generation.endswith("(TimeUS, MAG with I)" if generation == "new" else "(TimeMS, MAG)")
    # old CURR holds centi-amps and ThrOut thousandths (int16): the current to 5 mA, the throttle to 5e-4
    _check_common(
        r,
        flight,
        current_atol=1e-5 if generation == "new" else 5e-3,
        throttle_atol=1e-6 if generation == "new" else 5e-4,
    )
    np.testing.assert_allclose(r.stored.offsets_ut, cal["offsets_ut"], atol=1e-5)
    np.testing.assert_allclose(r.stored.matrix, cal["matrix"], atol=1e-6)
    np.testing.assert_allclose(r.stored.motor, cal["motor"], atol=1e-6)
    assert r.stored.motor_kind == "current" and r.stored.orientation == 0
    np.testing.assert_array_equal(r.frame_to_body, np.eye(3))
    # the firmware's field is ArduPilot's formula of that generation, written independently here
    D, O = cal["matrix"], cal["offsets_ut"]  # noqa: E741 - ArduPilot's D and O (matrix, offsets)
    mofs = np.outer(flight["current_a"], cal["motor"])
    m = flight["mag_raw_ut"]
    h = (m + O) @ D.T + mofs if generation == "new" else (m + O + mofs) @ D.T
    np.testing.assert_allclose(r.mag_firmware_ut, h, atol=RAW_ATOL_UT)
    assert "read back to raw from MAG" in r.raw_how


def test_ardupilot_numbered_mag2_of_old_logs(tmp_path):
    flight = simulated_flight(4)
    path = write_dataflash(tmp_path / "mag2.bin", ardupilot_flight_messages(flight, generation="old", instance=1))
    r = read_flight_compass(path, mag_instance=1)
    assert r.instance == 1 and "MAG2" in r.generation
    np.testing.assert_allclose(r.mag_raw_ut, flight["mag_raw_ut"], atol=RAW_ATOL_UT)
    with pytest.raises(LogFormatError, match="compass instances are 1"):
        read_flight_compass(path, mag_instance=0)


def test_ardupilot_second_battery_is_not_mixed_into_the_first(tmp_path):
    flight = simulated_flight(7, n=50)
    messages = ardupilot_flight_messages(flight)
    bat = next(m for m in messages if m["name"] == "BAT")
    second = {**bat, "data": {**bat["data"], "Inst": np.ones(50), "Curr": np.full(50, 99.0)}}
    path = write_dataflash(tmp_path / "two_batteries.bin", messages + [second])
    r = read_flight_compass(path)
    np.testing.assert_allclose(r.current_a, flight["current_a"], atol=1e-5)


def test_px4_log_of_a_flight_reads_back_what_was_written(tmp_path):
    flight = simulated_flight(5)
    _, ulg_path = write_flight_logs(tmp_path, flight)
    r = read_flight_compass(ulg_path)
    cal = flight["stored"]["px4"]
    assert r.firmware == "px4" and r.generation == "PX4 v1.14.0 (sensor_mag)"
    _check_common(r, flight)
    assert r.raw_how.startswith("logged raw")
    np.testing.assert_allclose(r.stored.offsets_ut, cal["offsets_ut"], atol=1e-5)
    np.testing.assert_allclose(r.stored.matrix, cal["matrix"], atol=1e-6)
    np.testing.assert_allclose(r.stored.motor, cal["motor"], atol=1e-6)
    assert r.stored.motor_kind == "current" and r.stored.orientation == 2
    assert r.stored.params["CAL_MAG0_ID"] == 396809
    np.testing.assert_allclose(r.frame_to_body, _rotation_z(90), atol=1e-12)  # ROTATION_YAW_90
    # PX4 Magnetometer::Correct, written independently: R (S ((m + c I) − o)), c in µT per A (xCOMP per kA)
    h = ((flight["mag_raw_ut"] + np.outer(flight["current_a"], cal["motor"])) - cal["offsets_ut"]) @ cal["matrix"].T
    np.testing.assert_allclose(r.mag_firmware_ut, h @ _rotation_z(90).T, atol=RAW_ATOL_UT)


def test_fmtu_names_the_instance_field(tmp_path):
    """A log with FMTU (ArduPilot 3.6 on): the field whose unit is ``#`` numbers the instances, whatever its name;
    its multipliers are not applied (pymavlink applies none), the fields read having fixed units."""
    flight = simulated_flight(8, n=40)
    messages = ardupilot_flight_messages(flight)
    mag = next(m for m in messages if m["name"] == "MAG")
    mag["columns"][1] = "Num"
    mag["data"]["Num"] = mag["data"].pop("I")
    units = "s#" + "G" * 9 + "-"
    mults = "F-" + "C" * 9 + "-"
    fmtu = {
        "name": "FMTU",
        "type": 177,
        "format": "QBNN",
        "columns": ["TimeUS", "FmtType", "UnitIds", "MultIds"],
        "data": {
            "TimeUS": np.zeros(1),
            "FmtType": np.array([mag["type"]]),
            "UnitIds": np.array([units.encode()]),
            "MultIds": np.array([mults.encode()]),
        },
    }
    second = {**mag, "data": {**mag["data"], "Num": np.ones(40), "MagX": mag["data"]["MagX"] + 1000.0}}
    path = write_dataflash(tmp_path / "fmtu.bin", [fmtu] + messages + [second])
    r = read_flight_compass(path)
    assert r.generation.endswith("(TimeUS, MAG with I)")
    np.testing.assert_allclose(r.mag_raw_ut, flight["mag_raw_ut"], atol=RAW_ATOL_UT)
    other = read_flight_compass(path, mag_instance=1)  # the same calibration read back: 1000 mG more on x
    assert len(other.time_s) == 40
    np.testing.assert_allclose(other.mag_firmware_ut[:, 0] - r.mag_firmware_ut[:, 0], 100.0, atol=1e-3)


def test_px4_log_with_vehicle_magnetometer_alone_is_read_back_to_raw(tmp_path):
    """PX4's default profile may log the selected compass only as vehicle_magnetometer (calibrated, body frame):
    read back with the CAL_MAGn_* of its device id, the power compensation taken out."""
    flight = simulated_flight(10, n=80)
    topics, params, info = px4_flight_topics(flight)
    cal = flight["stored"]["px4"]
    mag = topics.pop(0)
    h = ((flight["mag_raw_ut"] + np.outer(flight["current_a"], cal["motor"])) - cal["offsets_ut"]) @ cal["matrix"].T
    h = h @ _rotation_z(90).T / 100.0
    topics.append(
        {
            "name": "vehicle_magnetometer",
            "multi_id": 0,
            "fields": [
                ("uint64_t", "timestamp"),
                ("uint64_t", "timestamp_sample"),
                ("uint32_t", "device_id"),
                ("float[3]", "magnetometer_ga"),
            ],
            "data": {
                "timestamp": mag["data"]["timestamp"],
                "timestamp_sample": mag["data"]["timestamp"],
                "device_id": mag["data"]["device_id"],
                "magnetometer_ga": h,
            },
        }
    )
    path = tmp_path / "vm.ulg"
    path.write_bytes(ulog_bytes(topics, params=params, info=info))
    r = read_flight_compass(path)
    assert r.generation == "PX4 v1.14.0 (vehicle_magnetometer)" and "− c p" in r.raw_how
    np.testing.assert_allclose(r.mag_raw_ut, flight["mag_raw_ut"], atol=RAW_ATOL_UT)
    np.testing.assert_allclose(r.mag_firmware_ut, h * 100.0, atol=RAW_ATOL_UT)


def test_a_message_without_the_field_trical_needs_is_named_not_called_damaged(tmp_path):
    imu = ardupilot_imu(0, np.arange(10) * 5000, np.zeros((10, 3)), np.zeros((10, 3)), 30.0)
    imu["columns"][0] = "Stamp"
    imu["data"]["Stamp"] = imu["data"].pop("TimeUS")
    path = write_dataflash(tmp_path / "odd.bin", [imu])
    with pytest.raises(LogFormatError) as e:
        read_log(path)
    assert "IMU" in str(e.value) and "TimeUS" in str(e.value) and "TimeMS" in str(e.value)
    assert "damaged" not in str(e.value)
    flight = simulated_flight(6, n=20)
    messages = ardupilot_flight_messages(flight)
    mag = next(m for m in messages if m["name"] == "MAG")
    mag["columns"][2] = "FieldX"
    mag["data"]["FieldX"] = mag["data"].pop("MagX")
    path = write_dataflash(tmp_path / "odd_mag.bin", messages)
    with pytest.raises(LogFormatError, match="MAG messages have no MagX field") as e:
        read_flight_compass(path)
    assert "damaged" not in str(e.value)


def test_a_layout_trical_does_not_know_is_a_422_that_calls_the_file_fine(tmp_path):
    flight = simulated_flight(9, n=20)
    messages = ardupilot_flight_messages(flight)
    mag = next(m for m in messages if m["name"] == "MAG")
    mag["format"] = mag["format"][:2] + "N" + mag["format"][3:]  # MagX as text
    mag["data"]["MagX"] = np.array([b"north"] * 20)
    path = write_dataflash(tmp_path / "text_field.bin", messages)
    with pytest.raises(LogFormatError, match="cannot take its messages apart") as e:
        read_flight_compass(path)
    assert "the file itself is fine" in str(e.value) and "damaged" not in str(e.value)


def test_not_a_flight_log_is_refused(tmp_path):
    path = tmp_path / "x.csv"
    path.write_text("a,b\n1,2\n")
    with pytest.raises(LogFormatError, match="not a flight controller's log"):
        read_flight_compass(path)


def test_px4_rotations_come_from_the_one_table_and_a_number_past_25_is_refused_by_name():
    assert all(np.array_equal(px4_rotation(n, "f", "CAL_MAG0_ROT"), px4_matrix(n)) for n in range(26))
    with pytest.raises(LogFormatError, match=r"CAL_MAG0_ROT is 30, .* past ROTATION_PITCH_270 \(25\)"):
        px4_rotation(30, "f", "CAL_MAG0_ROT")
