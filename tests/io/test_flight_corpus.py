"""Real public flight logs of several generations (tests/data/real/flight/README.md), read through trical and
through pymavlink / pyulog directly: the messages and topics present, their counts, the first rows, and the
calibration each firmware stored in the log's parameters."""

from __future__ import annotations

import contextlib
import datetime as dt
import io
from pathlib import Path

import numpy as np
import pytest
from pymavlink import DFReader
from pyulog import ULog
from scipy.spatial.transform import Rotation

from app.calibration.magnetometer.ellipsoid import fit_sphere
from app.io.flight.compass import read_flight_compass
from app.io.flight.context import stored_calibration_parameters
from app.io.readers import read_log
from app.io.readers.read_options import ReadOptions

FLIGHT = Path(__file__).resolve().parents[1] / "data" / "real" / "flight"
LOG171 = FLIGHT / "log171.bin"
PLANE = FLIGHT.parents[1] / "flight_logs" / "test.BIN"
"""pymavlink's test log (tests/data/README.md): ArduPlane V3.8.2-dev, TimeUS with MAG/MAG2/MAG3 named per instance."""
ULOGS = {
    "sample_appended_multiple.ulg": "PX4 v1.6.0 (sensor_combined)",
    "sample_log_small.ulg": "PX4 v1.11.2 (sensor_mag, calibrated)",
    "sample_px4_events.ulg": "PX4 v1.15.0 (sensor_mag)",
    "px4_1.9_esc_status_log.ulg": "PX4 v1.9.0 (vehicle_magnetometer)",
    "px4_1.12_roboto_test.ulg": "PX4 v1.12.3 (sensor_mag)",
}


@pytest.fixture(scope="module")
def mavlink():
    """pymavlink's own reading of log171.bin: its counts, the first message of each type, its PARM values."""
    with contextlib.redirect_stdout(io.StringIO()):
        r = DFReader.DFReader_binary(str(LOG171), zero_time_base=True)
    counts = {r.id_to_name[i]: c for i, c in enumerate(r.counts) if c and i in r.id_to_name}
    first, params, gps_fix = {}, {}, None
    while (m := r.recv_msg()) is not None:
        kind = m.get_type()
        first.setdefault(kind, m)
        if kind == "PARM":
            params[m.Name] = m.Value
        if kind == "GPS" and gps_fix is None and m.Status >= 3:
            gps_fix = m
    return {"counts": counts, "first": first, "params": params, "gps_fix": gps_fix}


def test_log171_of_copter_3_3_reads_as_pymavlink_reads_it(mavlink):
    """Copter 3.3: TimeMS, Temp, IMU2/IMU3 and MAG2/MAG3 as their own messages (the issue's 422 'damaged')."""
    counts, first = mavlink["counts"], mavlink["first"]
    log = read_log(LOG171)
    listed = {(i["sensor"], i["instance"]): i["n_samples"] for i in log.flight.instances}
    for k, name in enumerate(("IMU", "IMU2", "IMU3")):
        assert listed[("acc", k)] == listed[("gyr", k)] == counts[name] == 11916
    for k, name in enumerate(("MAG", "MAG2", "MAG3")):
        assert listed[("mag", k)] == counts[name]
    for k, name in enumerate(("IMU", "IMU2", "IMU3")):
        one = read_log(LOG171, ReadOptions(instance=k))
        m = first[name]
        np.testing.assert_allclose(one.acc[0], [m.AccX, m.AccY, m.AccZ], rtol=0, atol=1e-6)
        np.testing.assert_allclose(one.gyr[0], [m.GyrX, m.GyrY, m.GyrZ], rtol=0, atol=1e-7)
        assert one.temperature_c[0] == pytest.approx(m.Temp, abs=1e-5)
        assert one.n_samples == 11916
    mags = read_log(LOG171, ReadOptions(clock="mag", mag_instance=1))
    assert mags.flight.mag == {"instance": 1, "source": "MAG"}


