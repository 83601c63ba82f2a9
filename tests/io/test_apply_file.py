"""A calibration applied to a whole recording, read in chunks and written as CSV, Parquet or .npy
(app.workflows.apply, app.io.readers.chunks, app.io.writers.samples), on real files: the MPU-6050 board's ten
still poses (tests/data/real/mpu6050_session1_poses.csv) calibrate its own 30 s still recording
(mpu6050_session2_still_30s.csv), and a phone's HyperIMU export (corpus/hyperimu_lsm6ds3_phone_still) carries a
gyroscope and a magnetometer beside its accelerometer."""

from __future__ import annotations

import dataclasses
import io
import json
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

from app.calibration import CalibrationError
from app.calibration.shared.gravity import STANDARD_GRAVITY
from app.calibration.still.triangular import fit_triangular
from app.io.errors import LogFormatError
from app.io.readers import read_log
from app.io.readers.chunks import read_in_chunks
from app.io.readers.read_options import ReadOptions
from app.io.writers.samples import output_format
from app.workflows.apply import apply_to_file
from tests.real_recordings import REAL, mpu6050_session1

STILL = REAL / "mpu6050_session2_still_30s.csv"
HYPERIMU = REAL / "corpus" / "hyperimu_lsm6ds3_phone_still" / "imu.csv"
HYPERIMU_COLUMNS = json.loads((HYPERIMU.parent / "case.json").read_text())["form"]["columns"]


@pytest.fixture(scope="module")
def calibration():
    """The board's triangular fit on its ten still poses (in g), as a stored body and as the result."""
    result = dataclasses.replace(fit_triangular(mpu6050_session1(), gravity=1.0), unit="g")
    body = {**result.to_dict(), "id": "cal_test"}
    return body, result


def written(body, path, fmt="npy", **kw):
    out = io.BytesIO()
    applied = apply_to_file(body, path, out, fmt=fmt, **kw)
    out.seek(0)
    return applied, out


def npy_columns(out) -> tuple[tuple[str, ...], np.ndarray]:
    arr = np.load(out)
    return arr.dtype.names, np.column_stack([arr[n] for n in arr.dtype.names])


def test_the_output_is_the_results_apply_on_the_whole_read(calibration):
    body, result = calibration
    whole = result.apply(read_log(STILL).acc, "acc")
    applied, out = written(body, STILL)
    names, values = npy_columns(out)
    assert names == ("acc_x (g)", "acc_y (g)", "acc_z (g)")
    assert applied.rows == 3000 == len(values)
    assert np.max(np.abs(values - whole)) <= 1e-9
    assert applied.corrected == ("acc",) and applied.passed == ()


def test_chunk_boundaries_do_not_change_the_output(calibration):
    body, _ = calibration
    whole = npy_columns(written(body, STILL)[1])[1]
    outputs = []
    for chunk_rows, head_lines in ((7, 40), (100, 500), (999, 2000)):
        applied, out = written(body, STILL, chunk_rows=chunk_rows, head_lines=head_lines)
        assert applied.streamed
        outputs.append(npy_columns(out)[1])
    chunks = list(read_in_chunks(STILL, name=STILL.name, chunk_rows=7, head_lines=40).chunks())
    assert len(chunks) > 10 and sum(c.rows for c in chunks) == 3000
    for values in outputs:
        assert np.array_equal(values, whole)


