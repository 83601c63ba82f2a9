"""A hand-recorded Ferraris session in imucal's CSV layout, through POST /api/v1/calibrations and
``trical calibrate --sections``: matched by orientation and angle, or from imucal's section list."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest

from simulations.cube import simulate_hand_ferraris
from tests.cli_in_process import trical
from tests.conftest import DATA

SECTION_FILE = DATA / "imucal_example_ferraris_session_list.json"
SECTIONS = json.loads(SECTION_FILE.read_text())


def imucal_csv(session) -> bytes:
    """The columns of imucal's example_ferraris_session.csv: n_samples, gyr (deg/s), acc (m/s²)."""
    buf = io.StringIO()
    data = np.hstack([np.arange(len(session.acc))[:, None], session.gyr, session.acc])
    np.savetxt(
        buf,
        data,
        delimiter=",",
        header="n_samples,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z",
        comments="",
        fmt=["%d"] + ["%.12g"] * 6,
    )
    return buf.getvalue().encode()


@pytest.fixture(scope="module")
def csv_bytes():
    return imucal_csv(simulate_hand_ferraris(np.random.default_rng(7)))


def _upload(client, csv_bytes):
    r = client.post(
        "/api/v1/recordings",
        files={"file": ("example_ferraris_session.csv", csv_bytes, "text/csv")},
        data={"sampling_rate_hz": "102.4", "acc_unit": "m/s^2", "gyr_unit": "deg/s"},
    )
    assert r.status_code == 201, r.text
    return r.json()["id"]


def test_ferraris_detected_and_from_sections(client, csv_bytes):
    rec = _upload(client, csv_bytes)
    r = client.post(
        "/api/v1/calibrations", json={"method": "cube", "recording_id": rec, "protocol": "ferraris", "gravity": 9.81}
    )
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["ok"], body["reasons"]
    assert body["metrics"]["n_handling"] == 4 and body["metrics"]["positions_from"] == "detected"
    assert [h["kind"] for h in body["segments"]["handling"]] == ["pause", "move", "move", "pause"]
    assert any(w.startswith("treated as handling") for w in body["warnings"])
    r2 = client.post(
        "/api/v1/calibrations",
        json={"method": "cube", "recording_id": rec, "protocol": "ferraris", "gravity": 9.81, "sections": SECTIONS},
    )
    assert r2.status_code == 201, r2.text
    b2 = r2.json()
    assert b2["ok"] and b2["metrics"]["positions_from"] == "sections"
    assert b2["protocol"]["reading_positions"] == [0, 1, 2, 3, 4, 5]
    assert b2["segments"]["static"][:6] == [
        [SECTIONS[k]["start"], SECTIONS[k]["end"]] for k in ("x_p", "x_a", "y_p", "y_a", "z_p", "z_a")
    ]
    np.testing.assert_allclose(b2["model"]["gyr"]["S"], body["model"]["gyr"]["S"], atol=1e-4)


@pytest.mark.parametrize(
    "sections, status, code, words",
    [
        ({**SECTIONS, "x_q": {"start": 0, "end": 5}}, 422, "invalid_request", "sections.x_q"),
        ({**SECTIONS, "x_rot": {"start": 6770}}, 422, "invalid_request", "sections.x_rot.end"),
        ({k: v for k, v in SECTIONS.items() if k != "z_a"}, 422, "calibration_refused", "sections lacks z_a"),
        (
            {**SECTIONS, "z_rot": {"start": 9205, "end": 99999}},
            422,
            "calibration_refused",
            "sections.z_rot ends at sample 99999, but the recording has 10000 samples",
        ),
    ],
)
def test_bad_sections_are_refused_with_the_key(client, csv_bytes, sections, status, code, words):
    rec = _upload(client, csv_bytes)
    r = client.post(
        "/api/v1/calibrations",
        json={"method": "cube", "recording_id": rec, "protocol": "ferraris", "sections": sections},
    )
    assert r.status_code == status, r.text
    assert r.json()["code"] == code and words in r.json()["detail"]


def test_cli_sections_option(tmp_path, csv_bytes):
    log = tmp_path / "example_ferraris_session.csv"
    log.write_bytes(csv_bytes)
    args = [
        "calibrate",
        str(log),
        "--method",
        "cube",
        "--protocol",
        "ferraris",
        "--sampling-rate-hz",
        "102.4",
        "--unit",
        "m/s^2",
        "--gyr-unit",
        "deg/s",
        "--gravity",
        "9.81",
        "--json",
        "--no-store",
    ]
    out = trical(*args, "--sections", str(SECTION_FILE), tmp_path=tmp_path)
    assert out.returncode == 0, out.stderr
    body = json.loads(out.stdout)
    assert body["metrics"]["positions_from"] == "sections" and body["ok"]
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({**SECTIONS, "y_rot": {"start": 8405, "end": 8081}}))
    out = trical(*args, "--sections", str(bad), tmp_path=tmp_path)
    assert out.returncode == 2 and "sections.y_rot runs from 8405 to 8081" in out.stderr
    bad.write_text("{not json")
    out = trical(*args, "--sections", str(bad), tmp_path=tmp_path)
    assert out.returncode == 2 and "not a readable JSON section list" in out.stderr