def test_log171_compass_context_against_pymavlink(mavlink):
    first, params = mavlink["first"], mavlink["params"]
    r = read_flight_compass(LOG171, mag_instance=1)
    m = first["MAG2"]
    assert r.generation == "ArduPilot Copter V3.3-dev (TimeMS, MAG2)"
    assert len(r.time_s) == mavlink["counts"]["MAG2"] and r.time_s[0] == pytest.approx(m.TimeMS * 1e-3, abs=1e-9)
    np.testing.assert_allclose(r.mag_firmware_ut[0], np.array([m.MagX, m.MagY, m.MagZ]) * 0.1, rtol=0, atol=1e-9)
    # the stored calibration, as ArduPilot means it (COMPASS_OFS2 added, mG)
    np.testing.assert_allclose(r.stored.offsets_ut, [params[f"COMPASS_OFS2_{a}"] * 0.1 for a in "XYZ"], atol=1e-6)
    d = [params[f"COMPASS_DIA2_{a}"] for a in "XYZ"]
    o = [params[f"COMPASS_ODI2_{a}"] for a in "XYZ"]
    np.testing.assert_allclose(r.stored.matrix, [[d[0], o[0], o[1]], [o[0], d[1], o[2]], [o[1], o[2], d[2]]], atol=1e-7)
    assert r.stored.motor_kind is None and r.stored.orientation == 0
    # raw read back: D (m + O) is the logged field (no motor offset in this log: COMPASS_MOTCT 0)
    np.testing.assert_allclose((r.mag_raw_ut + r.stored.offsets_ut) @ r.stored.matrix.T, r.mag_firmware_ut, atol=1e-9)
    att = first["ATT"]
    expected = Rotation.from_euler("ZYX", [att.Yaw, att.Pitch, att.Roll], degrees=True).as_matrix()
    np.testing.assert_allclose(r.attitude_c_nb[0], expected, atol=1e-9)
    assert r.attitude_time_s[0] == pytest.approx(att.TimeMS * 1e-3)
    cur = first["CURR"]  # Copter 3.3 logs the current in centi-amps (current_amps * 100, int16)
    assert r.current_a[0] == pytest.approx(cur.Curr / 100.0) and r.power_time_s[0] == pytest.approx(cur.TimeMS * 1e-3)
    assert r.current_a.max() == pytest.approx(27.44)
    ctun = first["CTUN"]
    assert (
        r.throttle.min() >= 0
        and r.throttle.max() <= 1
        and r.throttle[0] == pytest.approx(ctun.ThrOut / 1000.0, abs=1e-3)
    )
    fix = mavlink["gps_fix"]
    assert (r.latitude_deg, r.longitude_deg, r.altitude_m) == pytest.approx((fix.Lat, fix.Lng, fix.Alt), abs=1e-9)
    gps = dt.datetime(1980, 1, 6, tzinfo=dt.UTC) + dt.timedelta(weeks=fix.Week, milliseconds=fix.TimeMS)
    assert r.utc == gps - dt.timedelta(seconds=17)  # GPS − UTC was 17 s from July 2015 to the end of 2016
    assert r.utc.date() == dt.date(2015, 11, 21)


def test_log171_stored_offsets_agree_with_a_sphere_fit_of_the_raw_mag2():
    """The issue's claim: the firmware's offsets of MAG2 agree with a sphere fit of the readings read back to raw.
    With its stored DIA2/ODI2 applied (h − D O = D m), the sphere's centre gives the offsets within 0.2 µT; a
    sphere fitted to the raw readings alone leaves 2.2 µT (the soft iron, DIA2 0.95–1.05, is not a sphere's)."""
    r = read_flight_compass(LOG171, mag_instance=1)
    D = r.stored.matrix
    _, centre = fit_sphere(r.mag_raw_ut @ D.T)
    offsets_fit = -np.linalg.solve(D, centre)
    assert np.abs(offsets_fit - r.stored.offsets_ut).max() < 0.2
    _, raw_centre = fit_sphere(r.mag_raw_ut)
    assert 1.0 < np.abs(-raw_centre - r.stored.offsets_ut).max() < 3.0


