"""PX4 ULog and ArduPilot DataFlash readers: the public sample logs against the tools' own dumps, and logs
written with known content (tests/flight_logs.py)."""

from __future__ import annotations

import csv
import io
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.flight.instances import decode_device_id
from app.io.readers import read_log
from app.io.readers.read_options import ReadOptions
from tests.flight_logs import (
    GYR_BIAS,
    TRUTH,
    ardupilot_batch,
    ardupilot_file,
    ardupilot_imu,
    compass_tumble,
    imu_instances,
    px4_file,
    still_board,
    write_dataflash,
)

DATA = Path(__file__).resolve().parents[1] / "data" / "flight_logs"
ULOG = DATA / "sample_log_small.ulg"
BIN = DATA / "test.BIN"
BIN_DIR = Path(sys.executable).parent


def _csv_rows(text: str) -> list[dict]:
    return list(csv.DictReader(io.StringIO(text)))


@pytest.fixture(scope="module")
def ulog2csv(tmp_path_factory):
    """pyulog's own dump of the sample, as a process."""
    out = tmp_path_factory.mktemp("ulog2csv")
    subprocess.run(
        [
            str(BIN_DIR / "ulog2csv"),
            "-m",
            "sensor_accel,sensor_gyro,sensor_mag,sensor_combined",
            "-o",
            str(out),
            str(ULOG),
        ],
        check=True,
        capture_output=True,
        timeout=120,
    )
    return {p.stem.replace("sample_log_small_", ""): _csv_rows(p.read_text()) for p in out.glob("*.csv")}


def _mavlogdump(kind: str) -> list[dict]:
    r = subprocess.run(
        [sys.executable, str(BIN_DIR / "mavlogdump.py"), "--format", "csv", "--types", kind, str(BIN)],
        check=True,
        capture_output=True,
        text=True,
        timeout=120,
    )
    return _csv_rows(r.stdout)


def test_ulog_sample_reads_as_ulog2csv_prints(ulog2csv):
    dump = ulog2csv["sensor_accel_1"]
    log = read_log(ULOG, ReadOptions(instance=1))
    assert log.format == "ulog" and log.flight.imu == {
        "instance": 1,
        "source": "sensor_accel",
        "gyr_source": "sensor_gyro",
    }
    assert log.n_samples == len(dump) == 6
    first = dump[0]
    np.testing.assert_allclose(log.acc[0], [float(first[a]) for a in "xyz"], rtol=0, atol=1e-6)
    np.testing.assert_allclose(log.temperature_c, [float(r["temperature"]) for r in dump], rtol=0, atol=1e-5)
    gyr = ulog2csv["sensor_gyro_1"]
    # the gyroscope on the accelerometer's sample times: both stamped at nearly the same instants here
    t_acc = np.array([int(r["timestamp_sample"]) for r in dump], dtype=float)
    t_gyr = np.array([int(r["timestamp_sample"]) for r in gyr], dtype=float)
    expected = np.interp(t_acc, t_gyr, [float(r["x"]) for r in gyr])
    np.testing.assert_allclose(log.gyr[:, 0], expected, rtol=0, atol=1e-6)
    np.testing.assert_allclose(log.time_s, (t_acc - t_acc[0]) * 1e-6, rtol=0, atol=1e-9)
    rows = {(i["sensor"], i["source"], i["instance"]): i for i in log.flight.to_dict()["instances"]}
    for k in range(3):
        accel = ulog2csv[f"sensor_accel_{k}"]
        row = rows[("acc", "sensor_accel", k)]
        assert row["n_samples"] == len(accel)
        assert row["device_id"] == int(accel[-1]["device_id"])
        temps = [float(r["temperature"]) for r in accel]
        assert row["temperature_min_c"] == pytest.approx(min(temps), abs=1e-5)
        assert row["temperature_max_c"] == pytest.approx(max(temps), abs=1e-5)
    assert rows[("acc", "sensor_combined", 0)]["n_samples"] == len(ulog2csv["sensor_combined_0"]) == 1298
    assert rows[("acc", "sensor_accel", 1)]["device"] == {"bus_type": "spi", "bus": 4, "address": 0, "devtype": 56}


