"""``trical calibrate a.csv b.csv …``: a maker's pose files, one calibration (issue 22, point 4)."""

from __future__ import annotations

import json
import shutil

from tests.cli_in_process import trical
from tests.conftest import DATA

POSES = DATA / "real" / "mpu6050_pose_files"
ORDER = ("x_axis_pos", "x_axis_neg", "y_axis_pos", "y_axis_neg", "z_axis_pos", "z_axis_neg")


def test_calibrate_several_files_names_each_pose_by_its_file(tmp_path):
    paths = [str(POSES / f"{s}.csv") for s in ORDER]
    out = trical("calibrate", *paths, "--unit", "m/s^2", "--json", tmp_path=tmp_path)
    assert out.returncode == 0, out.stderr
    body = json.loads(out.stdout)
    assert body["method"] == "six_position" and body["ok"] and body["id"].startswith("cal_")
    assert [(r["source"], r["up"]) for r in body["readings"]] == [
        ("x_axis_pos.csv", "+x"),
        ("x_axis_neg.csv", "-x"),
        ("y_axis_pos.csv", "+y"),
        ("y_axis_neg.csv", "-y"),
        ("z_axis_pos.csv", "+z"),
        ("z_axis_neg.csv", "-z"),
    ]
    assert body["label"] == ", ".join(f"{s}.csv" for s in ORDER)
    human = trical("calibrate", *paths, "--unit", "m/s^2", "--no-store", tmp_path=tmp_path)
    lines = human.stdout.splitlines()
    assert lines[0].startswith("--method auto, chosen from the recording: 6 still poses"), lines[0]
    lines = lines[1:]  # the choice said, the summary as before
    assert (
        lines[0] == "6 still segments in 1200 samples of 6 files at 62.8687 Hz; used [0, 1, 2, 3, 4, 5]"
    )  # the span of the files' ms stamps
    assert (
        lines[1] == "Apply it: error on the 6 poses fitted 32.1\u00a0mg → 0.58\u00a0mg (a level off by 1.8° → 0.03°)."
    )
    assert lines[3:9] == [
        "x_axis_pos.csv: +x up, mean 10.2001  -0.0428  -0.0932",
        "x_axis_neg.csv: -x up, mean -9.4339  -0.2734  0.9238",
        "y_axis_pos.csv: +y up, mean 0.2958  9.7295  0.4899",
        "y_axis_neg.csv: -y up, mean 0.4618  -9.9932  0.3850",
        "z_axis_pos.csv: +z up, mean 0.8286  -0.1827  10.4105",
        "z_axis_neg.csv: -z up, mean -0.0548  -0.0848  -9.5370",
    ]


def test_a_misnamed_file_is_labelled_by_its_data_with_a_warning(tmp_path):
    for s in ORDER:
        shutil.copy(POSES / f"{s}.csv", tmp_path / f"{s}.csv")
    (tmp_path / "z_axis_pos.csv").rename(tmp_path / "tmp.csv")
    (tmp_path / "z_axis_neg.csv").rename(tmp_path / "z_axis_pos.csv")
    (tmp_path / "tmp.csv").rename(tmp_path / "z_axis_neg.csv")
    out = trical(
        "calibrate", *(str(tmp_path / f"{s}.csv") for s in ORDER), "--unit", "m/s^2", "--no-store", tmp_path=tmp_path
    )
    assert out.returncode == 0, out.stderr
    assert "z_axis_pos.csv: -z up, mean" in out.stdout and "z_axis_neg.csv: +z up, mean" in out.stdout
    assert (
        "warning: z_axis_pos.csv names +z up, but its still reading points -z up: the data's pose was used — "
        "check the file's name, or how the board lay"
    ) in out.stdout.splitlines()


def test_two_files_of_one_name_and_a_missing_file_are_one_line_errors(tmp_path):
    (tmp_path / "a").mkdir()
    shutil.copy(POSES / "x_axis_pos.csv", tmp_path / "a" / "x_axis_pos.csv")
    out = trical(
        "calibrate",
        str(POSES / "x_axis_pos.csv"),
        str(tmp_path / "a" / "x_axis_pos.csv"),
        "--unit",
        "m/s^2",
        "--no-store",
        tmp_path=tmp_path,
    )
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr == (
        "trical: error: x_axis_pos.csv is given more than once: give each pose's file once, each with its own name\n"
    )
    missing = trical(
        "calibrate", str(POSES / "x_axis_pos.csv"), str(tmp_path / "x_axis_neg.csv"), "--no-store", tmp_path=tmp_path
    )
    assert missing.returncode == 2 and missing.stderr == f"trical: error: no such file: {tmp_path / 'x_axis_neg.csv'}\n"
