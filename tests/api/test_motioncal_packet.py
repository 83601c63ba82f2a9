"""MotionCal's 68-byte calibration packet (app/io/exports/motioncal_packet.py, ``format=motioncal``), checked by a
receiver written independently in C (tests/io/c/motioncal_receiver.c, compiled by gcc here): it checks
the signature and the CRC, recovers every value to float32 precision, and refuses a corrupted byte."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from app.io.exports.motioncal_packet import MotionCalCalibration, PacketError, crc16, decode, encode, from_calibration
from simulations.magnetometer import simulate_session
from tests.processes import ProcessFailed, run_ok

RECEIVER = Path(__file__).parents[1] / "io" / "c" / "motioncal_receiver.c"
CANONICAL = ["-x", "+x", "-y", "+y", "-z", "+z"]
G0 = 9.80665


@pytest.fixture(scope="module")
def receiver(tmp_path_factory):
    cc = shutil.which("gcc")
    assert cc, "gcc is needed to build the packet's C receiver"
    exe = tmp_path_factory.mktemp("receiver") / "motioncal_receiver"
    run_ok([cc, "-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-o", str(exe), str(RECEIVER)], timeout_s=60)
    return exe


def receive(exe, packet: bytes) -> np.ndarray:
    out = run_ok([str(exe)], timeout_s=10, input=packet.decode("latin-1"), encoding="latin-1")
    return np.array([float(v) for v in out.stdout.split()], dtype=np.float64)


def test_crc_is_crc16_modbus():
    assert (
        crc16(b"123456789") == 0x4B37
    )  # the catalogued check value of CRC-16/MODBUS (poly 0xA001 reflected, init 0xFFFF)


def test_the_c_receiver_recovers_every_value_and_refuses_a_corrupted_byte(receiver):
    rng = np.random.default_rng(23)
    A = rng.normal(size=(3, 3))
    cal = MotionCalCalibration(
        rng.normal(0, 0.3, 3),
        rng.normal(0, 0.02, 3),
        rng.normal(0, 40, 3),
        float(rng.uniform(25, 65)),
        np.eye(3) + 0.05 * (A + A.T),
    )
    packet = encode(cal)
    assert len(packet) == 68 and packet[:2] == bytes((117, 84))
    got = receive(receiver, packet)
    want = np.array(cal.floats(), dtype=np.float32)
    np.testing.assert_array_equal(got.astype(np.float32), want)  # float32 to the last bit (9 digits round-trip)
    np.testing.assert_allclose(got, cal.floats(), rtol=6e-8, atol=1e-30)
    back = decode(packet)
    np.testing.assert_array_equal(back.mag_softiron, back.mag_softiron.T)
    np.testing.assert_allclose(back.mag_softiron, cal.mag_softiron, rtol=6e-8)
    for position in (0, 1, 2, 37, 65, 66, 67):
        bad = bytearray(packet)
        bad[position] ^= 0x10
        with pytest.raises(ProcessFailed, match="refused"):
            receive(receiver, bytes(bad))
        with pytest.raises(PacketError):
            decode(bytes(bad))
    with pytest.raises(ProcessFailed, match="refused: 67 bytes"):
        receive(receiver, packet[:-1])


def test_compass_calibration_exported_and_received(client, receiver):
    m, _M, _b = simulate_session(21, n=300, hard_iron_ut=80.0)
    r = client.post("/api/v1/calibrations", json={"method": "magnetometer", "mag": m.tolist(), "field_ut": 48.0})
    assert r.status_code == 201, r.text
    cal = r.json()
    e = client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": "motioncal"})
    assert e.status_code == 200 and e.headers["content-type"] == "application/octet-stream"
    assert len(e.content) == 68
    got = receive(receiver, e.content)
    Mf = np.array(cal["model"]["M"])
    assert np.all(got[:6] == 0.0)
    np.testing.assert_allclose(got[6:9], cal["model"]["b"], rtol=1e-7, atol=1e-5)
    assert got[9] == pytest.approx(48.0, rel=1e-7)
    np.testing.assert_allclose(
        got[10:], [Mf[0, 0], Mf[1, 1], Mf[2, 2], Mf[0, 1], Mf[0, 2], Mf[1, 2]], rtol=1e-6, atol=1e-7
    )
    # the receiver's correction h = M (m − b) in float32 gives trical's calibrated field
    h = client.post(f"/api/v1/calibrations/{cal['id']}/apply", json={"samples": m[:50].tolist(), "sensor": "mag"})
    assert h.status_code == 200, h.text
    back = decode(e.content)
    board = (m[:50] - back.mag_hardiron) @ back.mag_softiron.T
    np.testing.assert_allclose(board, h.json()["samples"], atol=1e-4)


def test_accelerometer_offsets_only_and_what_is_not_carried(client, receiver, table1):
    req = {
        "method": "six_position",
        "unit": "m/s^2",
        "readings": [{"up": lab, "mean": row.tolist()} for lab, row in zip(CANONICAL, table1[:6])],
    }
    r = client.post("/api/v1/calibrations", json=req)
    assert r.status_code == 201, r.text
    body = r.json()
    e = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "motioncal"})
    assert e.status_code == 200, e.text
    got = receive(receiver, e.content)
    np.testing.assert_allclose(got[0:3], body["model"]["y"], rtol=1e-6, atol=1e-6)
    assert np.all(got[3:9] == 0.0) and got[9] == 50.0
    np.testing.assert_array_equal(got[10:], [1, 1, 1, 0, 0, 0])
    notes = from_calibration(body).notes
    assert any("scales and cross terms" in n and "C header" in n for n in notes)


def test_counts_are_refused(client, table1):
    req = {
        "method": "six_position",
        "unit": "raw",
        "readings": [{"up": lab, "mean": (row / G0 * 16384).tolist()} for lab, row in zip(CANONICAL, table1[:6])],
    }
    r = client.post("/api/v1/calibrations", json=req)
    assert r.status_code == 201, r.text
    e = client.get(f"/api/v1/calibrations/{r.json()['id']}/export", params={"format": "motioncal"})
    assert e.status_code == 422
    assert "accelerometer of this calibration is in counts" in e.text and "C header" in e.text


def test_cli_export_writes_the_bytes_and_says_what_they_do_not_carry(tmp_path, receiver):
    from tests.cli_in_process import trical
    from tests.conftest import DATA

    out = trical(
        "calibrate",
        str(DATA / "six_orientations_150hz.csv"),
        "--method",
        "six_position",
        "--sampling-rate-hz",
        "150",
        "--json",
        tmp_path=tmp_path,
    )
    assert out.returncode == 0, out.stderr
    body = json.loads(out.stdout)
    packet_file = tmp_path / "board.motioncal"
    export = trical("export", body["id"], "--format", "motioncal", "-o", str(packet_file), tmp_path=tmp_path)
    assert export.returncode == 0, export.stderr
    assert "note: accelerometer: only the offsets are carried; its scales and cross terms" in export.stderr
    assert "C header" in export.stderr
    got = receive(receiver, packet_file.read_bytes())
    np.testing.assert_allclose(got[:3], body["model"]["y"], rtol=1e-6, atol=1e-6)


def test_trical_capture_s_packet_keeps_the_device_s_stored_compass(client, receiver, table1, tmp_path):
    """`trical capture --send` with --device-id, as the page's Send to the board: an accelerometer calibration's
    packet carries the device's latest ok compass calibration from the store (its hard iron, field and soft iron,
    the receiver's values), and nothing of a noise characterisation or of another device; --without-compass
    leaves it out."""
    from app.cli.capture import _latest_compass
    from app.config import Settings
    from app.io.exports.motioncal_packet import packet_of
    from app.store import open_store

    m, _M, _b = simulate_session(22, n=300, hard_iron_ut=60.0)
    readings = [{"up": lab, "mean": row.tolist()} for lab, row in zip(CANONICAL, table1[:6])]
    acc = client.post("/api/v1/calibrations", json={"method": "six_position", "unit": "m/s^2", "readings": readings})
    compass = client.post(
        "/api/v1/calibrations",
        json={"method": "magnetometer", "mag": m.tolist(), "field_ut": 48.0, "device_id": "imu-7"},
    )
    assert acc.status_code == compass.status_code == 201 and compass.json()["ok"], compass.text
    db = tmp_path / "trical.db"
    store = open_store(f"sqlite:///{db}", tmp_path / "recordings")
    stored = store.add_calibration(compass.json(), owner=None)
    store.add_calibration({**compass.json(), "device_id": "imu-8"}, owner=None)  # another device's
    settings = lambda: Settings(database_url=f"sqlite:///{db}", data_dir=tmp_path / "recordings")  # noqa: E731
    body = {**acc.json(), "device_id": "imu-7"}
    found = _latest_compass(body, "imu-7", settings)
    assert found is not None and found["id"] == stored["id"]
    assert _latest_compass(body, None, settings) is None and _latest_compass(body, "imu-9", settings) is None
    packet, notes = packet_of(body, found)
    got = receive(receiver, packet)
    np.testing.assert_allclose(got[0:3], acc.json()["model"]["y"], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(got[6:9], compass.json()["model"]["b"], rtol=1e-7, atol=1e-5)
    assert got[9] == pytest.approx(48.0, rel=1e-7)
    assert any(n == f"magnetometer: from the compass calibration {stored['id']}, carried whole" for n in notes)
    alone = receive(receiver, packet_of(body)[0])
    assert np.all(alone[6:9] == 0.0) and alone[9] == 50.0