def test_ulog_sample_compass_in_microtesla(ulog2csv):
    dump = ulog2csv["sensor_mag_1"]
    log = read_log(ULOG, ReadOptions(mag_instance=1, clock="mag"))
    assert log.units["mag"] == "uT" and log.flight.mag == {"instance": 1, "source": "sensor_mag"}
    # the compass's samples inside the span of the IMU read (sensor_combined: its accelerometer's times are the
    # message's plus accelerometer_timestamp_relative, its gyroscope's the message's), in µT: gauss × 100
    combined = ulog2csv["sensor_combined_0"]
    t_gyr = np.array([int(r["timestamp"]) for r in combined])
    t_acc = t_gyr + np.array([int(r["accelerometer_timestamp_relative"]) for r in combined])
    t_mag = np.array([int(r["timestamp_sample"]) for r in dump])
    inside = (t_mag >= max(t_acc[0], t_gyr[0])) & (t_mag <= min(t_acc[-1], t_gyr[-1]))
    gauss = np.array([[float(r[a]) for a in "xyz"] for r in dump])
    assert log.n_samples == inside.sum() >= 5
    np.testing.assert_allclose(log.mag, 100.0 * gauss[inside], rtol=0, atol=1e-4)
    assert log.temperature_c is None  # this compass logs no temperature (nan)


def test_ulog_sample_defaults_to_sensor_combined_and_says_so(ulog2csv):
    log = read_log(ULOG)
    dump = ulog2csv["sensor_combined_0"]
    assert log.flight.imu["source"] == "sensor_combined" and log.n_samples == len(dump)
    first = dump[0]
    np.testing.assert_allclose(log.acc[0], [float(first[f"accelerometer_m_s2[{k}]"]) for k in range(3)], atol=1e-6)
    np.testing.assert_allclose(log.gyr[0], [float(first[f"gyro_rad[{k}]"]) for k in range(3)], atol=1e-6)
    assert any("sensor_combined" in n and "already calibrated by PX4" in n for n in log.notes)
    assert log.temperature_c is None


def test_dataflash_sample_reads_as_mavlogdump_prints():
    dump = _mavlogdump("IMU2")
    log = read_log(BIN, ReadOptions(instance=1))
    assert log.format == "dataflash" and log.n_samples == len(dump) == 45
    np.testing.assert_allclose(log.acc, [[float(r[f"Acc{a}"]) for a in "XYZ"] for r in dump], rtol=0, atol=1e-6)
    np.testing.assert_allclose(log.gyr, [[float(r[f"Gyr{a}"]) for a in "XYZ"] for r in dump], rtol=0, atol=1e-6)
    np.testing.assert_allclose(log.temperature_c, [float(r["T"]) for r in dump], rtol=0, atol=1e-5)
    t = np.array([int(r["TimeUS"]) for r in dump])
    np.testing.assert_allclose(log.time_s, (t - t[0]) * 1e-6, atol=1e-9)
    mag3 = _mavlogdump("MAG3")
    compass = read_log(BIN, ReadOptions(mag_instance=2, clock="mag"))
    assert compass.flight.mag == {"instance": 2, "source": "MAG"}
    milligauss = np.array([[float(r[f"Mag{a}"]) for a in "XYZ"] for r in mag3])
    t_mag = np.array([int(r["TimeUS"]) for r in mag3])
    inside = (t_mag >= t[0]) & (t_mag <= t[-1])
    np.testing.assert_allclose(compass.mag, 0.1 * milligauss[inside], rtol=0, atol=1e-9)
    rows = {(i["sensor"], i["instance"]): i for i in log.flight.to_dict()["instances"]}
    assert rows[("mag", 2)]["n_samples"] == len(mag3) == 8
    assert rows[("acc", 0)]["n_samples"] == len(_mavlogdump("IMU")) == 45


