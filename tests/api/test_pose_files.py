"""One file per pose (issue 22, point 4), through the API: several files, or a zip of them, are one recording.

The files are a maker's real ones (tests/data/real/README.md): an MPU-6050 logged over a serial port,
one file per pose (`x_axis_pos.csv`, …), header ``aX (g)`` over values in m/s² — so every upload here
gives ``acc_unit=m/s^2``. The maker's own fit (imucal's Ferraris calibration) stands beside trical's.
"""

from __future__ import annotations

import io
import json
import zipfile

import numpy as np
import pytest
from pydantic import TypeAdapter

from app.api.schemas.calibrations import CalibrationOut
from app.api.schemas.recordings import RecordingOut
from tests.api.test_typed_contract import undescribed
from tests.conftest import DATA, make_settings

POSES = DATA / "real" / "mpu6050_pose_files"
ORDER = ("x_axis_pos", "x_axis_neg", "y_axis_pos", "y_axis_neg", "z_axis_pos", "z_axis_neg")
UP = {
    "x_axis_pos": "+x",
    "x_axis_neg": "-x",
    "y_axis_pos": "+y",
    "y_axis_neg": "-y",
    "z_axis_pos": "+z",
    "z_axis_neg": "-z",
}
PEER = json.loads((DATA / "real" / "mpu6050_pose_files_peer.json").read_text())
UNIT = {"acc_unit": "m/s^2"}


def pose_bytes(stem: str, rows: int | None = None) -> bytes:
    data = (POSES / f"{stem}.csv").read_bytes()
    if rows is None:
        return data
    return b"".join(data.splitlines(keepends=True)[: rows + 1])


def file_notes(rec: dict) -> list[str]:
    """The recording's notes on its files, without the time column's unit (said once for all files)."""
    return [n for n in rec["notes"] if not n.startswith("time column ")]


def upload_files(client, files: list[tuple[str, bytes]], **form):
    return client.post(
        "/api/v1/recordings",
        files=[("file", (name, content, "text/csv")) for name, content in files],
        data={**UNIT, **form},
    )


def six(rows: int | None = None, names=None) -> list[tuple[str, bytes]]:
    names = names or {s: f"{s}.csv" for s in ORDER}
    return [(names[s], pose_bytes(s, rows)) for s in ORDER]


def test_six_pose_files_are_one_recording_each_segment_naming_its_file(client, settings):
    r = upload_files(client, six())
    assert r.status_code == 201, r.text
    rec = r.json()
    assert undescribed(TypeAdapter(RecordingOut).validate_python(rec)) == []
    assert [p["filename"] for p in rec["parts"]] == [f"{s}.csv" for s in ORDER]  # the order given
    assert [p["pose_from_name"] for p in rec["parts"]] == [UP[s] for s in ORDER]
    assert [(p["start"], p["end"]) for p in rec["parts"]] == [(200 * i, 200 * (i + 1)) for i in range(6)]
    assert rec["n_samples"] == 1200 and rec["sampling_rate_hz"] == pytest.approx(62.5, abs=0.5)
    # One still segment per file, inside it, labelled by the data as the file's name says.
    assert [(s["source"], s["up"], s["part"]) for s in rec["segments"]] == [
        (f"{s}.csv", UP[s], i) for i, s in enumerate(ORDER)
    ]
    assert all(p["start"] <= s["start"] < s["end"] <= p["end"] for s, p in zip(rec["segments"], rec["parts"]))
    # The files' time column says no unit: read in ms from its step, said once for the six files.
    assert rec["notes"] == ["time column 'Timestamp' read in ms (from its step)"]
    # Nothing acknowledged is lost: the stored recording holds every file, byte for byte, under its name.
    stored = next(settings.recordings_dir.glob(f"{rec['id']}*"))
    with zipfile.ZipFile(stored) as zf:
        assert zf.namelist() == [f"{s}.csv" for s in ORDER]
        assert all(zf.read(f"{s}.csv") == pose_bytes(s) for s in ORDER)
    assert client.get(f"/api/v1/recordings/{rec['id']}").json() == rec


