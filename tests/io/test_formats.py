"""app.io.readers: detection rules, decimal commas, clocks, Sensor Logger signs, GnssLogger lines, units."""

from __future__ import annotations

import zipfile

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.readers import detect_format, read_log
from app.io.readers.read_options import ReadOptions
from app.io.readers.table import sniff
from app.io.readers.units import infer_acc_unit
from tests.conftest import DATA

SAMPLES = DATA / "formats"
G0 = 9.80665


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


def write_zip(tmp_path, name, members):
    p = tmp_path / name
    with zipfile.ZipFile(p, "w") as zf:
        for member, text in members.items():
            zf.writestr(member, text)
    return p


@pytest.mark.parametrize(
    "filename, fmt",
    [
        ("phyphox_comma.csv", "phyphox"),
        ("phyphox_tab.csv", "phyphox"),
        ("phyphox_semicolon_decimal_comma.csv", "phyphox"),
        ("phyphox_export.zip", "phyphox"),
        ("sensor_logger_android.zip", "sensor_logger"),
        ("sensor_logger_TotalAcceleration.csv", "sensor_logger"),
        ("physics_toolbox_gforce.csv", "physics_toolbox"),
        ("gnss_logger.txt", "gnss_logger"),
        ("arduino_serial_plotter.txt", "arduino"),
        ("arduino_lsb.csv", "arduino"),
        ("generic_g.csv", "csv"),
        ("../six_orientations_150hz.csv", "csv"),
    ],
)
def test_detection(filename, fmt):
    assert detect_format(sniff(SAMPLES / filename, filename)) == fmt


def test_phyphox_flavours_read_the_same_numbers():
    ref = read_log(SAMPLES / "phyphox_comma.csv")
    for name in ("phyphox_tab.csv", "phyphox_semicolon_decimal_comma.csv", "phyphox_export.zip"):
        log = read_log(SAMPLES / name)
        np.testing.assert_array_equal(log.acc, ref.acc)
        np.testing.assert_array_equal(log.time_s, ref.time_s)


def test_phyphox_bad_number_names_line_and_column(tmp_path):
    header = '"Time (s)";"Acceleration x (m/s^2)";"Acceleration y (m/s^2)";"Acceleration z (m/s^2)"\n'
    p = write(tmp_path, "p.csv", header + "0,0;0,1;0,2;9,8\n0,01;0,1;oops;9,8\n")
    with pytest.raises(LogFormatError, match=r"line 3, column 'Acceleration y \(m/s\^2\)': 'oops' is not a number"):
        read_log(p)


def test_physics_toolbox_clock_time_and_decimal_comma(tmp_path):
    rows = "\n".join(f"12:00:{i // 100:02d}:{(i % 100) * 10:03d};0,01;0,02;1,0;1,0" for i in range(300))
    log = read_log(write(tmp_path, "ptb.csv", f"time;gFx;gFy;gFz;TgF\n{rows}\n"))
    assert log.format == "physics_toolbox" and log.units["acc"] == "g"
    assert log.sampling_rate_hz == pytest.approx(100.0)
    np.testing.assert_allclose(log.acc[0], [0.01, 0.02, 1.0])


def test_physics_toolbox_multi_record_ignores_linear_columns(tmp_path):
    rows = "\n".join(f"{i / 100:.2f},0.0,0.0,1.0,0.3,0.2,0.1,0.01,0.02,0.03,20,30,-40" for i in range(200))
    log = read_log(write(tmp_path, "m.csv", f"time,gFx,gFy,gFz,ax,ay,az,wx,wy,wz,Bx,By,Bz\n{rows}\n"))
    np.testing.assert_allclose(log.acc[0], [0, 0, 1])
    assert log.channels == ["acc", "gyr", "mag"] and log.units["mag"] == "uT"


def _sl_csv(rows):
    return (
        "time,seconds_elapsed,z,y,x\n"
        + "\n".join(
            f"{1_700_000_000_000_000_000 + i * 10_000_000},{i / 100},{z},{y},{x}" for i, (x, y, z) in enumerate(rows)
        )
        + "\n"
    )