@pytest.mark.parametrize(
    "path, option, words",
    [
        (ULOG, {"instance": 3}, "has no IMU instance 3: its IMU instances are 0, 1, 2"),
        (ULOG, {"mag_instance": 2}, "has no magnetometer instance 2: its magnetometer instances are 0, 1"),
        (BIN, {"instance": 2}, "has no IMU instance 2: its IMU instances are 0, 1"),
        (BIN, {"mag_instance": 5}, "its magnetometer instances are 0, 1, 2"),
    ],
)
def test_an_instance_the_log_lacks_is_refused_naming_those_it_has(path, option, words):
    with pytest.raises(LogFormatError, match=words):
        read_log(path, ReadOptions(**option))


def test_text_options_are_refused_for_flight_logs(tmp_path):
    with pytest.raises(LogFormatError, match="chip is for text logs"):
        read_log(BIN, ReadOptions(chip="mpu6050-2g"))
    with pytest.raises(LogFormatError, match="units is for text logs"):
        read_log(ULOG, ReadOptions(units={"acc": "g"}))
    assert (
        read_log(ULOG, ReadOptions(units={"acc": "m/s^2"}, instance=0)).units["acc"] == "m/s^2"
    )  # the format's own unit
    csv_path = tmp_path / "still.csv"
    csv_path.write_text("t,ax,ay,az\n" + "".join(f"{i / 100},0,0,9.81\n" for i in range(100)))
    with pytest.raises(LogFormatError, match="instance and mag_instance choose a sensor of a flight"):
        read_log(csv_path, ReadOptions(instance=0))


def test_dataflash_is_read_by_its_magic_whatever_its_suffix(tmp_path):
    # .bin is also GENEActiv's suffix (read through actipy): the first bytes decide
    copy = tmp_path / "00000042.BIN"
    copy.write_bytes(BIN.read_bytes())
    assert read_log(copy).format == "dataflash"
    renamed = tmp_path / "flight.dat"
    renamed.write_bytes(ULOG.read_bytes())
    assert read_log(renamed, ReadOptions(instance=2)).format == "ulog"


@pytest.mark.parametrize("cut", [20, 300, 2000])
def test_a_ulog_cut_before_its_data_is_refused_naming_the_problem(tmp_path, cut):
    path = tmp_path / "cut.ulg"
    path.write_bytes(ULOG.read_bytes()[:cut])
    with pytest.raises(LogFormatError, match="PX4 ULog") as info:
        read_log(path)
    assert "cut short" in str(info.value) or "damaged" in str(info.value)


def test_a_damaged_ulog_header_is_refused(tmp_path):
    data = bytearray(ULOG.read_bytes()[:5000])
    data[7] = 0xFF  # a version pyulog does not know
    data[16:19] = b"\xff\xff\x42"  # the flag-bits message ("B") claiming 65535 bytes, past the file's end
    path = tmp_path / "bad.ulg"
    path.write_bytes(bytes(data))
    with pytest.raises(LogFormatError, match="PX4 ULog"):
        read_log(path)


@pytest.mark.parametrize("cut", [3, 200, 4000])
def test_a_dataflash_log_cut_before_its_samples_is_refused(tmp_path, cut):
    path = tmp_path / "cut.bin"
    path.write_bytes(BIN.read_bytes()[:cut])
    with pytest.raises(LogFormatError, match="DataFlash log"):
        read_log(path)


def test_a_dataflash_log_cut_in_its_data_reads_up_to_the_cut(tmp_path):
    data = BIN.read_bytes()
    path = tmp_path / "cut.bin"
    path.write_bytes(data[: len(data) - 37])  # through the middle of a message
    log = read_log(path, ReadOptions(instance=1))
    assert 40 <= log.n_samples <= 45 and np.isfinite(log.acc).all()


