"""``trical import FILE``: a device's own calibration read from its firmware's file, stored, and exported again; a
file of no accepted kind is one line on stderr and exit status 2."""

from __future__ import annotations

import json
from pathlib import Path

from tests.cli_in_process import run_main

REAL = Path(__file__).resolve().parent / "data" / "real"


def _env(tmp_path: Path) -> dict[str, str]:
    return {"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}", "TRICAL_RECORDINGS_DIR": str(tmp_path / "r")}


def test_import_stores_the_device_s_calibration_and_export_writes_it_for_inav(tmp_path):
    env = _env(tmp_path)
    path = REAL / "imports" / "px4_1.12_flight1_cal.params"
    r = run_main(["import", str(path), "--device-id", "fc1", "--json"], env, tmp_path)
    assert r.returncode == 0, r.stderr
    body = json.loads(r.stdout)
    assert body["method"] == "imported" and body["device_id"] == "fc1" and body["label"] == path.name
    assert body["read_from"]["firmware"] == "PX4" and body["read_from"]["version"] == "1.12.3"
    assert body["model"]["acc_o"][1] == 0.202201366424560547
    r = run_main(["export", body["id"], "--format", "inav"], env, tmp_path)
    assert r.returncode == 0, r.stderr
    # CAL_ACC0_YOFF 0.2022 m/s² = 42.2 counts at 2048 per g; CAL_ACC0_ZSCALE 0.97539 = 3995 / 4096
    assert "set acczero_y = 42" in r.stdout and "set accgain_z = 3995" in r.stdout
    r = run_main(["import", str(path), "--no-store"], env, tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[0] == "Apply it: it passed every check."
    assert "imported from PX4 1.12.3 (QGroundControl .params)" in r.stdout and "stored as" not in r.stdout


def test_a_file_of_no_accepted_kind_is_one_line_naming_the_option(tmp_path):
    path = tmp_path / "notes.txt"
    path.write_text("hello\n")
    r = run_main(["import", str(path)], _env(tmp_path), tmp_path)
    assert r.returncode == 2
    assert r.stderr.startswith("trical: error: the file holds no parameter") and len(r.stderr.splitlines()) == 1
    assert "--firmware" in r.stderr and "`firmware`" not in r.stderr
