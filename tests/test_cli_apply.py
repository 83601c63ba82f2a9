"""`trical apply CAL FILE -o OUT`: the MPU-6050 board's fit on its ten real still poses applied to its real 30 s
still recording, the calibration stored (by id) or in a JSON file; errors name this command's flags (the command
run in this process, tests/cli_in_process.py)."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pyarrow.parquet as pq
import pytest

from app.calibration.still.triangular import fit_triangular
from app.io.readers import read_log
from app.store import open_store
from tests.cli_in_process import trical
from tests.real_recordings import REAL, mpu6050_session1

STILL = REAL / "mpu6050_session2_still_30s.csv"


@pytest.fixture
def fitted():
    result = dataclasses.replace(fit_triangular(mpu6050_session1(), gravity=1.0), unit="g")
    return result.to_dict(), result


@pytest.fixture
def stored(tmp_path, fitted):
    """The calibration stored in the database the command opens (TRICAL_DATABASE_URL under ``tmp_path``)."""
    body, _ = fitted
    store = open_store(f"sqlite:///{tmp_path / 'trical.db'}", tmp_path / "recordings")
    return store.add_calibration({**body, "device_id": "mpu6050"}, owner=None)["id"]


def test_a_stored_calibration_applied_by_id_writes_npy_named_with_units(tmp_path, stored, fitted):
    _, result = fitted
    out = tmp_path / "calibrated.npy"
    r = trical("apply", stored, STILL, "-o", out, tmp_path=tmp_path)
    assert r.returncode == 0, r.stderr
    assert f"wrote {out}: 3000 rows (npy); acc corrected (g)" in r.stderr
    arr = np.load(out)
    assert arr.dtype.names == ("acc_x (g)", "acc_y (g)", "acc_z (g)")
    got = np.column_stack([arr[n] for n in arr.dtype.names])
    assert np.max(np.abs(got - result.apply(read_log(STILL).acc, "acc"))) <= 1e-9


def test_a_calibration_file_and_format_parquet_with_json_summary(tmp_path, fitted):
    body, result = fitted
    cal = tmp_path / "cal.json"
    cal.write_text(json.dumps(body))
    out = tmp_path / "calibrated.data"
    r = trical("apply", cal, STILL, "-o", out, "--format", "parquet", "--json", tmp_path=tmp_path)
    assert r.returncode == 0, r.stderr
    said = json.loads(r.stdout)
    assert said["rows"] == 3000 and said["corrected"] == ["acc"] and said["format"] == "parquet"
    assert [c["name"] for c in said["columns"]] == ["acc_x (g)", "acc_y (g)", "acc_z (g)"]
    table = pq.read_table(out)
    assert table.schema.field("acc_z (g)").metadata[b"unit"] == b"g"
    acc = np.column_stack([table.column(f"acc_{a} (g)").to_numpy() for a in "xyz"])
    assert np.max(np.abs(acc - result.apply(read_log(STILL).acc, "acc"))) <= 1e-9


def test_errors_name_this_commands_flags_and_leave_no_file(tmp_path, stored):
    out = tmp_path / "out.xyz"
    r = trical("apply", stored, STILL, "-o", out, tmp_path=tmp_path)
    assert r.returncode == 2 and "give --format (one of csv, parquet, npy)" in r.stderr
    r = trical("apply", stored, STILL, "-o", tmp_path / "out.csv", "--unit", "raw", tmp_path=tmp_path)
    assert r.returncode == 2
    assert "model takes g, and mpu6050_session2_still_30s.csv gives its accelerometer in counts (raw)" in r.stderr
    assert "--chip or --lsb-per-g" in r.stderr
    assert not (tmp_path / "out.csv").exists() and list(tmp_path.glob(".*part")) == []
    r = trical("apply", "cal_0000", STILL, "-o", tmp_path / "out.csv", tmp_path=tmp_path)
    assert r.returncode == 2 and "no calibration with id 'cal_0000'" in r.stderr
    r = trical("apply", "nothing-here", STILL, "-o", tmp_path / "out.csv", tmp_path=tmp_path)
    assert r.returncode == 2 and "neither a file nor a calibration id" in r.stderr


def test_the_json_that_trical_export_writes_is_a_calibration_file_too(tmp_path, stored, fitted):
    _, result = fitted
    exported = tmp_path / "exported.json"
    assert trical("export", stored, "--format", "json", "-o", exported, tmp_path=tmp_path).returncode == 0
    out = tmp_path / "calibrated.csv"
    r = trical("apply", exported, STILL, "-o", out, tmp_path=tmp_path)
    assert r.returncode == 0, r.stderr
    lines = out.read_text().splitlines()
    assert lines[0] == f"# calibrated by trical with calibration {stored} (triangular) from {STILL.name}"
    assert lines[2] == "acc_x (g),acc_y (g),acc_z (g)"
    rows = np.loadtxt(lines[3:], delimiter=",")
    assert np.max(np.abs(rows - result.apply(read_log(STILL).acc, "acc"))) <= 1e-9