def test_the_calibration_names_each_reading_s_file(client):
    rec = upload_files(client, six()).json()
    r = client.post("/api/v1/calibrations", json={"method": "auto", "recording_id": rec["id"]})
    assert r.status_code == 201, r.text
    body = r.json()
    assert undescribed(TypeAdapter(CalibrationOut).validate_python(body)) == []
    assert body["method"] == "six_position" and body["ok"] and body["verdict"]["apply"]
    assert sorted((x["source"], x["up"]) for x in body["readings"]) == sorted((f"{s}.csv", UP[s]) for s in ORDER)
    assert not any("names" in w for w in body["warnings"])
    # Read back from the store (the zip read again, file by file), the same calibration.
    again = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]}).json()
    np.testing.assert_allclose(again["model"]["X"], body["model"]["X"], rtol=0, atol=1e-12)
    assert [x["source"] for x in again["readings"]] == [x["source"] for x in body["readings"]]


def test_a_zip_of_the_pose_files_is_the_same_recording(client):
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("__MACOSX/._x_axis_pos.csv", b"\x00\x05\x16\x07")
        for s in ORDER:
            zf.writestr(f"poses/{s}.csv", pose_bytes(s))
        zf.writestr("poses/photo_of_the_jig.jpg", b"\xff\xd8\xff")
    r = client.post("/api/v1/recordings", files={"file": ("poses.zip", buf.getvalue(), "application/zip")}, data=UNIT)
    assert r.status_code == 201, r.text
    rec = r.json()
    files = upload_files(client, six()).json()
    assert [p["filename"] for p in rec["parts"]] == [p["filename"] for p in files["parts"]]
    assert [s["acc_mean"] for s in rec["segments"]] == [s["acc_mean"] for s in files["segments"]]
    assert file_notes(rec) == ["poses.zip: poses/photo_of_the_jig.jpg left out (not a log file)"]


def test_a_file_whose_name_contradicts_its_data_is_labelled_by_the_data_with_a_warning(client):
    # The maker swapped two names: x_axis_pos.csv holds the -x pose and x_axis_neg.csv the +x pose.
    swapped = {**{s: f"{s}.csv" for s in ORDER}, "x_axis_pos": "x_axis_neg.csv", "x_axis_neg": "x_axis_pos.csv"}
    rec = upload_files(client, six(names=swapped)).json()
    segs = {s["source"]: s for s in rec["segments"]}
    assert (segs["x_axis_neg.csv"]["up"], segs["x_axis_neg.csv"]["pose_from_name"]) == ("+x", "-x")
    assert (segs["x_axis_pos.csv"]["up"], segs["x_axis_pos.csv"]["pose_from_name"]) == ("-x", "+x")
    assert file_notes(rec) == [
        "x_axis_neg.csv: its name says -x up, but its still readings point +x up: the data's label is used — "
        "check the file's name, or how the board lay",
        "x_axis_pos.csv: its name says +x up, but its still readings point -x up: the data's label is used — "
        "check the file's name, or how the board lay",
    ]
    body = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]}).json()
    assert body["ok"]
    named = [w for w in body["warnings"] if "names" in w]
    assert named == [
        "x_axis_neg.csv names -x up, but its still reading points +x up: the data's pose was used — check the "
        "file's name, or how the board lay",
        "x_axis_pos.csv names +x up, but its still reading points -x up: the data's pose was used — check the "
        "file's name, or how the board lay",
    ]
    # The data decide: the same calibration as with the right names.
    right = client.post(
        "/api/v1/calibrations",
        json={"method": "six_position", "recording_id": upload_files(client, six()).json()["id"]},
    ).json()
    np.testing.assert_allclose(body["model"]["X"], right["model"]["X"], rtol=0, atol=1e-12)


