"""Logs as loggers write them: no header row, any separator, decimal commas; `columns`; the iOS sign."""

from __future__ import annotations

import re

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.readers import read_log
from app.io.readers.read_options import ReadOptions
from app.io.readers.table import numeric_layout
from tests.conftest import DATA

SAMPLES = DATA / "formats"
N = 300
REST = np.array([0.012, -0.034, 9.807])


def rows(columns: int, *, step=0.01, sep=",", decimal=".", fmt="{:.5f}", time_fmt="{:.3f}"):
    """N lines of a device resting face up, as `columns` numbers: (time,) x, y, z (, more)."""
    rng = np.random.default_rng(5)
    out = []
    for i in range(N):
        acc = REST + rng.normal(0, 0.01, 3)
        cells = [time_fmt.format(i * step)] if columns >= 4 else []
        cells += [fmt.format(v) for v in acc]
        cells += [fmt.format(0.001 * k) for k in range(columns - len(cells))]
        out.append(sep.join(c.replace(".", decimal) for c in cells))
    return "\n".join(out) + "\n"


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


@pytest.mark.parametrize(
    "sep, decimal, word",
    [
        (",", ".", "commas"),
        (";", ".", "semicolons"),
        ("\t", ".", "tabs"),
        (" ", ".", "spaces"),
        ("   ", ".", "spaces"),
        (" \t ", ".", "tabs"),
        (";", ",", "semicolons"),
        ("\t", ",", "tabs"),
        (" ", ",", "spaces"),
    ],
)
def test_four_columns_are_time_x_y_z_with_any_separator(tmp_path, sep, decimal, word):
    log = read_log(write(tmp_path, "log.txt", rows(4, sep=sep, decimal=decimal)))
    assert log.format == "csv" and log.columns == ["time", "acc_x", "acc_y", "acc_z"]
    assert log.sampling_rate_hz == pytest.approx(100.0) and log.n_samples == N
    np.testing.assert_allclose(log.acc.mean(axis=0), REST, atol=3e-3)
    assert f"separated by {word}" in log.notes[0]
    assert ("decimal comma" in log.notes) == (decimal == ",")


@pytest.mark.parametrize(
    "step, time_fmt, rate", [(0.02, "{:.3f}", 50.0), (20, "{:.0f}", 50.0), (2_000_000, "{:.0f}", 500.0)]
)
def test_the_time_unit_is_inferred_from_the_step(tmp_path, step, time_fmt, rate):
    # 0.02 s; 20 ms; 2 000 000 ns (500 Hz) — as for a header's `time` column without a unit.
    log = read_log(write(tmp_path, "t.txt", rows(4, step=step, sep=" ", time_fmt=time_fmt)))
    assert log.sampling_rate_hz == pytest.approx(rate)
    assert log.time_s[-1] == pytest.approx((N - 1) / rate)


def test_three_columns_are_x_y_z_and_take_a_rate(tmp_path):
    p = write(tmp_path, "xyz.txt", rows(3, sep="\t"))
    log = read_log(p)  # still poses need no rate: the note says which methods ask for one
    assert log.sampling_rate_hz is None
    assert any(re.search("has no time column.*noise, cube and autocal methods ask for one", n) for n in log.notes)
    log = read_log(p, ReadOptions(sampling_rate_hz=200))
    assert log.columns == ["acc_x", "acc_y", "acc_z"] and log.sampling_rate_hz == 200 and log.time_s is None


def test_comment_lines_before_the_numbers_are_skipped(tmp_path):
    log = read_log(write(tmp_path, "c.txt", "# board 7, MPU-6050\n#\n" + rows(4, sep=" ")))
    assert log.n_samples == N


