"""Over HTTP: POST /api/v1/calibrations/import stores a device's own calibration as the device's, which its
history lists and the exports write; a file of no accepted kind is a 422 naming what is accepted."""

from __future__ import annotations

from pathlib import Path

REAL = Path(__file__).resolve().parents[1] / "data" / "real"


def test_an_ardupilot_log_s_parameters_are_stored_as_the_device_s_calibration(client):
    path = REAL / "flight" / "arducopter_3.5_rtl_landing_dataflashlog.bin"
    with path.open("rb") as f:
        r = client.post(
            "/api/v1/calibrations/import",
            files={"file": ("flight.bin", f, "application/octet-stream")},
            data={"device_id": "quad-3", "label": "as flown"},
        )
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["method"] == "imported" and body["ok"] and body["verdict"]["kind"] == "apply"
    assert body["headline"].startswith("imported from ArduPilot (DataFlash log PARM)")
    assert body["read_from"]["firmware_units"] == {"acc": "m/s^2", "gyr": "rad/s", "mag": "mGauss"}
    history = client.get("/api/v1/calibrations", params={"device_id": "quad-3"}).json()["items"]
    assert [item["id"] for item in history] == [body["id"]]
    parm = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "ardupilot"})
    assert parm.status_code == 200, parm.text
    assert "COMPASS_DIA_X 0.946845412" in parm.text and "COMPASS_SCALE 1" in parm.text
    bf = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "betaflight"})
    assert bf.status_code == 200 and "set acc_calibration = " in bf.text and "holds no scale" in bf.text


def test_a_forced_family_and_a_file_of_no_accepted_kind_are_refused_with_their_cause_first(client):
    r = client.post("/api/v1/calibrations/import", files={"file": ("x.param", b"hello\n", "text/plain")})
    assert r.status_code == 422 and r.json()["code"] == "unrecognised_calibration", r.text
    detail = r.json()["detail"]
    assert detail.startswith("the file holds no parameter, set line or JSON: give one of ArduPilot parameter files")
    assert "`firmware`" in detail
    r = client.post(
        "/api/v1/calibrations/import",
        files={"file": ("x.txt", b"INS_ACCOFFS_X 0.1\n", "text/plain")},
        data={"firmware": "px4"},
    )
    assert r.status_code == 422 and "of PX4 with 1 parameter but no calibration of slot 0" in r.json()["detail"]
    r = client.post(
        "/api/v1/calibrations/import", files={"file": ("x.txt", b"x", "text/plain")}, data={"firmware": "dji"}
    )
    assert r.status_code == 422 and r.json()["code"] == "invalid_request"


def test_the_same_import_as_json_and_a_file_beyond_the_firmware_s_ranges_is_stored_not_ok(client):
    import base64

    text = b"INS_ACCOFFS_X,4.2\nINS_ACCOFFS_Y,0.1\nINS_ACCOFFS_Z,-0.2\nINS_ACCSCAL_X,1.01\n"
    r = client.post(
        "/api/v1/calibrations",
        json={"method": "imported", "file_base64": base64.b64encode(text).decode("ascii"), "device_id": "old-fc"},
    )
    assert r.status_code == 201, r.text
    body = r.json()
    assert not body["ok"] and body["verdict"]["kind"] == "failed"
    assert body["reasons"][0].startswith("INS_ACCOFFS_X = 4.2 m/s/s is outside ArduPilot's -3.5…3.5 m/s/s")
    applied = client.post(f"/api/v1/calibrations/{body['id']}/apply", json={"samples": [[4.2, 0.1, 9.8]]})
    assert applied.status_code == 200 and applied.json()["samples"][0][0] == 0.0
    r = client.post("/api/v1/calibrations", json={"method": "imported", "file_base64": "not base64!"})
    assert r.status_code == 422 and r.json()["code"] == "unrecognised_calibration", r.text
    assert r.json()["detail"].startswith("`file_base64` is not base64")


def test_an_empty_file_is_refused_as_such(client):
    r = client.post("/api/v1/calibrations/import", files={"file": ("empty.param", b"", "text/plain")})
    assert r.status_code == 422 and r.json()["code"] == "unrecognised_calibration", r.text
    assert r.json()["detail"].startswith("the file is empty: give one of ArduPilot parameter files")