def test_plane_3_8_of_timeus_with_numbered_compasses_against_pymavlink():
    with contextlib.redirect_stdout(io.StringIO()):
        reader = DFReader.DFReader_binary(str(PLANE), zero_time_base=True)
        first = {}
        while (m := reader.recv_msg()) is not None:
            first.setdefault(m.get_type(), m)
    r = read_flight_compass(PLANE, mag_instance=1)
    assert r.generation == "ArduPilot ArduPlane V3.8.2-dev (TimeUS, MAG2)"
    m = first["MAG2"]
    assert r.time_s[0] == pytest.approx(m.TimeUS * 1e-6, abs=1e-9)
    np.testing.assert_allclose(r.mag_firmware_ut[0], np.array([m.MagX, m.MagY, m.MagZ]) * 0.1, atol=1e-9)
    np.testing.assert_allclose(
        (r.mag_raw_ut[0] + r.stored.offsets_ut + np.array([m.MOfsX, m.MOfsY, m.MOfsZ]) * 0.1) @ r.stored.matrix.T,
        r.mag_firmware_ut[0],
        atol=1e-9,
    )
    bat, ctun = first["BAT"], first["CTUN"]
    assert r.current_a.max() == pytest.approx(1.166, abs=1e-6) and "BAT.Curr" in r.power_source
    assert "Plane, percent" in r.power_source and r.throttle[0] == pytest.approx(ctun.ThrOut / 100.0)
    assert bat.Curr >= 0
    assert r.utc.year == 2017 and r.latitude_deg == pytest.approx(-35.3626277)


@pytest.mark.parametrize("name", sorted(ULOGS))
def test_ulog_corpus_reads_as_pyulog_reads_it(name):
    path = FLIGHT / name
    with contextlib.redirect_stdout(io.StringIO()):
        u = ULog(str(path))
    data = {(d.name, d.multi_id): d.data for d in u.data_list}
    r = read_flight_compass(path)
    assert r.generation == ULOGS[name]
    if ("sensor_mag", 0) in data:
        mag = data[("sensor_mag", 0)]
        assert len(r.time_s) == len(mag["timestamp"])
        np.testing.assert_allclose(r.time_s[0], mag["timestamp_sample"][0] * 1e-6, atol=1e-9)
        logged = np.array([mag[a][0] for a in "xyz"]) * 100.0
        if "calibrated" in r.generation:  # before PX4 1.12: the driver's calibration, S (m − o)
            np.testing.assert_allclose((r.mag_raw_ut[0] - r.stored.offsets_ut) @ r.stored.matrix.T, logged, atol=1e-4)
        else:
            np.testing.assert_allclose(r.mag_raw_ut[0], logged, atol=1e-5)
        listed = {i["instance"]: i["n_samples"] for i in read_log(path).flight.instances if i["sensor"] == "mag"}
        assert listed == {k: len(d["timestamp"]) for (t, k), d in data.items() if t == "sensor_mag"}
    else:
        combined = data[("sensor_combined", 0)]
        if "magnetometer_ga[0]" in combined:  # PX4 ≤ 1.8: the compass inside sensor_combined
            rel = combined["magnetometer_timestamp_relative"].astype(np.int64)
            t = combined["timestamp"].astype(np.int64) + rel
            ok = rel != 0x7FFFFFFF
            assert len(r.time_s) == len(np.unique(t[ok]))
            first = np.array([combined[f"magnetometer_ga[{k}]"][ok][0] for k in range(3)]) * 100.0
        else:  # PX4 1.9–1.11's default profile: only vehicle_magnetometer, the selected compass
            vm = data[("vehicle_magnetometer", 0)]
            assert len(r.time_s) == len(vm["timestamp"])
            first = np.array([vm[f"magnetometer_ga[{k}]"][0] for k in range(3)]) * 100.0
        np.testing.assert_allclose(r.mag_firmware_ut[0], first, atol=1e-5)
        # the recording lists that compass, as the flight's compass reads it
        listed = {i["instance"]: i["n_samples"] for i in read_log(path).flight.instances if i["sensor"] == "mag"}
        assert listed == {0: len(r.time_s)}
        # read back: R S (m − o) is the logged field
        back = (r.mag_raw_ut - r.stored.offsets_ut) @ r.stored.matrix.T @ r.frame_to_body.T
        np.testing.assert_allclose(back, r.mag_firmware_ut, atol=1e-4)
    att = data[("vehicle_attitude", 0)]
    q = np.array([att[f"q[{k}]"][0] for k in range(4)])
    expected = Rotation.from_quat([q[1], q[2], q[3], q[0]]).as_matrix()  # scipy: x, y, z, w
    np.testing.assert_allclose(r.attitude_c_nb[0], expected, atol=1e-6)
    assert len(r.attitude_time_s) == len(att["timestamp"])
    # the stored calibration matched by device id, as PX4 means it (offsets subtracted, gauss)
    values = u.initial_parameters
    slot = next(
        n
        for n in range(4)
        if f"CAL_MAG{n}_XOFF" in values
        and np.allclose(r.stored.offsets_ut, [values[f"CAL_MAG{n}_{a}OFF"] * 100 for a in "XYZ"])
    )
    assert r.stored.params[f"CAL_MAG{slot}_ID"] == values[f"CAL_MAG{slot}_ID"]
    np.testing.assert_allclose(np.diag(r.stored.matrix), [values[f"CAL_MAG{slot}_{a}SCALE"] for a in "XYZ"])