def test_sensor_logger_ios_standardised_keeps_the_sign(tmp_path):
    rows = [(0.0, 0.0, 9.81)] * 200
    meta = "version,device name,recording time,platform,appVersion,standardisation\n3,x,t,ios,1.41,true\n"
    log = read_log(write_zip(tmp_path, "s.zip", {"Metadata.csv": meta, "AccelerometerUncalibrated.csv": _sl_csv(rows)}))
    assert log.units["acc"] == "m/s^2" and log.acc[0, 2] == pytest.approx(9.81)


def test_sensor_logger_metadata_contradicting_the_data_is_refused(tmp_path):
    rows = [(0.0, 0.0, -9.81)] * 200  # m/s², but metadata says raw iOS (which is in g)
    meta = "version,device name,recording time,platform,appVersion,standardisation\n3,x,t,iOS,1.41,false\n"
    with pytest.raises(LogFormatError, match="looks edited"):
        read_log(write_zip(tmp_path, "s.zip", {"Metadata.csv": meta, "AccelerometerUncalibrated.csv": _sl_csv(rows)}))


def test_sensor_logger_single_csv_in_g_is_the_ios_raw_stream(tmp_path):
    log = read_log(write(tmp_path, "AccelerometerUncalibrated.csv", _sl_csv([(0.0, 0.0, -1.0)] * 200)))
    assert log.units["acc"] == "g" and log.acc[0, 2] == pytest.approx(1.0)
    assert any("sign decided from the unit" in n for n in log.notes)


def test_sensor_logger_columns_are_reordered_from_z_y_x(tmp_path):
    log = read_log(write(tmp_path, "TotalAcceleration.csv", _sl_csv([(1.0, 2.0, 9.5)] * 200)))
    np.testing.assert_allclose(log.acc[0], [1.0, 2.0, 9.5])
    assert log.sampling_rate_hz == pytest.approx(100.0)


def test_sensor_logger_linear_accelerometer_file_alone_is_refused(tmp_path):
    rows = np.random.default_rng(2).normal(0, 0.05, (200, 3))
    with pytest.raises(LogFormatError, match=r"linear acceleration \(gravity removed\).*TotalAcceleration"):
        read_log(write(tmp_path, "Accelerometer.csv", _sl_csv(rows)))


def test_gnss_logger_found_past_the_first_lines(tmp_path):
    raw = "\n".join(f"Raw,{i},1,2,3" for i in range(400))
    acc = "\n".join(f"UncalAccel,{i},{i * 10_000_000},0.0,0.1,9.8,0,0,0" for i in range(200))
    log = read_log(write(tmp_path, "g.txt", f"{raw}\n{acc}\n"))
    assert log.format == "gnss_logger" and log.sampling_rate_hz == pytest.approx(100.0)


def test_gnss_logger_bad_line_is_named(tmp_path):
    text = (
        "# UncalAccel,utcTimeMillis,elapsedRealtimeNanos,UncalAccelXMps2,UncalAccelYMps2,UncalAccelZMps2,"
        "BiasXMps2,BiasYMps2,BiasZMps2\n"
        "UncalAccel,1,1000000,0.1,0.2,9.8,0,0,0\nUncalAccel,2,2000000,0.1,x,9.8,0,0,0\n"
    )
    with pytest.raises(LogFormatError, match="line 3 \\(UncalAccel\\)"):
        read_log(write(tmp_path, "g.txt", text))