def test_other_column_counts_are_named_from_the_data_or_by_columns(tmp_path):
    p = write(tmp_path, "imu.csv", rows(7))
    # An accelerometer resting at 9.8 and three columns resting near zero: time, accelerometer, gyroscope.
    guessed = read_log(p)
    assert guessed.columns == ["time", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"]
    log = read_log(p, ReadOptions(columns="t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z"))
    assert log.channels == ["acc", "gyr"] and log.units["gyr"] == "rad/s"
    np.testing.assert_allclose(log.gyr[0], [0.0, 0.001, 0.002])
    skipped = read_log(p, ReadOptions(columns="time_s,acc_x,acc_y,acc_z,-,-,-"))
    assert skipped.channels == ["acc"] and skipped.sampling_rate_hz == pytest.approx(100.0)


@pytest.mark.parametrize(
    "columns, fragment",
    [
        ("t,acc_x,acc_y,acc_z", "names 4 columns (t, acc_x, acc_y, acc_z) but the file has 7 per line"),
        ("t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyro_z", "'gyro_z', which trical does not know"),
        ("t,acc_x,acc_y,acc_z,gyr_x,gyr_y,-", "names gyr_x, gyr_y but not gyr_z"),
        ("t,-,-,-,-,-,-", "names no sensor"),
        ("t,acc_x,acc_y,acc_z,acc_x,-,-", "names acc_x more than once"),
        ("t,time_ms,acc_x,acc_y,acc_z,-,-", "names t, time_ms more than once"),
        ("acc_x:north,acc_y", "is not canonical:column"),
    ],
)
def test_bad_columns_name_the_problem(tmp_path, columns, fragment):
    with pytest.raises(LogFormatError) as e:
        read_log(write(tmp_path, "imu.csv", rows(7)), ReadOptions(columns=columns))
    assert fragment in str(e.value)


def test_decimal_commas_between_comma_separators_are_refused_by_their_count(tmp_path):
    p = write(tmp_path, "eu.csv", "".join(f"{i / 100:.2f},0.01,0.02,9.81\n".replace(".", ",") for i in range(N)))
    with pytest.raises(LogFormatError, match=r"decimal commas .* save the log with semicolons or tabs"):
        read_log(p, ReadOptions(columns="t,acc_x,acc_y,acc_z"))


def test_columns_replace_a_header_row(tmp_path):
    text = "Zeit;Wert1;Wert2;Wert3\n" + rows(4, sep=";", decimal=",")
    log = read_log(write(tmp_path, "de.csv", text), ReadOptions(columns="time_s,acc_x,acc_y,acc_z"))
    assert log.columns == ["time_s", "acc_x", "acc_y", "acc_z"] and log.sampling_rate_hz == pytest.approx(100.0)
    assert "header row replaced by columns time_s, acc_x, acc_y, acc_z" in log.notes


def test_a_header_row_separated_by_spaces(tmp_path):
    log = read_log(write(tmp_path, "h.txt", "time_ms ax ay az\n" + rows(4, step=10, sep="  ", time_fmt="{:.0f}")))
    assert log.columns == ["time_ms", "ax", "ay", "az"] and log.sampling_rate_hz == pytest.approx(100.0)


def test_a_last_column_that_stays_at_a_room_temperature_is_the_temperature(tmp_path):
    text = "".join("0.01,0.02,9.81,25.0\n" for _ in range(N))  # x, y, z and a temperature
    log = read_log(write(tmp_path, "x.csv", text))
    assert log.columns == ["acc_x", "acc_y", "acc_z", "temp_c"] and log.temperature_c[0] == 25.0


def test_a_bad_number_is_named_by_line_and_column(tmp_path):
    text = rows(4, sep=" ").splitlines()
    text[5] = "0.05 0.01 oops 9.8"
    with pytest.raises(LogFormatError, match="line 6, column 'acc_y': 'oops' is not a number"):
        read_log(write(tmp_path, "bad.txt", "\n".join(text) + "\n"))


@pytest.mark.parametrize(
    "line, layout",
    [
        ("0 1 2", (" ", ".", 3)),
        ("0,5;1,5;9,8", (";", ",", 3)),
        ("0.5,1,2", (",", ".", 3)),
        ("0,5 1,5 2", (" ", ",", 3)),
        ("0.1\t0.2\t9.8", ("\t", ".", 3)),
        ("0.1, 0.2, 9.8", (",", ".", 3)),
        ("time x y z", None),
        ("acc_x,acc_y,acc_z", None),
        ("nan,1,2", None),
    ],
)
def test_numeric_layout(line, layout):
    assert numeric_layout([line]) == layout


def test_sign_minus_one_negates_the_accelerations(tmp_path):
    p = write(tmp_path, "log.txt", rows(4, sep=" "))
    kept, flipped = read_log(p), read_log(p, ReadOptions(sign=-1))
    np.testing.assert_array_equal(flipped.acc, -kept.acc)
    assert (kept.sign, flipped.sign) == (1, -1) and "accelerations negated as sign=-1 asks" in flipped.notes
    with pytest.raises(LogFormatError, match=r"sign must be 1 .* or -1"):
        read_log(p, ReadOptions(sign=2))


def test_a_sensorlog_file_is_detected_as_ios_and_negated():
    log = read_log(SAMPLES / "sensorlog_ios.csv")
    assert log.format == "sensorlog" and log.sign == -1 and log.units == {"acc": "g", "gyr": "rad/s"}
    assert any(
        n.startswith("this looks like an iOS Core Motion log (accelerometerAccelerationX(G)")
        and n.endswith("pass sign=1 to keep them")
        for n in log.notes
    )
    generic = read_log(SAMPLES / "headerless_tab_xyz_g.txt", ReadOptions(sampling_rate_hz=50))
    np.testing.assert_allclose(log.acc, generic.acc, atol=1e-6)  # the same rests on trical's sign
    kept = read_log(SAMPLES / "sensorlog_ios.csv", ReadOptions(sign=1))
    np.testing.assert_array_equal(kept.acc, -log.acc)
    assert kept.sign == 1 and "sign=1 given: the file's accelerations are kept as they are (not negated)" in kept.notes


def test_core_motion_names_in_a_generic_csv(tmp_path):
    header = (
        "timestamp,accelerationX,accelerationY,accelerationZ,userAccelerationX,userAccelerationY,"
        "userAccelerationZ,gravityX,gravityY,gravityZ\n"
    )
    body = "".join(f"{i / 100:.2f},0.01,0.02,-1.0,0.0,0.0,0.0,0.01,0.02,-1.0\n" for i in range(N))
    log = read_log(write(tmp_path, "cm.csv", header + body))
    assert log.sign == -1 and log.acc[0, 2] == pytest.approx(1.0)
    assert any(
        "iOS Core Motion log (userAccelerationX, userAccelerationY, userAccelerationZ, …)" in n for n in log.notes
    )


def test_core_motion_names_in_m_s2_are_kept_with_a_note(tmp_path):
    header = "time,accelerationX,accelerationY,accelerationZ,userAccelerationX,userAccelerationY,userAccelerationZ\n"
    body = "".join(f"{i / 100:.2f},0.1,0.2,9.8,0.0,0.0,0.0\n" for i in range(N))
    log = read_log(write(tmp_path, "cm.csv", header + body))
    assert log.sign == 1 and log.acc[0, 2] == pytest.approx(9.8)
    assert any("not Core Motion's g: an app converted them" in n for n in log.notes)


def test_android_gravity_columns_alone_are_not_ios(tmp_path):
    header = "time,acc_x,acc_y,acc_z,gravity_x,gravity_y,gravity_z\n"
    body = "".join(f"{i / 100:.2f},0.01,0.02,1.0,0.0,0.0,1.0\n" for i in range(N))
    log = read_log(write(tmp_path, "a.csv", header + body))
    assert log.sign == 1 and log.acc[0, 2] == pytest.approx(1.0)


def test_sensor_logger_ios_flip_can_be_refused_with_sign_one():
    flipped = read_log(SAMPLES / "sensor_logger_ios.zip")
    kept = read_log(SAMPLES / "sensor_logger_ios.zip", ReadOptions(sign=1))
    assert flipped.sign == -1 and kept.sign == 1
    np.testing.assert_array_equal(kept.acc, -flipped.acc)
