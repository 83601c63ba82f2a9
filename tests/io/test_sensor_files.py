"""One recording in several files, one per sensor (issue 31, point 3): told from pose files by the files
themselves, merged onto one clock, each file's gaps kept, each sensor's unit decided on its own file.

The real set is an iPhone's (tests/data/real/corpus/iphone_heading_per_sensor_files: accelerometer.csv in g,
gyroscope.csv in rad/s, magnetometer.csv, each with an epoch time column); the gaps are a seeded simulation.
"""

from __future__ import annotations

import zipfile

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.readers import read_log
from app.io.readers.read_options import ReadOptions
from app.io.readers.sensor_files import per_sensor_files, sensor_from_name
from tests.conftest import DATA

IPHONE = DATA / "real" / "corpus" / "iphone_heading_per_sensor_files"
FILES = ("accelerometer.csv", "gyroscope.csv", "magnetometer.csv")


def zipped(tmp_path, files: dict[str, bytes]):
    path = tmp_path / "rec.zip"
    with zipfile.ZipFile(path, "w") as zf:
        for name, data in files.items():
            zf.writestr(name, data)
    return path


@pytest.mark.parametrize(
    "name, sensor",
    [
        ("accelerometer.csv", "acc"),
        ("Accelerometer.csv", "acc"),
        ("acc.csv", "acc"),
        ("imu_accel_2024.txt", "acc"),
        ("TotalAcceleration.csv", "acc"),
        ("gyroscope.csv", "gyr"),
        ("Gyroscope.csv", "gyr"),
        ("gyro.csv", "gyr"),
        ("GyroscopeUncalibrated.csv", "gyr"),
        ("mag.csv", "mag"),
        ("compass_log.csv", "mag"),
        ("hmc5883l.csv", "mag"),
        ("qmc5883.csv", "mag"),
        ("ak8963.csv", "mag"),
        ("MagnetometerUncalibrated.csv", "mag"),
        ("x_axis_pos.csv", None),
        ("data.csv", None),
        ("acc_gyro.csv", None),
        ("image.csv", None),
        ("package.csv", None),
    ],
)
def test_a_file_name_names_one_sensor_or_none(name, sensor):
    assert sensor_from_name(name) == sensor


def test_pose_files_are_not_per_sensor_files():
    assert per_sensor_files(["x_axis_pos.csv", "x_axis_neg.csv"]) is None
    assert per_sensor_files(["acc_1.csv", "acc_2.csv"]) is None  # one sensor twice: poses (or parts)
    assert per_sensor_files(["accelerometer.csv"]) is None
    assert per_sensor_files(list(FILES)) == dict(zip(FILES, ("acc", "gyr", "mag")))


def test_the_real_iphone_files_are_one_recording_on_the_accelerometers_clock(tmp_path):
    log = read_log(zipped(tmp_path, {f: (IPHONE / f).read_bytes() for f in FILES}), name="rec.zip")
    assert log.channels == ["acc", "gyr", "mag"]
    assert log.units == {"acc": "g", "gyr": "rad/s", "mag": "raw"}  # each decided on its own file
    # The accelerometer's 1500 samples (103 Hz), less those before the gyroscope's first sample (78 ms later)
    # and after the magnetometer's and the gyroscope's last.
    assert log.n_samples == 1490
    assert log.sampling_rate_hz == pytest.approx(102.9, abs=0.1)
    assert log.notes[0].startswith("one recording in 3 files, one per sensor: accelerometer.csv the accelerometer (g)")
    assert "merged on the clock of accelerometer.csv (the accelerometer's" in log.notes[1]
    assert "10 of the 1500 samples of accelerometer.csv left out" in log.notes[2]
    # The gyroscope interpolated at the accelerometer's times, on the epoch clock the files share.
    gyr = np.genfromtxt(IPHONE / "gyroscope.csv", delimiter=";", skip_header=1)
    acc = np.genfromtxt(IPHONE / "accelerometer.csv", delimiter=";", skip_header=1)
    first = int(np.flatnonzero(acc[:, 0] >= gyr[0, 0])[0])
    assert first == 9
    expected = [np.interp(acc[first, 0], gyr[:, 0], gyr[:, k]) for k in (1, 2, 3)]
    assert log.gyr[0] == pytest.approx(expected, abs=1e-6)
    assert log.acc[0] == pytest.approx(acc[first, 1:4], abs=1e-12)