def test_px4_gyroscope_is_interpolated_onto_the_accelerometer_times(tmp_path):
    imus = imu_instances(2)
    ramp = np.linspace(-1.0, 1.0, len(imus[0]["gyr"]))
    imus[0]["gyr"] = np.column_stack([ramp, 2 * ramp, -ramp])
    log = read_log(px4_file(tmp_path / "lag.ulg", imus, gyro_lag_us=1000), ReadOptions(instance=0))
    # The gyroscope is stamped 1 ms (0.2 sample at 200 Hz) after the accelerometer: the first accelerometer
    # sample precedes every gyroscope sample and is left out; sample i then reads the ramp at i − 0.2.
    n = log.n_samples
    assert n == len(ramp) - 1
    expected = ramp[1 : 1 + n] - 0.2 * (ramp[1] - ramp[0])
    np.testing.assert_allclose(log.gyr, np.column_stack([expected, 2 * expected, -expected]), atol=1e-6)
    np.testing.assert_allclose(log.acc, imus[0]["acc"][1 : 1 + n], atol=2e-6)
    np.testing.assert_allclose(log.temperature_c, imus[0]["temperature"][1 : 1 + n], atol=2e-6)


def test_dataflash_batch_sampler_at_full_rate_with_the_imu_temperature(tmp_path):
    imus = still_board(4, rate_hz=50.0, duration_s=4.0)
    n = 4 * 1000
    t_batch = (1_000_000 + np.arange(n) * 1000).astype(np.uint64)
    acc = np.tile([0.0, 0.0, -9.80665], (n, 1))
    temps = np.linspace(35.0, 36.0, len(imus[1]["time_us"]))
    messages = [
        ardupilot_imu(k, imu["time_us"], imu["acc"], imu["gyr"], temps if k else imu["temperature"])
        for k, imu in enumerate(imus)
    ]
    messages += [ardupilot_batch("ACC", 1, t_batch, acc), ardupilot_batch("GYR", 1, t_batch, np.zeros((n, 3)))]
    log = read_log(write_dataflash(tmp_path / "batch.bin", messages), ReadOptions(instance=1))
    assert log.flight.imu == {"instance": 1, "source": "ACC", "gyr_source": "GYR"}
    assert log.sampling_rate_hz == pytest.approx(1000.0, rel=1e-9) and log.n_samples == n
    t_imu = imus[1]["time_us"].astype(float)
    np.testing.assert_allclose(log.temperature_c, np.interp(t_batch.astype(float), t_imu, temps), atol=1e-6)
    assert read_log(tmp_path / "batch.bin", ReadOptions(instance=0)).flight.imu["source"] == "IMU"


def test_older_dataflash_names_instances_mag2(tmp_path):
    imus, mags, _ = compass_tumble(3, duration_s=4.0)
    path = ardupilot_file(tmp_path / "old.bin", imus, mags, numbered_mags=True)
    log = read_log(path, ReadOptions(mag_instance=1, clock="mag"))
    np.testing.assert_allclose(log.mag, np.round(mags[1]["mag"] * 10.0) / 10.0, atol=1e-9)
    assert log.sampling_rate_hz == pytest.approx(50.0, rel=1e-9)


def test_the_two_imu_instances_are_their_own(tmp_path):
    imus = imu_instances(6)
    for write in (px4_file, ardupilot_file):
        path = write(tmp_path / f"six.{write.__name__}", imus)
        for k in (0, 1):
            log = read_log(path, ReadOptions(instance=k))
            n = log.n_samples  # PX4's gyroscope is stamped after the first accelerometer sample: that one is left out
            assert n == len(imus[k]["acc"]) - (write is px4_file)
            np.testing.assert_allclose(log.acc, imus[k]["acc"][-n:], atol=2e-6)
            np.testing.assert_allclose(log.temperature_c, imus[k]["temperature"][-n:], atol=2e-6)
            assert log.flight.imu["instance"] == k
        assert not np.allclose(TRUTH[0][1], TRUTH[1][1]) and not np.allclose(GYR_BIAS[0], GYR_BIAS[1])


def test_device_id_decodes_as_the_firmwares_pack_it():
    # 2424842 = 0x25000A: bus type 2 (SPI), bus 1, address 0, device type 0x25 (the sample log's instance 0)
    assert decode_device_id(2424842) == {"bus_type": "spi", "bus": 1, "address": 0, "devtype": 37}
    assert decode_device_id(0) is None