def test_ulog_context_of_the_newest_generation():
    """PX4 1.15 SITL: vehicle_thrust_setpoint for the throttle, sensor_gps/vehicle_gps_position in degrees as
    doubles, no current sensor (current_a −1)."""
    r = read_flight_compass(FLIGHT / "sample_px4_events.ulg")
    assert r.current_a is None and r.throttle is not None and "vehicle_thrust_setpoint" in r.power_source
    assert (r.latitude_deg, r.longitude_deg) == pytest.approx((47.3977418, 8.5455939), abs=1e-7)
    assert r.utc.year == 2024
    assert any("vehicle_magnetometer by" in n for n in r.notes)


def test_px4_1_11_sensor_mag_is_calibrated_as_vehicle_magnetometer_shows():
    """PX4 1.11's drivers calibrated sensor_mag: the selected external compass (CAL_MAG1_ROT 0) turned into the
    body frame is vehicle_magnetometer to 0.1 µT, which PX4's raw formula would miss by the offsets (55 µT)."""
    r = read_flight_compass(FLIGHT / "sample_log_small.ulg", mag_instance=1)
    note = next(n for n in r.notes if "vehicle_magnetometer by" in n)
    assert float(note.split(" by ")[1].split(" µT")[0]) < 0.1
    assert r.latitude_deg == pytest.approx(63.4170622) and r.utc.year == 2021


def _pymavlink_params(path):
    out = {}
    with contextlib.redirect_stdout(io.StringIO()):
        r = DFReader.DFReader_binary(str(path), zero_time_base=True)
        while (m := r.recv_match(type="PARM")) is not None:
            out[m.Name] = m.Value
    return out


@pytest.mark.parametrize("name", ["log171.bin"] + sorted(ULOGS))
def test_stored_calibration_parameters_as_the_libraries_read_them(name):
    path = FLIGHT / name
    ours = stored_calibration_parameters(path)
    if name.endswith(".bin"):
        theirs = _pymavlink_params(path)
        wanted = [f"COMPASS_OFS{k}_{a}" for k in ("", "2", "3") for a in "XYZ"] + [
            f"INS_ACC{k}OFFS_{a}" for k in ("", "2", "3") for a in "XYZ"
        ]
    else:
        with contextlib.redirect_stdout(io.StringIO()):
            theirs = ULog(str(path), message_name_filter_list=[]).initial_parameters
        wanted = [k for k in theirs if k.startswith(("CAL_ACC", "CAL_MAG"))]
    assert wanted and all(k in ours for k in wanted)
    for k in wanted:
        assert ours[k] == pytest.approx(theirs[k], abs=1e-12), k