def test_gnss_logger_gyroscope_is_interpolated_at_the_accelerometer_times():
    log = read_log(SAMPLES / "gnss_logger.txt")
    assert log.gyr.shape == log.mag.shape == log.acc.shape
    assert log.units == {"acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}
    np.testing.assert_allclose(np.median(log.mag, axis=0), [18.0, -6.0, -42.0], atol=0.2)


def test_gnss_logger_without_uncal_accel(tmp_path):
    text = "# UncalAccel,utcTimeMillis,elapsedRealtimeNanos,UncalAccelXMps2\nFix,GPS,1,2\n"
    with pytest.raises(LogFormatError, match=r"no UncalAccel \(or UncalMag\) lines"):
        read_log(write(tmp_path, "g.txt", text))


@pytest.mark.parametrize("scale, unit", [(1.0, "g"), (G0, "m/s^2"), (16384.0, "raw"), (3.0, None)])
def test_unit_inference(scale, unit):
    acc = np.tile([0.0, 0.0, 1.0], (100, 1)) * scale
    if unit == "raw":
        acc = np.round(acc)
    assert infer_acc_unit(acc) == unit


def test_lsb_per_g_needs_counts(tmp_path):
    with pytest.raises(LogFormatError, match="converts counts"):
        read_log(SAMPLES / "generic_g.csv", ReadOptions(lsb_per_g=4096, units={"acc": "g"}))
    with pytest.raises(LogFormatError, match="positive number"):
        read_log(SAMPLES / "arduino_lsb.csv", ReadOptions(lsb_per_g=-1))


def test_serial_plotter_without_accelerometer_labels(tmp_path):
    with pytest.raises(LogFormatError, match="name no accelerometer x, y and z"):
        read_log(write(tmp_path, "s.txt", "temp:21 hum:40\ntemp:22 hum:41\n"), ReadOptions(sampling_rate_hz=10))


def test_unknown_format_name(tmp_path):
    with pytest.raises(LogFormatError, match="unknown format 'xlsx'"):
        read_log(SAMPLES / "generic_g.csv", ReadOptions(format="xlsx"))


def test_zip_with_a_broken_directory(tmp_path):
    p = tmp_path / "b.zip"
    p.write_bytes(b"PK\x03\x04" + b"\x00" * 100)
    with pytest.raises(LogFormatError, match="cannot be opened") as e:
        read_log(p)
    assert e.value.status == 415


def test_zip_member_size_is_checked(tmp_path, monkeypatch):
    import app.io.readers.table as table

    monkeypatch.setattr(table, "MAX_UNZIPPED_BYTES", 1000)
    with pytest.raises(LogFormatError, match="expands to") as e:
        read_log(SAMPLES / "phyphox_export.zip")
    assert e.value.status == 413


def test_the_samples_are_the_generator_output(tmp_path):
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_format_samples", SAMPLES / "make_format_samples.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.main(tmp_path)
    written = sorted(p.name for p in tmp_path.iterdir())
    assert written == sorted(p.name for p in SAMPLES.iterdir() if p.suffix in (".csv", ".txt", ".zip", ".json"))
    for name in written:
        assert (tmp_path / name).read_bytes() == (SAMPLES / name).read_bytes(), name


def test_g_readings_declared_in_m_s2_are_read_in_g_with_a_warning():
    log = read_log(SAMPLES / "generic_g.csv", ReadOptions(units={"acc": "m/s^2"}))
    assert log.units["acc"] == "g"
    assert any(
        n.startswith("acc_unit said m/s^2 for the accelerometer, but its readings rest at a median norm of")
        and n.endswith("about 1 g in g: calibrated in g")
        for n in log.warnings
    )


def test_a_sensor_logger_zip_names_the_files_it_does_not_read():
    """Sensor Logger's Android zip (Metadata, TotalAcceleration, Accelerometer, Gyroscope, a README): the
    accelerometer with gravity and the gyroscope are read, and the user acceleration and the README are named as
    not read, never left in silence."""
    log = read_log(SAMPLES / "sensor_logger_android.zip", name="rec.zip")
    assert log.channels == ["acc", "gyr"]
    (said,) = [n for n in log.notes if "of the zip not read" in n]
    assert said.startswith("2 files of the zip not read: Accelerometer.csv, README.txt")


def test_tagged_lines_that_name_no_sensor_are_refused_naming_their_tags(tmp_path):
    """A file read as format=tagged whose lines' tags name no sensor: a refusal naming its tags and the ones trical
    reads (it was a StopIteration, an error without a message)."""
    path = tmp_path / "tags.txt"
    path.write_text("foo 1 2 3\nfoo 2 3 4\nbar 3 4 5\nfoo 4 5 6\nbar 5 6 7\n")
    with pytest.raises(LogFormatError, match="no line names a sensor trical reads \\(its tags are bar, foo\\)"):
        read_log(path, ReadOptions(format="tagged"), name="tags.txt")
