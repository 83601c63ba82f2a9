"""Units that cannot be wrong silently, over real HTTP with real uploads: the data decide the unit and
the answer says what was said and what was used; a chip turns counts into physical units; figures
left in counts are labelled counts, and firmware exports of counts refuse naming the scale to give;
no refusal on any path of the upload and the API names an array shape."""

from __future__ import annotations

import io
import re

import numpy as np
import pytest

from simulations.logs import simulate_static_log
from simulations.magnetometer import EARTH_FIELD_UT, simulate_session

G = 9.80665
SIX = simulate_static_log(np.random.default_rng(22), sampling_rate_hz=100.0, rest_s=(3.0, 4.0), turn_s=(1.0, 1.5))
T = np.arange(len(SIX.samples)) / 100.0
MAG, M_TRUE, B_TRUE = simulate_session(7, n=600)
AK8963_UT_PER_LSB = 0.15  # AK8963 datasheet, 16-bit output


def _csv(header: str, columns: list, fmt: str = "%.6f") -> bytes:
    out = io.StringIO()
    out.write(header + "\n")
    timed = header.startswith("t,")
    for row in np.column_stack(columns):
        out.write(",".join(f"{v:.3f}" if (i == 0 and timed) else (fmt % v) for i, v in enumerate(row)) + "\n")
    return out.getvalue().encode()


def _upload(client, content: bytes, filename: str = "log.csv", **form):
    return client.post(
        "/api/v1/recordings", files={"file": (filename, content, "text/csv")}, data={k: str(v) for k, v in form.items()}
    )


def _calibrate(client, **body):
    return client.post("/api/v1/calibrations", json=body)


def _export(client, cal_id: str, fmt: str):
    return client.get(f"/api/v1/calibrations/{cal_id}/export", params={"format": fmt})


