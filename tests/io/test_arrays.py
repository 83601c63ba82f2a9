""".npy and Parquet readers (app/io/readers/arrays.py) and the dispatch by suffix."""

from __future__ import annotations

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from app.io.errors import LogFormatError
from app.io.readers import read_log
from app.io.readers.arrays import read_npy_log, read_parquet_log
from app.io.readers.read_options import ReadOptions


def _samples(n=1000, seed=0):
    rng = np.random.default_rng(seed)
    return (np.array([0.0, 0.0, 1.0]) + 0.01 * rng.standard_normal((n, 3))).astype(np.float32)


def test_npy_n_by_3_is_memory_mapped(tmp_path):
    x = _samples()
    f = tmp_path / "rec.npy"
    np.save(f, x)
    log = read_npy_log(f, sampling_rate_hz=50.0, units={"acc": "g"})
    assert isinstance(log.acc, np.memmap) or isinstance(log.acc.base, np.memmap)
    assert log.acc.dtype == np.float32 and log.acc.shape == (1000, 3)
    assert np.array_equal(np.asarray(log.acc), x)
    assert log.sampling_rate_hz == 50.0 and log.units == {"acc": "g"} and log.format == "npy"
    assert log.time_s is None


def test_npy_n_by_4_takes_the_rate_from_the_time_column(tmp_path):
    x = _samples(500)
    t = np.arange(500) * 0.01  # seconds
    f = tmp_path / "rec.npy"
    np.save(f, np.column_stack([t, x]))
    log = read_npy_log(f)
    assert log.sampling_rate_hz == pytest.approx(100.0)
    assert np.allclose(log.acc, x) and log.time_s[-1] == pytest.approx(4.99)
    np.save(f, np.column_stack([np.arange(500) * 10_000_000, x]))  # nanoseconds
    assert read_npy_log(f).sampling_rate_hz == pytest.approx(100.0)
    assert read_npy_log(f, sampling_rate_hz=25.0).sampling_rate_hz == 25.0


@pytest.mark.parametrize(
    "content, match",
    [
        (b"acc_x,acc_y,acc_z\n1,2,3\n", "not a readable .npy"),
        (b"", "not a readable .npy"),
        (b"\x93NUMPY\x01\x00garbage", "not a readable .npy"),
    ],
)
def test_unreadable_npy_is_a_clear_415(tmp_path, content, match):
    f = tmp_path / "bad.npy"
    f.write_bytes(content)
    with pytest.raises(LogFormatError, match=match) as err:
        read_npy_log(f, sampling_rate_hz=100.0)
    assert err.value.status == 415


def test_npy_wrong_shapes_and_no_rate(tmp_path):
    f = tmp_path / "rec.npy"
    np.save(f, np.zeros((10, 5)))
    with pytest.raises(LogFormatError, match=r"holds rows of 5 numbers: save one row per sample with 3 numbers"):
        read_npy_log(f, sampling_rate_hz=1.0)
    np.save(f, np.array(["a", "b", "c"]).reshape(1, 3))
    with pytest.raises(LogFormatError, match="expected numbers"):
        read_npy_log(f, sampling_rate_hz=1.0)
    np.save(f, np.zeros((0, 3)))
    with pytest.raises(LogFormatError, match="no samples"):
        read_npy_log(f, sampling_rate_hz=1.0)
    np.save(f, np.zeros((10, 3)))
    # No time column and no rate: read, without a rate (the methods that need one ask for it).
    log = read_npy_log(f)
    assert log.sampling_rate_hz is None and log.timing.source == "none"
    assert any("no time column" in n for n in log.notes)
    with pytest.raises(LogFormatError, match="unit"):
        read_npy_log(f, sampling_rate_hz=1.0, units={"acc": "furlongs"})
    with pytest.raises(FileNotFoundError):
        read_npy_log(tmp_path / "missing.npy", sampling_rate_hz=1.0)


