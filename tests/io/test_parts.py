"""Recordings made of several files (app.io.readers.parts): the pose a file's name gives, the files joined."""

from __future__ import annotations

import zipfile

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.readers import read_log
from app.io.readers.parts import log_members, pose_from_name


@pytest.mark.parametrize(
    "name, pose",
    [
        ("x_axis_pos.csv", "+x"),
        ("x_axis_neg.csv", "-x"),
        ("y_axis_neg2.csv", "-y"),
        ("data/z_axis_pos.csv", "+z"),
        ("xpos.csv", "+x"),
        ("xneg", "-x"),
        ("xplus.csv", "+x"),
        ("xminus.csv", "-x"),  # merged words
        ("x_up.txt", "+x"),
        ("z_down.csv", "-z"),
        ("Y-UP.csv", "+y"),
        ("up_z.csv", "+z"),
        ("imu_data_posZ.csv", "+z"),
        ("imu_data_negZ.csv", "-z"),
        ("negx", "-x"),
        ("+x.csv", "+x"),
        ("-z.csv", "-z"),
        ("acc_-y.csv", "-y"),
        ("pose +x.csv", "+x"),
        ("x_p.csv", "+x"),
        ("x_a.csv", "-x"),
        ("z_n.csv", "-z"),  # imucal's region names: x_p parallel, x_a anti
        ("x_positive.csv", "+x"),
        ("y_negative.csv", "-y"),
    ],
)
def test_a_file_name_gives_the_up_axis(name, pose):
    assert pose_from_name(name) == pose


@pytest.mark.parametrize(
    "name",
    [
        "x_axis.csv",
        "log.csv",
        "box_up.csv",
        "imu-x.csv",
        "maxpos.csv",
        "1.csv",
        "still.csv",
        "xpos_yneg.csv",  # two poses: none
        "tux_down.csv",
        "experiment_up.csv",
    ],
)
def test_a_name_that_gives_no_single_pose_gives_none(name):
    assert pose_from_name(name) is None


def test_zip_members_of_the_system_are_left_out():
    members = [
        "poses/",
        "poses/x_axis_pos.csv",
        "__MACOSX/poses/._x_axis_pos.csv",
        "poses/.DS_Store",
        "poses/x_axis_neg.csv",
    ]
    assert log_members(members) == ["poses/x_axis_pos.csv", "poses/x_axis_neg.csv"]


def _csv(rows, header="t,acc_x,acc_y,acc_z"):
    return header + "\n" + "".join(",".join(f"{v:g}" for v in r) + "\n" for r in rows)


def test_a_zip_of_pose_files_is_read_file_by_file_and_joined(tmp_path):
    rng = np.random.default_rng(22)
    p = tmp_path / "poses.zip"
    truth = {}
    with zipfile.ZipFile(p, "w") as zf:
        for i, (name, g) in enumerate((("x_up.csv", [9.81, 0, 0]), ("z_down.csv", [0, 0, -9.81]))):
            rate = 50.0 * (i + 1)  # each file its own rate, and its own clock (starting anywhere)
            t = 1000.0 * (7 + i) + np.arange(120 * (i + 1)) * 1000.0 / rate
            acc = np.asarray(g) + 0.01 * rng.standard_normal((len(t), 3))
            truth[name] = (rate, acc)
            zf.writestr(name, _csv(np.column_stack([t, acc])))
    log = read_log(p, name="poses.zip")
    assert [(q.filename, q.start, q.end) for q in log.parts] == [("x_up.csv", 0, 120), ("z_down.csv", 120, 360)]
    assert [q.sampling_rate_hz for q in log.parts] == pytest.approx([50.0, 100.0])
    np.testing.assert_allclose(log.acc, np.vstack([truth["x_up.csv"][1], truth["z_down.csv"][1]]), atol=1e-5)
    # Time runs on from one file to the next, one interval apart.
    assert np.all(np.diff(log.time_s) > 0)
    assert log.time_s[120] - log.time_s[119] == pytest.approx(1 / 50.0)
    assert log.sampling_rate_hz == pytest.approx((120 * 50 + 240 * 100) / 360)


def test_files_in_different_units_are_refused_naming_both(tmp_path):
    p = tmp_path / "poses.zip"
    with zipfile.ZipFile(p, "w") as zf:
        zf.writestr(
            "x_up.csv", _csv([[0, 9.81, 0, 0], [10, 9.81, 0, 0]], "t_ms,acc_x (m/s^2),acc_y (m/s^2),acc_z (m/s^2)")
        )
        zf.writestr("x_down.csv", _csv([[0, -1, 0, 0], [10, -1, 0, 0]], "t_ms,acc_x (g),acc_y (g),acc_z (g)"))
    with pytest.raises(LogFormatError, match=r"x_down.csv reads the acc in g but x_up.csv in m/s\^2: give the unit"):
        read_log(p, name="poses.zip")


def test_a_zip_whose_files_expand_past_the_limit_together_is_refused(tmp_path, monkeypatch):
    from app.io.readers import table

    p = tmp_path / "poses.zip"
    with zipfile.ZipFile(p, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        for name in ("x_up.csv", "x_down.csv"):
            zf.writestr(name, _csv([[i, 9.81, 0, 0] for i in range(400)]))
    size = sum(i.file_size for i in zipfile.ZipFile(p).infolist())
    monkeypatch.setattr(table, "MAX_UNZIPPED_BYTES", size - 1)  # each file alone passes, together they do not
    with pytest.raises(LogFormatError, match=rf"the files in poses.zip expand to {size} bytes together") as err:
        read_log(p, name="poses.zip")
    assert err.value.status == 413