def test_a_g_header_over_m_s2_values_calibrates_as_with_the_right_unit(client):
    # The issue's case: `aX (g)` over values the sketch printed in m/s² answered
    # 422 "means must have shape N×3 ...; got shape (0,)".
    wrong = _upload(client, _csv("t,aX (g),aY (g),aZ (g)", [T, SIX.samples]))
    assert wrong.status_code == 201, wrong.text
    rec = wrong.json()
    assert rec["units"]["acc"] == "m/s^2" and len(rec["segments"]) == 6
    said = rec["warnings"][0]
    assert said.startswith("the header said g for the accelerometer") and said.endswith("calibrated in m/s^2")
    right = _upload(client, _csv("t,aX (g),aY (g),aZ (g)", [T, SIX.samples]), acc_unit="m/s^2").json()
    bodies = []
    for recording in (rec, right):
        r = _calibrate(client, method="six_position", recording_id=recording["id"])
        assert r.status_code == 201, r.text
        bodies.append(r.json())
    assert bodies[0]["ok"] and bodies[0]["unit"] == "m/s^2" and bodies[0]["warnings"][0] == said
    np.testing.assert_allclose(bodies[0]["model"]["X"], bodies[1]["model"]["X"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(bodies[0]["model"]["X"], SIX.X, atol=2e-3)
    np.testing.assert_allclose(bodies[0]["model"]["y"], SIX.y, atol=0.01)


def test_counts_at_4_g_calibrate_in_g_and_say_which_sensitivity(client):
    counts = np.round(SIX.samples / G * 8192)
    rec = _upload(client, _csv("t,ax,ay,az", [T, counts], "%.0f")).json()
    assert rec["units"]["acc"] == "g" and "about 8192 LSB per g" in rec["warnings"][0]
    body = _calibrate(client, method="six_position", recording_id=rec["id"]).json()
    assert body["ok"] and body["unit"] == "g" and body["output_unit"] == "g"
    np.testing.assert_allclose(body["model"]["y"], SIX.y / G, atol=2e-3)
    assert _export(client, body["id"], "ardupilot").status_code == 200


def test_a_magnetometer_in_counts_is_labelled_counts_and_its_firmware_exports_name_the_scale(client):
    counts = np.round(MAG / AK8963_UT_PER_LSB)
    rec = _upload(client, _csv("mag_x,mag_y,mag_z", [counts], "%.0f"), sampling_rate_hz=50).json()
    assert rec["units"] == {"mag": "raw"} and "give chip (e.g. ak8963-16bit" in rec["warnings"][0]
    r = _calibrate(client, method="magnetometer", recording_id=rec["id"])
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["unit"] == "raw" and body["output_unit"] == "raw"
    assert re.search(r"expect \d+\.\d\d counts of the 3\d\d\.\d counts field", body["headline"]), body["headline"]
    assert "µT" not in body["headline"] and body["verdict"]["unit"] == "counts"
    assert "counts" in body["verdict"]["words"] and "µT" not in body["verdict"]["words"]
    header = _export(client, body["id"], "c")
    assert header.status_code == 200 and "/* magnetometer: counts in, counts out */" in header.text
    assert "uT" not in header.text
    for fmt in ("ardupilot", "px4"):
        refused = _export(client, body["id"], fmt)
        assert refused.status_code == 422, refused.text
        assert (
            "upload the log again with chip (the magnetometer's part and range, e.g. ak8963-16bit"
            in refused.json()["detail"]
        )


def test_a_chip_gives_the_magnetometer_in_ut_and_ardupilot_its_true_offsets(client):
    # The issue's case: the ArduPilot file of an AK8963 calibrated in counts had offsets 0.15× off.
    counts = np.round(MAG / AK8963_UT_PER_LSB)
    rec = _upload(client, _csv("mag_x,mag_y,mag_z", [counts], "%.0f"), sampling_rate_hz=50, chip="ak8963-16bit").json()
    assert rec["units"] == {"mag": "uT"} and rec["warnings"] == [] and rec["read_with"]["chip"] == "ak8963-16bit"
    body = _calibrate(client, method="magnetometer", recording_id=rec["id"], field_ut=EARTH_FIELD_UT).json()
    assert body["ok"] and body["unit"] == "uT" and body["output_unit"] == "uT", body["reasons"]
    np.testing.assert_allclose(body["model"]["b"], B_TRUE, atol=0.1)
    text = _export(client, body["id"], "ardupilot").text
    offsets = np.array([float(re.search(rf"^COMPASS_OFS_{a} (\S+)$", text, re.M).group(1)) for a in "XYZ"])
    np.testing.assert_allclose(offsets, -10.0 * B_TRUE, atol=1.0)  # mGauss, within 0.1 µT of the truth


def _moving_log() -> bytes:
    rng = np.random.default_rng(4)
    d = rng.normal(size=(3000, 3))
    acc = G * d / np.linalg.norm(d, axis=1, keepdims=True)
    return _csv("t,ax,ay,az", [np.arange(3000) / 100.0, acc])


def _npy(shape) -> bytes:
    buf = io.BytesIO()
    np.save(buf, np.zeros(shape))
    return buf.getvalue()


SIX_CSV = _csv("t,ax,ay,az", [T, SIX.samples])
UPLOADS = {
    "empty": (b"", {}),
    "binary": (b"\x00\x01\x02" * 10, {}),
    "header only": (b"t,ax,ay,az\n", {}),
    "text in a column": (b"t,ax,ay,az\n0,1,2,3\n0.01,1,x,3\n", {}),
    "unrecognised header": (b"a,b,c,d\n1,2,3,4\n", {}),
    "five columns, no header": (b"1,2,3,4,5\n1,2,3,4,5\n", {}),
    "unknown column names": (SIX_CSV, {"columns": "t,foo,bar,baz"}),
    "unknown chip": (SIX_CSV, {"chip": "mpu9999"}),
    "two chips for one sensor": (SIX_CSV, {"chip": "ak8963-16bit,qmc5883l-2g"}),
    "chip and unit": (SIX_CSV, {"chip": "mpu6050-2g", "acc_unit": "g"}),
    "lsb_per_g over m/s^2": (SIX_CSV, {"lsb_per_g": 16384}),
    "a wrong lsb_per_g": (_csv("t,ax,ay,az", [T, np.round(SIX.samples / G * 8192)], "%.0f"), {"lsb_per_g": 16384}),
    "a magnitude no unit explains": (_csv("t,ax (g),ay (g),az (g)", [T, SIX.samples * 0.3]), {}),
    "linear acceleration": (_csv("t,ax,ay,az", [T, SIX.samples * 0.01]), {}),
    "an npy of one row": (_npy((5,)), {"sampling_rate_hz": 100, "filename": "x.npy"}),
    "an npy of five columns": (_npy((10, 5)), {"sampling_rate_hz": 100, "filename": "x.npy"}),
    "a chip for an npy": (_npy((10, 3)), {"sampling_rate_hz": 100, "filename": "x.npy", "chip": "mpu6050-2g"}),
}
SHAPE = re.compile(r"shape|\(\d+,\s*\d*\)|\bN×\d|\d+×\d+", re.IGNORECASE)


@pytest.mark.parametrize("case", UPLOADS, ids=list(UPLOADS))
def test_no_refused_upload_names_an_array_shape(client, case):
    content, form = UPLOADS[case]
    form = dict(form)
    r = _upload(client, content, form.pop("filename", "log.csv"), **form)
    assert 400 <= r.status_code < 500, r.text
    detail = r.json()["detail"]
    assert not SHAPE.search(detail), detail


def _counts_cal(client) -> str:
    rec = _upload(client, _csv("t,ax,ay,az", [T, np.round(SIX.samples / G * 8192)], "%.0f"), acc_unit="raw").json()
    return _calibrate(client, method="six_position", recording_id=rec["id"]).json()["id"]


def _mag_counts_cal(client) -> str:
    rec = _upload(client, _csv("mag_x,mag_y,mag_z", [np.round(MAG / 0.15)], "%.0f"), sampling_rate_hz=50).json()
    return _calibrate(client, method="magnetometer", recording_id=rec["id"]).json()["id"]


def _rec(client, content: bytes, **form) -> str:
    r = _upload(client, content, **form)
    assert r.status_code == 201, r.text
    return r.json()["id"]


REQUESTS = {
    "six_position on a moving recording": lambda c: _calibrate(
        c, method="six_position", recording_id=_rec(c, _moving_log())
    ),
    "triangular on a moving recording": lambda c: _calibrate(
        c, method="triangular", recording_id=_rec(c, _moving_log())
    ),
    "auto on a moving recording": lambda c: _calibrate(c, method="auto", recording_id=_rec(c, _moving_log())),
    "orientations on a moving recording": lambda c: _calibrate(
        c, method="orientations", recording_id=_rec(c, _moving_log())
    ),
    "nonorthogonal on six poses": lambda c: _calibrate(c, method="nonorthogonal", recording_id=_rec(c, SIX_CSV)),
    "a segment that does not exist": lambda c: _calibrate(
        c, method="orientations", segments=[0, 1, 2, 3, 4, 99], recording_id=_rec(c, SIX_CSV)
    ),
    "magnetometer on an accelerometer log": lambda c: _calibrate(
        c, method="magnetometer", recording_id=_rec(c, SIX_CSV)
    ),
    "six_position on a magnetometer log": lambda c: _calibrate(
        c, method="six_position", recording_id=_rec(c, _csv("mag_x,mag_y,mag_z", [MAG]), sampling_rate_hz=50)
    ),
    "inline means of two numbers": lambda c: _calibrate(c, method="triangular", means=[[1.0, 2.0]] * 12),
    "inline readings of four numbers": lambda c: _calibrate(
        c, method="six_position", readings=[{"mean": [0, 0, 9.8, 1], "up": "+z"}] * 6
    ),
    "inline magnetometer of two numbers": lambda c: _calibrate(c, method="magnetometer", mag=[[1.0, 2.0]] * 50),
    "ardupilot of an accelerometer in counts": lambda c: _export(c, _counts_cal(c), "ardupilot"),
    "px4 of an accelerometer in counts": lambda c: _export(c, _counts_cal(c), "px4"),
    "ardupilot of a magnetometer in counts": lambda c: _export(c, _mag_counts_cal(c), "ardupilot"),
}


@pytest.mark.parametrize("case", REQUESTS, ids=list(REQUESTS))
def test_no_refused_request_names_an_array_shape(client, case):
    r = REQUESTS[case](client)
    assert 400 <= r.status_code < 500, r.text
    detail = r.json()["detail"]
    assert not SHAPE.search(detail), detail


def test_inline_readings_in_g_without_their_unit_calibrate_in_g_and_say_so(client):
    # The API alike: six averaged readings typed in g, the request's unit left at its default m/s².
    means = [np.mean(SIX.samples[a:b], axis=0) / G for a, b, _ in SIX.segments]
    ups = [up for _, _, up in SIX.segments]
    readings = [{"mean": m.tolist(), "up": up} for m, up in zip(means, ups)]
    r = _calibrate(client, method="six_position", readings=readings)
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["ok"] and body["unit"] == "g" and body["gravity"] == 1.0
    assert any(
        w.startswith("the request gave no unit, so m/s^2, but its readings' median norm is 0.9")
        and w.endswith("about 1 g in g: calibrated in g")
        for w in body["warnings"]
    )
    np.testing.assert_allclose(body["model"]["X"], SIX.X, atol=2e-3)
    said = _calibrate(client, method="six_position", readings=readings, unit="m/s^2").json()
    assert any(w.startswith("the request's unit said m/s^2, but") for w in said["warnings"])
