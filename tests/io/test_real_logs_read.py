"""Real logs as their programs write them (tests/data/real/corpus, issue 31): a still magnetometer's
counts, readings in mg, a terminal capture's start-up lines, HyperIMU's '@' comments, prefixed and
chip-named sensor columns beside linear ones, packets of two rates interleaved, text blocks in cells.
The upload of each case is tests/api/test_real_corpus.py; here the reader's functions themselves."""

from __future__ import annotations

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.readers import read_log
from app.io.readers.generic_csv import leading_prose, map_columns, split_header, table_layout
from app.io.readers.read_options import ReadOptions
from app.io.readers.table import read_columns, text_block_cell
from app.io.readers.units import common_sensitivity, field_magnitude, infer_mag_unit, turn_field
from tests.conftest import DATA

CORPUS = DATA / "real" / "corpus"
BNO = CORPUS / "bno055_pi_still_serial_capture" / "imu_raw.csv"
BNO_ROWS = CORPUS / "bno055_pi_still_magnetometer_counts" / "imu_raw.csv"
HYPERIMU = CORPUS / "hyperimu_lsm6ds3_phone_still" / "imu.csv"
MICROSTRAIN = CORPUS / "microstrain_cx5_six_pose_files" / "xplus.csv"
BLUEYE = CORPUS / "blueye_drone_protobuf_text_cells" / "calibration_data.csv"
BNO_COLUMNS = ["acc_x", "acc_y", "acc_z", "mag_x", "mag_y", "mag_z", "gyr_x", "gyr_y", "gyr_z", "-"]


def _bno_mag() -> np.ndarray:
    return np.loadtxt(BNO_ROWS, delimiter=",")[:, 3:6]


# -- D1: a still magnetometer shows no turn ------------------------------------------------------


def test_a_still_bno055_magnetometer_shows_no_turn_and_its_counts_stay_counts():
    mag = _bno_mag()  # 954 counts at 16 LSB/µT, its 1-99 % wander ±21-28 counts
    assert turn_field(mag) is None
    assert field_magnitude(mag) == pytest.approx(954.4, abs=0.5)
    assert infer_mag_unit(mag) == "raw"


def test_a_turn_still_shows_its_field_and_a_ball_of_noise_does_not():
    rng = np.random.default_rng(3)
    directions = rng.normal(size=(2000, 3))
    turned = 48.0 * directions / np.linalg.norm(directions, axis=1)[:, None] + [300.0, -40.0, 10.0]
    assert turn_field(turned) == pytest.approx(48.0, rel=0.03)
    # Noise and wander spanning 2.6 % of the norm in every axis, as the BNO055's: no turn.
    still = np.array([-528.8, -29.2, -793.9]) + rng.normal(0.0, 11.0, (2000, 3))
    assert turn_field(still) is None


def test_whole_numbers_of_a_still_magnetometer_are_counts_unless_a_unit_is_stated(tmp_path):
    # Their norm can fall in 15-100 (an AK8963 at 14 bits reads 80 for 48 µT); as floats it is µT.
    rng = np.random.default_rng(4)
    counts = np.round([50.0, 20.0, 55.0] + rng.normal(0.0, 0.6, (2000, 3)))
    for header, values, fmt, unit in (
        ("mag_x,mag_y,mag_z", counts, "%.0f", "raw"),
        ("mag_x (uT),mag_y (uT),mag_z (uT)", counts, "%.0f", "uT"),
        ("mag_x,mag_y,mag_z", counts + rng.uniform(-0.4, 0.4, counts.shape), "%.3f", "uT"),
    ):
        path = tmp_path / "mag.csv"
        np.savetxt(path, values, fmt=fmt, delimiter=",", header=header, comments="")
        log = read_log(path, ReadOptions(sampling_rate_hz=50, units={}), name="mag.csv")
        assert log.units["mag"] == unit, (header, fmt)


# -- D8: an accelerometer in mg ------------------------------------------------------------------


def test_counts_resting_near_1000_are_milli_g():
    assert common_sensitivity(982.0) == 1000.0
    assert common_sensitivity(2048.0) == 2048.0 and common_sensitivity(3000.0) is None