def test_trical_s_figures_beside_the_maker_s_ferraris_fit(client):
    """The maker fitted imucal's Ferraris calibration on the first 100 samples of each file with g = 9.81."""
    rec = upload_files(client, six(rows=PEER["samples_per_pose"])).json()
    assert [s["count"] for s in rec["segments"]] == [100] * 6
    body = client.post(
        "/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"], "gravity": PEER["gravity"]}
    ).json()
    K, R, b = np.diag(PEER["K"]), np.asarray(PEER["R"]), np.asarray(PEER["b"])
    # The same matrix (both take each axis's column from its two poses: (m₊ − m₋) / 2g) ...
    np.testing.assert_allclose(body["model"]["X"], K @ R, rtol=0, atol=1e-7)
    # ... and an offset within 0.011 m/s² (about 1 mg): Ferraris takes each axis's offset from its own two poses,
    # the closed form of Georgieva et al. (ESGI'95, section 3.3.1) the mean of the three pairs.
    offset = np.asarray(body["model"]["y"]) - b
    np.testing.assert_allclose(offset, [-0.0008, -0.0101, -0.0068], rtol=0, atol=2e-4)
    means = np.array([x["mean"] for x in body["readings"]])
    g = PEER["gravity"]

    def error_mg(a):
        return 1000 * np.mean(np.abs(np.linalg.norm(a, axis=1) - g) / g)

    peer = (np.linalg.inv(R) @ np.linalg.inv(K) @ (means - b).T).T
    ours = (np.linalg.inv(np.asarray(body["model"]["X"])) @ (means - body["model"]["y"]).T).T
    assert error_mg(means) == pytest.approx(32.13, abs=0.01)
    assert body["metrics"]["error_before_mg"] == pytest.approx(32.13, abs=0.01)
    assert error_mg(ours) == pytest.approx(0.62, abs=0.01) == body["metrics"]["error_after_mg"]
    assert error_mg(peer) == pytest.approx(0.03, abs=0.01)


@pytest.mark.parametrize(
    "files, status, words",
    [
        (
            [
                ("x_axis_pos.csv", b"t,acc_x,acc_y,acc_z\n0,9.8,0,0\n1,9.8,0,0\n"),
                ("x_axis_pos.csv", b"t,acc_x,acc_y,acc_z\n0,-9.8,0,0\n1,-9.8,0,0\n"),
            ],
            422,
            "x_axis_pos.csv is given more than once: give each pose's file once",
        ),
        (
            [
                ("x_axis_pos.csv", pose_bytes("x_axis_pos")),
                (
                    "x_axis_neg.csv",
                    b"t,acc_x,acc_y,acc_z\n" + b"".join(f"{16 * i},-9.4,-0.3,0.9\n".encode() for i in range(200)),
                ),
            ],
            422,
            "x_axis_neg.csv holds acc but x_axis_pos.csv holds acc, gyr: every file of one calibration needs the same "
            "sensors",
        ),
        ([("a.csv", pose_bytes("x_axis_pos")), ("b.zip", b"PK\x03\x04")], 422, "b.zip is a zip inside a recording"),
    ],
)
def test_files_that_cannot_be_one_recording_are_refused_by_name(client, files, status, words):
    r = upload_files(client, files)
    assert r.status_code == status and r.json()["code"] == "unreadable_log", r.text
    assert words in r.json()["detail"] and "shape" not in r.json()["detail"]


def test_the_size_limit_counts_every_file(tmp_path):
    from fastapi.testclient import TestClient

    from app.main import create_app

    settings = make_settings(tmp_path, max_upload_mb=0.04)  # 41 943 bytes: four pose files are ~35 kB, six ~52 kB
    with TestClient(create_app(settings), raise_server_exceptions=False) as c:
        assert upload_files(c, six()[:4]).status_code == 201
        r = upload_files(c, six())
        assert r.status_code == 413 and r.json()["code"] == "payload_too_large"
    assert sorted(p.suffix for p in settings.recordings_dir.iterdir()) == [".zip"]  # the refused one left nothing