def test_a_ulog_is_parsed_once_for_the_upload_and_the_compass_and_again_when_it_changes(tmp_path):
    """The upload's reading and the compass from the flight share pyulog's parse of the same file (a 100 MB log takes
    seconds, bench/flight_compass_speed.py); a file rewritten in place is parsed afresh."""
    import shutil

    from app.io.flight import ulog

    path = tmp_path / "flight.ulg"
    shutil.copy(FLIGHT / "sample_log_small.ulg", path)
    ulog._parsed.cache_clear()
    read_log(path)
    read_flight_compass(path, mag_instance=1)
    assert (ulog._parsed.cache_info().hits, ulog._parsed.cache_info().misses) == (1, 1)
    shutil.copy(FLIGHT / "px4_1.9_esc_status_log.ulg", path)
    assert read_flight_compass(path).generation == "PX4 v1.9.0 (vehicle_magnetometer)"
    assert ulog._parsed.cache_info().misses == 2


NEWER_ARDUPILOT = {
    "arduplane_4.2_center_0003.bin": ("ArduPilot ArduPlane V4.2.3 (TimeUS, MAG with I)", {0: 465}, False),
    "arduplane_4.2_pilot_0004.bin": ("ArduPilot ArduPlane V4.2.3 (TimeUS, MAG with I)", {0: 979}, False),
    "arducopter_4.6_backend_log_80k.bin": ("ArduPilot ArduCopter V4.6.2 (TimeUS, MAG with I)", {0: 4, 1: 4}, True),
    "ardusub_4.1_small.bin": ("ArduPilot ArduSub V4.1.0 (TimeUS, MAG with I)", {0: 237, 1: 237}, True),
}
"""Real ArduPilot 4.x logs (tests/data/real/flight/README.md): two ArduPlane 4.2.3 logs with minimal logging (no
IMU message), an ArduCopter 4.6.2 log cut short after its parameters, two compasses of four rows each, and an
ArduSub 4.1.0 dive of two compasses and no GPS."""


@pytest.mark.parametrize("name", sorted(NEWER_ARDUPILOT))
def test_ardupilot_4_logs_read_as_pymavlink_reads_them(name):
    generation, rows, has_imu = NEWER_ARDUPILOT[name]
    path = FLIGHT / name
    with contextlib.redirect_stdout(io.StringIO()):
        reader = DFReader.DFReader_binary(str(path), zero_time_base=True)
        mags: dict[int, list] = {}
        kinds = set()
        while (m := reader.recv_msg()) is not None:
            kinds.add(m.get_type())
            if m.get_type() == "MAG":
                mags.setdefault(m.I, []).append(m)
    assert {k: len(v) for k, v in mags.items()} == rows and ("IMU" in kinds) == has_imu
    for instance, messages in mags.items():
        r = read_flight_compass(path, mag_instance=instance)
        assert r.generation == generation and len(r.time_s) == rows[instance]
        first = messages[0]
        np.testing.assert_allclose(r.mag_firmware_ut[0], np.array([first.MagX, first.MagY, first.MagZ]) * 0.1)
    log = read_log(path)
    if has_imu:
        assert log.acc is not None and log.flight.imu
    else:  # a minimal log is its compass alone, on the compass's clock
        assert log.acc is None and log.channels == ["mag"] and log.flight.imu == {}
        assert any(n.startswith("the log holds no IMU samples: read for what needs none") for n in log.notes)


def test_copter_3_5_with_numbered_compass_messages_reads_as_pymavlink_reads_it():
    """The real ArduCopter 3.5 landing (spark404/dataflashlog's test log): MAG and MAG2 as their own messages, 503
    rows each, read with pymavlink's first field (mG) as trical's first (µT), and its IMU messages read too."""
    path = FLIGHT / "arducopter_3.5_rtl_landing_dataflashlog.bin"
    with contextlib.redirect_stdout(io.StringIO()):
        reader = DFReader.DFReader_binary(str(path), zero_time_base=True)
        mags: dict[str, list] = {"MAG": [], "MAG2": []}
        while (m := reader.recv_match(type=list(mags))) is not None:
            mags[m.get_type()].append(m)
    for instance, name in enumerate(mags):
        r = read_flight_compass(path, mag_instance=instance)
        assert r.generation == f"ArduPilot (TimeUS, {name})" and len(r.time_s) == len(mags[name]) == 503
        first = mags[name][0]
        np.testing.assert_allclose(r.mag_firmware_ut[0], np.array([first.MagX, first.MagY, first.MagZ]) * 0.1)
    log = read_log(path)
    assert log.acc is not None and log.flight.imu