# -- D5: a terminal capture's start-up lines ----------------------------------------------------


def test_a_terminal_captures_start_up_lines_are_skipped_and_named():
    text = BNO.read_text()
    assert leading_prose(text.splitlines()) == [0, 1, 2]
    layout = table_layout(text, "imu_raw.csv", BNO_COLUMNS)
    assert layout.skip_lines == 3 and layout.headerless and layout.delimiter == ","
    assert layout.notes[0] == (
        "lines 1, 2, 3 skipped before the table: neither a header nor numbers ('GPIO "
        "initialized.', 'i2c bus opened with handle 0.', 'Device with address a0 found')"
    )


def test_start_up_lines_before_a_header_are_skipped_and_the_header_kept():
    lines = BNO.read_text().splitlines()
    text = "\n".join(lines[:3] + [",".join(BNO_COLUMNS[:9] + ["period_ns"])] + lines[3:])
    assert leading_prose(text.splitlines()) == [0, 1, 2]
    layout = table_layout(text)
    assert layout.skip_lines == 4 and not layout.headerless and layout.names[0] == "acc_x"
    # A header row is not prose, nor is a table starting at its first line.
    assert leading_prose(text.splitlines()[3:]) == [] and leading_prose(lines[3:]) == []


def test_the_bno055_capture_reads_in_g_from_its_milli_g():
    log = read_log(BNO, ReadOptions(sampling_rate_hz=50, units={}, columns=",".join(BNO_COLUMNS)), name="imu_raw.csv")
    assert log.units == {"acc": "g", "gyr": "raw", "mag": "raw"}
    rows = np.loadtxt(BNO_ROWS, delimiter=",")
    np.testing.assert_array_equal(log.acc, rows[:, :3] / 1000.0)
    np.testing.assert_allclose(log.acc.mean(axis=0), [-0.01589, -0.05176, 0.98093], atol=5e-6)
    assert any("about 1000 LSB per g (readings in milli-g (mg)" in w for w in log.warnings)


# -- D6: HyperIMU's '@' comment lines; D2: chip-named columns beside linear ones -----------------


def test_hyperimu_at_lines_are_comments_and_its_chip_named_columns_are_read():
    number, delimiter, names = split_header(HYPERIMU.read_text())
    assert number == 4 and delimiter == "," and names[:2] == ["timestamp", "accelerometer_lsm6ds3_c.x"]
    channels, time_col, _, _ = map_columns(names)
    assert [names[channels["acc"][a]] for a in "xyz"] == [f"accelerometer_lsm6ds3_c.{a}" for a in "xyz"]
    assert [names[channels["gyr"][a]] for a in "xyz"] == [f"gyroscope_lsm6ds3_c.{a}" for a in "xyz"]
    assert names[time_col] == "timestamp"
    log = read_log(HYPERIMU, ReadOptions(sampling_rate_hz=None, units={}), name="imu.csv")
    assert log.units["acc"] == "m/s^2" and log.acc.shape == (330, 3)


def test_microstrain_scaled_columns_are_the_accelerometer_beside_the_filters_linear_ones():
    names = MICROSTRAIN.read_text().splitlines()[0].split(",")
    channels, time_col, _, _ = map_columns(names)
    assert [names[channels["acc"][a]] for a in "xyz"] == ["scaledAccelX", "scaledAccelY", "scaledAccelZ"]
    assert [names[channels["gyr"][a]] for a in "xyz"] == ["scaledGyroX", "scaledGyroY", "scaledGyroZ"]
    assert names[time_col] == "timestamp"


def test_linear_columns_alone_are_refused_and_beside_unknown_acceleration_columns_asked_about():
    with pytest.raises(LogFormatError, match=r"hold linear acceleration .gravity removed.; calibration needs"):
        map_columns(["time", "accuracy", "linear_acceleration.x", "linear_acceleration.y", "linear_acceleration.z"])
    with pytest.raises(
        LogFormatError,
        match=r"'estLinearAccelX', .* hold linear acceleration \(gravity removed\), "
        r"but 'bodyAccX', 'bodyAccY', 'bodyAccZ' may be the accelerometer .*"
        r"columns=acc_x:<name>",
    ):
        map_columns(["t", "bodyAccX", "bodyAccY", "bodyAccZ", "estLinearAccelX", "estLinearAccelY", "estLinearAccelZ"])