def test_the_noise_of_pose_files_is_one_file_s_never_across_files(client):
    rec = upload_files(client, six()).json()
    r = client.post("/api/v1/calibrations", json={"method": "noise", "recording_id": rec["id"], "sensors": ["acc"]})
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["warnings"][0].startswith("the recording is made of 6 files: the noise is characterised on one, ")
    chosen = body["warnings"][0].split("one, ")[1].split(" (")[0]
    assert chosen in {f"{s}.csv" for s in ORDER}
    # The figures are the chosen file's alone, uploaded by itself.
    alone = upload_files(client, [(chosen, pose_bytes(chosen.removesuffix(".csv")))]).json()
    single = client.post(
        "/api/v1/calibrations", json={"method": "noise", "recording_id": alone["id"], "sensors": ["acc"]}
    ).json()
    np.testing.assert_allclose(
        body["model"]["acc"]["noise_density"], single["model"]["acc"]["noise_density"], rtol=1e-12
    )
    assert body["model"]["acc"]["noise_density"][0] < 2e-3  # m/s²/√Hz: a still file's, not a pose change's


def test_pose_files_without_a_rate_are_stored_and_their_noise_asks_for_the_rate(client):
    # No time column and no rate given: the upload is stored, each file's rate unknown (it was a 500 after the
    # recording was saved: the answer's schema wanted a number); the noise, which needs the rate, asks for it as
    # it asks of one file without one (it was a TypeError, a 500, before the type checker found it).
    files = [(name, b"\n".join(line.split(b",", 1)[1] for line in data.splitlines()) + b"\n") for name, data in six()]
    r = upload_files(client, files)
    assert r.status_code == 201, r.text
    rec = r.json()
    assert len(rec["parts"]) == 6 and all(p["sampling_rate_hz"] is None for p in rec["parts"])
    r = client.post("/api/v1/calibrations", json={"method": "noise", "recording_id": rec["id"], "sensors": ["acc"]})
    assert r.status_code == 422, r.text
    assert "method noise needs the sensor's sampling rate" in r.json()["detail"]
    # the still poses need no rate: their calibration is the one a log with times gives
    assert client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]}).json()["ok"]


def test_pose_files_too_short_for_a_still_segment_are_each_one_reading(client):
    # 60 samples (0.96 s) per pose, under the 1.5 s a still segment needs: each file, still all through, is its
    # pose's reading, and the calibration is the one its means give.
    rec = upload_files(client, six(rows=60)).json()
    assert [(s["source"], s["up"], s["count"], s["end"] - s["start"]) for s in rec["segments"]] == [
        (f"{s}.csv", UP[s], 60, 60) for s in ORDER
    ]
    assert len(file_notes(rec)) == 6 and file_notes(rec)[0].startswith(
        "x_axis_pos.csv: 1.0 s, shorter than the 1.5 s a still segment needs, but still all through (spread "
    )
    body = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]}).json()
    assert body["ok"]
    means = [np.loadtxt(io.BytesIO(pose_bytes(s, 60)), delimiter=",", skiprows=1)[:, 1:4].mean(axis=0) for s in ORDER]
    np.testing.assert_allclose([r["mean"] for r in body["readings"]], means, rtol=0, atol=1e-12)


def test_a_short_file_that_moved_gives_no_reading(client):
    # Its gyroscope reads like the real files' (rad/s printed to 2 decimals): a constant 1.6 there would be a
    # 92 °/s offset in rad/s, which its data would read as °/s — another unit than the other file's.
    moving = b"Timestamp,aX (g),aY (g),aZ (g),Temp (C),gX,gY,gZ\n" + b"".join(
        f"{16 * i},{9.8 * np.cos(i / 10):.3f},{9.8 * np.sin(i / 10):.3f},0.1,26.9,0.0,0.0,0.02\n".encode()
        for i in range(60)
    )
    rec = upload_files(client, [("x_axis_pos.csv", pose_bytes("x_axis_pos")), ("x_up_again.csv", moving)]).json()
    assert [s["source"] for s in rec["segments"]] == ["x_axis_pos.csv"]
    assert file_notes(rec) == [
        "x_up_again.csv: no still stretch found in its 60 samples, so it gives no reading: record "
        "the board resting, untouched, for a few seconds in that pose"
    ]