def test_a_phones_gyroscope_and_magnetometer_pass_through_and_m_s2_becomes_the_calibrations_g(calibration):
    body, result = calibration
    options = ReadOptions(columns=HYPERIMU_COLUMNS)
    log = read_log(HYPERIMU, options, name=HYPERIMU.name)
    assert log.units == {"acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}
    applied, out = written(body, HYPERIMU, fmt="csv", options=options, chunk_rows=25, head_lines=60)
    assert applied.streamed and applied.corrected == ("acc",) and applied.passed == ("gyr", "mag")
    text = out.getvalue().decode()
    comments = [ln for ln in text.splitlines() if ln.startswith("#")]
    assert "acc: corrected, m/s^2 -> g" in comments[1] and "times 0.101971621298" in comments[1]
    assert comments[2].startswith("# gyr: passed through unchanged, rad/s")
    header = text.splitlines()[len(comments)].split(",")
    assert header == ["time (s)"] + [f"acc_{a} (g)" for a in "xyz"] + [f"gyr_{a} (rad/s)" for a in "xyz"] + [
        f"mag_{a} (uT)" for a in "xyz"
    ]
    rows = np.loadtxt(io.StringIO(text), delimiter=",", comments="#", skiprows=len(comments) + 1)
    assert np.max(np.abs(rows[:, 0] - log.time_s)) <= 1e-9
    assert np.max(np.abs(rows[:, 1:4] - result.apply(log.acc / STANDARD_GRAVITY, "acc"))) <= 1e-9
    assert np.array_equal(rows[:, 4:7], log.gyr) and np.array_equal(rows[:, 7:10], log.mag)


def test_a_written_csv_reads_back_in_the_units_its_header_names(calibration, tmp_path):
    body, result = calibration
    options = ReadOptions(columns=HYPERIMU_COLUMNS)
    out = tmp_path / "calibrated.csv"
    with open(out, "wb") as f:
        apply_to_file(body, HYPERIMU, f, fmt="csv", options=options)
    back = read_log(out)
    assert back.units == {"acc": "g", "gyr": "rad/s", "mag": "uT"}
    log = read_log(HYPERIMU, options)
    assert np.max(np.abs(back.acc - result.apply(log.acc / STANDARD_GRAVITY, "acc"))) <= 1e-9


def test_parquet_fields_carry_their_unit_and_whether_they_were_corrected(calibration, tmp_path):
    body, result = calibration
    options = ReadOptions(columns=HYPERIMU_COLUMNS)
    out = tmp_path / "calibrated.parquet"
    with open(out, "wb") as f:
        apply_to_file(body, HYPERIMU, f, fmt="parquet", options=options, chunk_rows=50, head_lines=60)
    table = pq.read_table(out)
    meta = {f.name: {k.decode(): v.decode() for k, v in f.metadata.items()} for f in table.schema}
    assert meta["acc_x (g)"] == {"unit": "g", "corrected": "true"}
    assert meta["gyr_z (rad/s)"] == {"unit": "rad/s", "corrected": "false"}
    assert meta["time (s)"]["unit"] == "s"
    assert "cal_test" in json.loads(table.schema.metadata[b"trical"])[0]
    log = read_log(HYPERIMU, options)
    acc = np.column_stack([table.column(f"acc_{a} (g)").to_numpy() for a in "xyz"])
    assert np.max(np.abs(acc - result.apply(log.acc / STANDARD_GRAVITY, "acc"))) <= 1e-9
    assert np.array_equal(np.column_stack([table.column(f"mag_{a} (uT)").to_numpy() for a in "xyz"]), log.mag)


def test_counts_against_a_calibration_in_g_are_refused_naming_both_units(calibration):
    body, _ = calibration
    with pytest.raises(CalibrationError, match=r"takes g, and .* in counts \(raw\), which cannot be converted"):
        written(body, STILL, options=ReadOptions(units={"acc": "raw"}))


def test_a_calibration_of_no_sensor_the_file_holds_is_refused(calibration):
    body, _ = calibration
    mag_only = REAL / "corpus" / "hmc5883l_esp32_still_counts" / "mag_data.csv"
    case = json.loads((mag_only.parent / "case.json").read_text())
    options = ReadOptions(**{k: v for k, v in case.get("form", {}).items() if k in ("columns", "chip")})
    said = r"corrects accelerometer, and mag_data\.csv holds magnetometer: apply it to a recording of the sensor"
    with pytest.raises(CalibrationError, match=said):
        written(body, mag_only, options=options)


@pytest.mark.parametrize(
    ("path", "fmt", "match"),
    [
        ("out.xyz", None, r"suffix '.xyz' names no format"),
        ("out.csv", "hdf5", r"unknown output format 'hdf5'"),
    ],
)
def test_an_unknown_output_format_is_refused(path, fmt, match):
    with pytest.raises(LogFormatError, match=match):
        output_format(Path(path), fmt)


def test_a_line_of_text_deep_in_a_streamed_csv_is_refused_naming_its_line(calibration, tmp_path):
    body, _ = calibration
    lines = STILL.read_text().splitlines()
    lines[2500] = "748,oops,15708"
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(LogFormatError, match="line 2501"):
        written(body, bad, chunk_rows=100, head_lines=500)


def test_a_json_longer_than_the_head_is_read_whole_and_said_so():
    """A Betaflight configurator's tumble export (14 127 lines of JSON): its first lines are no JSON, so it is read
    whole, then handed on in chunks."""
    path = REAL / "corpus" / "betaflight_compass_tumble_samples" / "calibration_samples_2026-06-11T03-08-04-544Z.json"
    chunked = read_in_chunks(path, name=path.name, chunk_rows=100)
    assert not chunked.streamed
    assert (
        chunked.log.notes[-1]
        == "read whole: betaflight_mag files are not read in chunks (a generic CSV, Parquet and .npy are)"
    )
    whole = read_log(path, name=path.name).mag
    assert np.array_equal(np.vstack([c.sensors["mag"] for c in chunked.chunks()]), whole)


def test_a_noise_characterisation_is_refused_in_its_own_words():
    """The board's still recording characterised (its noise), then applied: it corrects nothing."""
    from app.workflows.noise import characterise_log

    body = characterise_log(read_log(STILL, ReadOptions(sampling_rate_hz=100.0))).body()
    with pytest.raises(CalibrationError, match="a noise characterisation corrects nothing"):
        written(body, STILL)


def test_a_body_cut_short_is_refused_saying_what_it_lacks(calibration):
    body, _ = calibration
    with pytest.raises(CalibrationError, match=r"cannot be read back .*'model'"):
        written({k: v for k, v in body.items() if k != "model"}, STILL)


def test_a_parquet_recording_is_read_in_batches_as_the_reader_reads_it_whole(calibration, tmp_path):
    """The phone's recording written as Parquet (time, accelerometer in g, gyroscope, magnetometer), then read in
    batches: the same samples, units and seconds as its whole read, and the calibration applied the same."""
    body, result = calibration
    recording = tmp_path / "phone.parquet"
    with open(recording, "wb") as f:
        apply_to_file(body, HYPERIMU, f, fmt="parquet", options=ReadOptions(columns=HYPERIMU_COLUMNS))
    whole = read_log(recording, name=recording.name)
    chunked = read_in_chunks(recording, name=recording.name, chunk_rows=64, head_lines=100)
    assert chunked.streamed and chunked.log.units == whole.units == {"acc": "g", "gyr": "rad/s", "mag": "uT"}
    chunks = list(chunked.chunks())
    assert len(chunks) == -(-whole.n_samples // 64)
    for sensor in ("acc", "gyr", "mag"):
        assert np.array_equal(np.vstack([c.sensors[sensor] for c in chunks]), getattr(whole, sensor))
    assert np.array_equal(np.concatenate([c.time_s for c in chunks]), whole.time_s)
    applied, out = written(body, recording, chunk_rows=64, head_lines=100)
    assert applied.streamed and applied.passed == ("gyr", "mag")
    names, values = npy_columns(out)
    assert names[:4] == ("time (s)", "acc_x (g)", "acc_y (g)", "acc_z (g)")
    assert np.max(np.abs(values[:, 1:4] - result.apply(whole.acc, "acc"))) <= 1e-9


def test_a_npy_recording_is_memory_mapped_and_sliced(calibration, tmp_path):
    """The board's still recording saved as an N×3 .npy in g (as a wearable's export is): sliced, the same rows."""
    body, result = calibration
    acc = read_log(STILL).acc
    recording = tmp_path / "still.npy"
    np.save(recording, acc)
    applied, out = written(body, recording, chunk_rows=7, options=ReadOptions(units={"acc": "g"}))
    assert applied.streamed and applied.rows == 3000
    assert np.array_equal(npy_columns(out)[1], result.apply(acc, "acc"))


def test_a_temperature_column_passes_through_and_the_file_is_streamed(calibration, tmp_path):
    """A seeded warm-up (its noise the real board's, tests/temperature_logs.py) with a ``temp_c`` column, in g."""
    from tests.temperature_logs import warm_up_csv

    body, result = calibration
    recording = tmp_path / "warm_up.csv"
    recording.write_bytes(warm_up_csv(acc_in_g=True))
    whole = read_log(recording, ReadOptions(units={"acc": "g"}))
    applied, out = written(
        body, recording, fmt="csv", options=ReadOptions(units={"acc": "g"}), chunk_rows=500, head_lines=2000
    )
    assert applied.streamed and [c.name for c in applied.columns][-1] == "temp_c"
    text = out.getvalue().decode()
    rows = np.loadtxt(io.StringIO(text), delimiter=",", comments="#", skiprows=4)
    assert len(rows) == whole.n_samples > 2000
    assert np.array_equal(rows[:, -1], whole.temperature_c)
    assert np.max(np.abs(rows[:, 1:4] - result.apply(whole.acc, "acc"))) <= 1e-9