def _stream(rng, start_s, rate_hz, n, value, noise, gap_at=None, gap_s=0.0):
    t = start_s + np.arange(n) / rate_hz
    if gap_at is not None:
        t[gap_at:] += gap_s
    v = np.asarray(value) + noise * rng.standard_normal((n, 3))
    return t, v


def _csv(header, t, v) -> bytes:
    rows = [header] + [f"{a:.6f},{x:.6f},{y:.6f},{z:.6f}" for a, (x, y, z) in zip(t, v)]
    return ("\n".join(rows) + "\n").encode()


def test_a_gap_in_the_gyroscopes_file_is_not_interpolated_across(tmp_path):
    rng = np.random.default_rng(31)
    ta, va = _stream(rng, 100.0, 100.0, 2000, [0, 0, 1.0], 0.002)  # 20 s in g
    tg, vg = _stream(rng, 100.013, 200.0, 4000, [0.01, -0.02, 0.005], 0.001, gap_at=2000, gap_s=1.5)  # 1.5 s lost
    log = read_log(
        zipped(tmp_path, {"acc.csv": _csv("t,x,y,z", ta, va), "gyro.csv": _csv("t,x,y,z", tg, vg)}), name="rec.zip"
    )
    assert log.channels == ["acc", "gyr"] and log.units["acc"] == "g"
    # The accelerometer's samples in the gyroscope's 1.5 s gap (and before its first sample) are left out,
    # and the merged recording shows that gap.
    dropped = 2000 - log.n_samples
    assert dropped == 2 + 151  # the 2 before the gyroscope's first sample, the 151 in its gap
    assert any(abs(g.missing_s - 1.5) < 0.03 for g in log.gaps)
    assert np.abs(log.gyr.mean(axis=0) - [0.01, -0.02, 0.005]).max() < 1e-3


def test_files_of_one_sensor_each_that_follow_each_other_are_refused(tmp_path):
    rng = np.random.default_rng(3)
    ta, va = _stream(rng, 0.0, 100.0, 500, [0, 0, 1.0], 0.002)
    tg, vg = _stream(rng, 10.0, 100.0, 500, [0.01, 0, 0], 0.001)
    with pytest.raises(LogFormatError, match="their times do not overlap"):
        read_log(
            zipped(tmp_path, {"acc.csv": _csv("t,x,y,z", ta, va), "gyro.csv": _csv("t,x,y,z", tg, vg)}), name="rec.zip"
        )


def test_without_time_columns_files_of_equal_length_are_taken_sample_by_sample(tmp_path):
    rng = np.random.default_rng(5)
    _, va = _stream(rng, 0, 100, 300, [0, 0, 9.81], 0.01)
    _, vg = _stream(rng, 0, 100, 300, [0.01, 0, 0], 0.001)

    def rows(v):
        return ("ax,ay,az\n" + "\n".join(",".join(f"{x:.5f}" for x in r) for r in v) + "\n").encode()

    def rowsg(v):
        return ("gx,gy,gz\n" + "\n".join(",".join(f"{x:.5f}" for x in r) for r in v) + "\n").encode()

    log = read_log(
        zipped(tmp_path, {"accelerometer.csv": rows(va), "gyroscope.csv": rowsg(vg)}),
        ReadOptions(sampling_rate_hz=100),
        name="rec.zip",
    )
    assert log.channels == ["acc", "gyr"] and log.n_samples == 300
    assert any("taken as simultaneous" in n for n in log.notes)
    with pytest.raises(LogFormatError, match="cannot be put on one clock"):
        read_log(
            zipped(tmp_path, {"accelerometer.csv": rows(va), "gyroscope.csv": rowsg(vg[:200])}),
            ReadOptions(sampling_rate_hz=100),
            name="rec.zip",
        )