def test_parquet_with_time_and_named_columns(tmp_path):
    x = _samples(400)
    f = tmp_path / "rec.parquet"
    table = pa.table(
        {"time_ms": np.arange(400) * 20.0, "acc_x": x[:, 0], "acc_y": x[:, 1], "acc_z": x[:, 2], "note": ["a"] * 400}
    )
    pq.write_table(table, f)
    log = read_parquet_log(f, units={"acc": "g"})
    assert log.sampling_rate_hz == pytest.approx(50.0)
    assert np.allclose(log.acc, x) and log.format == "parquet"
    assert log.time_s[-1] == pytest.approx(399 * 0.02)


def test_parquet_reads_the_gyroscope_and_magnetometer_beside_the_accelerometer(tmp_path):
    x, w, b = _samples(400), _samples(400) * 0.01, _samples(400) * 5
    f = tmp_path / "imu.parquet"
    pq.write_table(
        pa.table(
            {
                "time_s": np.arange(400) / 100.0,
                **{f"acc_{a}": x[:, i] for i, a in enumerate("xyz")},
                **{f"gyr_{a} (deg/s)": w[:, i] for i, a in enumerate("xyz")},
                **{f"mag_{a}": b[:, i] for i, a in enumerate("xyz")},
            }
        ),
        f,
    )
    log = read_parquet_log(f)
    assert np.allclose(log.gyr, w) and np.allclose(log.mag, b) and log.channels == ["acc", "gyr", "mag"]
    assert log.units == {"acc": "m/s^2", "gyr": "deg/s", "mag": "uT"}


def test_parquet_timestamp_column(tmp_path):
    x = _samples(300)
    ts = np.datetime64("2026-01-01T00:00:00") + np.arange(300) * np.timedelta64(10, "ms")
    f = tmp_path / "rec.pq"
    pq.write_table(
        pa.table({"timestamp": pa.array(ts, type=pa.timestamp("ms")), "x": x[:, 0], "y": x[:, 1], "z": x[:, 2]}), f
    )
    log = read_log(f)
    assert log.format == "parquet" and log.sampling_rate_hz == pytest.approx(100.0)


def test_parquet_errors(tmp_path):
    f = tmp_path / "bad.parquet"
    f.write_text("acc_x,acc_y,acc_z\n1,2,3\n")
    with pytest.raises(LogFormatError, match="not a readable Parquet") as err:
        read_parquet_log(f, sampling_rate_hz=1.0)
    assert err.value.status == 415
    pq.write_table(pa.table({"a": [1.0], "b": [2.0]}), f)
    with pytest.raises(LogFormatError, match="no accelerometer"):
        read_parquet_log(f, sampling_rate_hz=1.0)
    pq.write_table(pa.table({"x": [1.0, 2.0], "y": [1.0, 2.0], "z": [1.0, 2.0]}), f)
    assert read_parquet_log(f).sampling_rate_hz is None  # no time column, none given: no rate
    pq.write_table(pa.table({"gyr_x": [1.0, 2.0], "gyr_y": [1.0, 2.0], "gyr_z": [1.0, 2.0]}), f)
    log = read_parquet_log(f, sampling_rate_hz=10.0)  # a gyroscope alone
    assert log.acc is None and log.channels == ["gyr"] and log.sampling_rate_hz == 10.0


def test_read_log_dispatches_by_suffix(tmp_path):
    x = _samples(200)
    csv = tmp_path / "rec.csv"
    csv.write_text("acc_x,acc_y,acc_z\n" + "\n".join(",".join(f"{v:.6f}" for v in row) for row in x))
    assert read_log(csv, ReadOptions(sampling_rate_hz=10.0)).format == "csv"
    npy = tmp_path / "rec.npy"
    np.save(npy, x)
    assert read_log(npy, ReadOptions(sampling_rate_hz=10.0)).format == "npy"