ESP32 = DATA / "real" / "mpu6050_esp32_pose_files"
ESP32_PEER = json.loads((DATA / "real" / "mpu6050_esp32_pose_files_peer.json").read_text())["raw_avg_accel_lsb"]
ESP32_ORDER = ("posX", "negX", "posY", "negY", "posZ", "negZ")


def test_a_maker_s_pose_file_that_holds_another_pose_is_found_and_named(client):
    """The ESP32 board's six files: imu_data_posZ.csv holds the -z pose again (tests/data/real/README.md)."""
    files = [(f"imu_data_{s}.csv", (ESP32 / f"imu_data_{s}.csv").read_bytes()) for s in ESP32_ORDER]
    rec = upload_files(client, files, acc_unit="raw", lsb_per_g="16384")
    assert rec.status_code == 201, rec.text
    rec = rec.json()
    assert rec["sampling_rate_hz"] == pytest.approx(175.7, abs=0.1)  # every fifth sample of ~878 Hz
    assert [(s["source"], s["pose_from_name"], s["up"]) for s in rec["segments"]] == [
        ("imu_data_posX.csv", "+x", "+x"),
        ("imu_data_negX.csv", "-x", "-x"),
        ("imu_data_posY.csv", "+y", "+y"),
        ("imu_data_negY.csv", "-y", "-y"),
        ("imu_data_posZ.csv", "+z", "-z"),
        ("imu_data_negZ.csv", "-z", "-z"),
    ]
    assert file_notes(rec)[-1] == (
        "imu_data_posZ.csv: its name says +z up, but its still readings point -z up: the "
        "data's label is used — check the file's name, or how the board lay"
    )
    # Each still reading beside the maker's printed average of the file, in counts: within 10 (0.6 mg) for the
    # five files that are what was printed; the posZ file is 33 000 counts from its printout on z.
    for seg in rec["segments"]:
        counts = np.asarray(seg["acc_mean"]) * 16384
        gap = np.abs(counts - ESP32_PEER[seg["source"]]).max()
        assert (gap > 33_000) if seg["source"] == "imu_data_posZ.csv" else (gap < 10), (seg["source"], gap)
    hint = (
        "The files' names promise +z up, but no still reading shows it (imu_data_posZ.csv holds -z up): record "
        "that pose again, or check which file holds which pose"
    )
    for method in ("auto", "six_position"):
        r = client.post("/api/v1/calibrations", json={"method": method, "recording_id": rec["id"]})
        assert r.status_code == 422 and r.json()["code"] == "insufficient_data", r.text
        assert r.json()["detail"].endswith(hint)
    six = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]}).json()
    assert six["detail"].startswith(
        "the recording has no still segment with +z up; found +x (segment 0), -x "
        "(segment 1), +y (segment 2), -y (segment 3), -z (segment 4)."
    )


@pytest.mark.parametrize("protocol", ["cube24", "ferraris"])
def test_the_cube_method_refuses_pose_files_naming_what_to_do(client, protocol):
    rec = upload_files(client, six()).json()
    r = client.post("/api/v1/calibrations", json={"method": "cube", "recording_id": rec["id"], "protocol": protocol})
    assert r.status_code == 422 and r.json()["code"] == "calibration_refused"
    assert r.json()["detail"] == (
        "the cube method follows the turns between its positions in one recording; this one is made of 6 files "
        "(one per pose), which hold no turns: calibrate the accelerometer from them with method six_position or "
        "orientations, or record the cube session in one file"
    )