SENSOR_LOGGER = DATA / "real" / "corpus" / "sensor_logger_iphone_per_sensor_files"
PHYPHOX = DATA / "real" / "corpus" / "phyphox_per_sensor_files"


def test_sensor_loggers_gyroscope_and_magnetometer_files_are_one_recording_on_the_gyroscopes_clock(tmp_path):
    """Without the accelerometer (Sensor Logger's Accelerometer.csv holds no gravity), the fastest sensor's clock."""
    files = ("Gyroscope.csv", "Magnetometer.csv")
    log = read_log(zipped(tmp_path, {f: (SENSOR_LOGGER / f).read_bytes() for f in files}), name="rec.zip")
    assert log.channels == ["gyr", "mag"] and log.units == {"gyr": "rad/s", "mag": "uT"}
    assert log.n_samples == 400  # the two files share their timestamps: nothing left out
    assert "merged on the clock of Gyroscope.csv (the fastest sensor's, the gyroscope's, 99.71 Hz)" in log.notes[1]
    raw = np.genfromtxt(SENSOR_LOGGER / "Gyroscope.csv", delimiter=",", skip_header=1)
    assert log.gyr[:, 0] == pytest.approx(raw[:, 4], abs=1e-12)  # z, y, x columns: x is the last


def test_a_phyphox_gyroscope_file_keeps_its_headers_unit_when_read_as_the_gyroscope(tmp_path):
    text = (PHYPHOX / "Gyroscope.csv").read_text().replace("(rad/s)", "(deg/s)")
    log = read_log(
        zipped(
            tmp_path,
            {"Accelerometer.csv": (PHYPHOX / "Accelerometer.csv").read_bytes(), "Gyroscope.csv": text.encode()},
        ),
        name="rec.zip",
    )
    assert log.units == {"acc": "m/s^2", "gyr": "deg/s"}  # the header's unit, not the default rad/s
    assert log.n_samples == 299


def test_json_arrays_one_per_sensor_are_one_recording(tmp_path):
    """accelerometer.json and gyroscope.json, each an array of {"t", "x", "y", "z"}:
    the gyroscope's x, y, z are its own."""
    import json

    rng = np.random.default_rng(12)
    ta, va = _stream(rng, 50.0, 100.0, 600, [0.0, 0.0, 9.81], 0.01)
    tg, vg = _stream(rng, 50.004, 100.0, 600, [0.02, -0.01, 0.0], 0.002)

    def as_json(t, v):
        return json.dumps([{"t": a, "x": x, "y": y, "z": z} for a, (x, y, z) in zip(t, v)]).encode()

    log = read_log(
        zipped(tmp_path, {"accelerometer.json": as_json(ta, va), "gyroscope.json": as_json(tg, vg)}), name="rec.zip"
    )
    assert log.channels == ["acc", "gyr"] and log.units == {"acc": "m/s^2", "gyr": "rad/s"}
    assert log.n_samples == 599  # the accelerometer's first sample comes 4 ms before the gyroscope's
    assert np.abs(log.gyr.mean(axis=0) - [0.02, -0.01, 0.0]).max() < 1e-3


def test_files_not_named_for_a_sensor_but_holding_one_each_are_one_recording(tmp_path):
    rng = np.random.default_rng(9)
    ta, va = _stream(rng, 7.0, 100.0, 400, [0, 0, 1.0], 0.002)
    tg, vg = _stream(rng, 7.002, 100.0, 400, [0.01, 0, 0], 0.001)
    log = read_log(
        zipped(tmp_path, {"log_1.csv": _csv("t,ax,ay,az", ta, va), "log_2.csv": _csv("t,gx,gy,gz", tg, vg)}),
        name="rec.zip",
    )
    assert log.channels == ["acc", "gyr"] and log.n_samples == 399
    assert (
        log.notes[0] == "one recording in 2 files, one per sensor: log_1.csv the accelerometer (g), log_2.csv the "
        "gyroscope (rad/s)"
    )