# -- D3: packets of two rates interleaved ----------------------------------------------------------


def test_rows_of_the_other_packet_are_dropped_with_a_note_and_a_partly_empty_row_refused(tmp_path):
    names = MICROSTRAIN.read_text().splitlines()[0].split(",")
    cols = [2, 4, 5, 6]  # timestamp, scaledAccelX/Y/Z
    notes: list[str] = []
    t, x, y, z = read_columns(
        MICROSTRAIN,
        skip_lines=1,
        n_columns=len(names),
        columns=cols,
        delimiter=",",
        name="xplus.csv",
        column_names=names,
        drop_empty=(4, 5, 6),
        notes=notes,
    )
    assert len(x) == 603 - 201 and np.isfinite(np.column_stack([x, y, z])).all()
    assert np.median(np.diff(t)) == pytest.approx(1e6, rel=0.01)  # the IMU packets' 1 kHz, in ns
    assert notes == [
        "xplus.csv: 201 of 603 rows leave the sensors' columns empty (another packet type's rows, "
        "as logs interleaving packets of two rates write them): skipped"
    ]
    lines = MICROSTRAIN.read_text().splitlines()
    cells = lines[2].split(",")
    cells[5] = ""  # scaledAccelY of an IMU packet lost
    bad = tmp_path / "partly.csv"
    bad.write_text("\n".join(lines[:2] + [",".join(cells)] + lines[3:]) + "\n")
    with pytest.raises(
        LogFormatError,
        match=r"data row 2 .line 3 if the file has no blank lines. has an empty value in column 'scaledAccelY'",
    ):
        read_columns(
            bad,
            skip_lines=1,
            n_columns=len(names),
            columns=cols,
            delimiter=",",
            name="partly.csv",
            column_names=names,
            drop_empty=(4, 5, 6),
            notes=[],
        )


# -- D9: text blocks in cells --------------------------------------------------------------------------


def test_a_text_block_in_a_cell_is_quoted_with_its_line_and_column():
    text = BLUEYE.read_text()
    assert text_block_cell(text, ",", 1, ["Timestamp", "IMU1Data", "IMU2Data", "Depth"]) == (
        2,
        "IMU1Data",
        "accelerometer {",
    )
    assert text_block_cell(MICROSTRAIN.read_text(), ",", 1, []) is None
    for columns in (None, "time_s:Timestamp,acc_x:IMU1Data,acc_y:IMU1Data,acc_z:IMU1Data"):
        with pytest.raises(
            LogFormatError,
            match=r"line 2, column 'IMU1Data' holds a block of text over several "
            r"lines \('accelerometer \{' …\), not a number: .* no columns "
            "mapping can read it",
        ):
            read_log(BLUEYE, ReadOptions(sampling_rate_hz=None, units={}, columns=columns), name="calibration_data.csv")


def test_the_rate_a_hyperimu_comment_states_is_used_when_there_is_no_time_column(tmp_path):
    lines = HYPERIMU.read_text().splitlines()  # '@ Date:…, Sampling Rate:50ms'
    path = tmp_path / "imu.csv"
    path.write_text("\n".join(lines[:3] + [",".join(r.split(",")[1:4]) for r in lines[3:]]) + "\n")
    log = read_log(path, ReadOptions(sampling_rate_hz=None, units={}), name="imu.csv")
    assert log.sampling_rate_hz == 20.0 and log.timing.source == "file"
    assert "no time column: the rate 20 Hz the lines before its table state is used" in log.notes
    assert read_log(path, ReadOptions(sampling_rate_hz=25.0, units={}), name="imu.csv").sampling_rate_hz == 25.0
    # With its time column the timestamps decide (Android delivers near, not at, the requested rate).
    assert (
        read_log(HYPERIMU, ReadOptions(sampling_rate_hz=None, units={}), name="imu.csv").timing.source == "time column"
    )
