"""Serial board logs end to end over HTTP: host-stamped bursts, gaps, several rests, no time column."""

from __future__ import annotations

import io

import numpy as np
import pytest

from simulations.noise import simulate_still
from simulations.serial import host_arrival_times

FS = 100.0
N_DEG = 0.01  # the gyroscope's noise density, deg/s/√Hz
N_RAD = np.deg2rad(N_DEG)


def _csv(header: str, *columns, fmt="%.7g") -> bytes:
    buf = io.StringIO()
    np.savetxt(buf, np.column_stack(columns), delimiter=",", comments="", header=header, fmt=fmt)
    return buf.getvalue().encode()


def _still_gyr(seed: int, n: int) -> np.ndarray:
    """A still gyroscope in deg/s: white noise N_DEG, a bias, no slower terms."""
    return simulate_still(
        np.random.default_rng(seed), n_samples=n, sampling_rate_hz=FS, N=N_DEG, B=0.0, K=0.0, bias=[0.3, -0.2, 0.1]
    )


def _upload(client, content: bytes, **form) -> dict:
    r = client.post(
        "/api/v1/recordings",
        files={"file": ("board.csv", content, "text/csv")},
        data={k: str(v) for k, v in form.items()},
    )
    assert r.status_code == 201, r.text
    return r.json()


def _noise(client, recording_id: str) -> dict:
    r = client.post("/api/v1/calibrations", json={"method": "noise", "recording_id": recording_id})
    assert r.status_code == 201, r.text
    return r.json()


def test_a_still_gyroscope_with_bursty_host_stamps_gives_its_noise_density(client):
    # The log: t (host ms), gyr_x, gyr_y, gyr_z in deg/s, a 100 Hz sensor whose lines arrive in bursts.
    n = 30_000
    t_ms = host_arrival_times(np.random.default_rng(11), n_samples=n, sampling_rate_hz=FS) * 1e3 + 52_113.0
    rec = _upload(client, _csv("t,gyr_x,gyr_y,gyr_z", np.round(t_ms, 3), _still_gyr(12, n)), gyr_unit="deg/s")
    assert rec["channels"] == ["gyr"] and rec["overview"]["sensor"] == "gyr" and rec["segments"] == []
    assert rec["sampling_rate_hz"] == pytest.approx(FS, rel=3e-3)
    assert rec["timing"]["source"] == "time column" and rec["timing"]["jitter"] > 1 and rec["timing"]["gaps"] == []
    body = _noise(client, rec["id"])
    assert body["ok"], body["reasons"]
    assert body["sampling_rate_hz"] == rec["sampling_rate_hz"]
    np.testing.assert_allclose(body["model"]["gyr"]["noise_density"], N_RAD, rtol=0.05)
    assert any("irregular" in w and "% of the interval" in w for w in body["warnings"])
    # The rate given overrides the time column's.
    rec = _upload(
        client,
        _csv("t,gyr_x,gyr_y,gyr_z", np.round(t_ms, 3), _still_gyr(12, n)),
        gyr_unit="deg/s",
        sampling_rate_hz=100,
    )
    assert rec["sampling_rate_hz"] == 100 and rec["timing"]["source"] == "sampling_rate_hz"
    np.testing.assert_allclose(_noise(client, rec["id"])["model"]["gyr"]["noise_density"], N_RAD, rtol=0.05)


def test_gaps_in_the_still_part_are_left_out_or_name_the_timing(client):
    """A serial log losing 7 s in two gaps: the longest stretch without one (116 s) is characterised, the gaps
    named; losing 1 s every 4 s, no stretch lasts the noise's 5 s, and the timing is the reason, with a serial
    port's remedy."""
    n = 30_000
    lost = [(9_000, 9_400), (21_000, 21_300)]  # 7 s of 300 s lost
    t = host_arrival_times(np.random.default_rng(13), n_samples=n, sampling_rate_hz=FS, lost=lost)
    keep = np.ones(n, dtype=bool)
    for a, b in lost:
        keep[a:b] = False
    rec = _upload(client, _csv("time_ms,gyr_x,gyr_y,gyr_z", t * 1e3, _still_gyr(14, n)[keep]), gyr_unit="deg/s")
    assert [g["index"] for g in rec["timing"]["gaps"]] == [9_000, 20_600]
    assert rec["timing"]["missing_s"] == pytest.approx(7.0, abs=0.15)
    body = _noise(client, rec["id"])
    assert body["ok"], body["reasons"]
    assert body["still"]["start"] == 9_000 and body["still"]["end"] == 20_600
    assert any(
        "the longest stretch without one, 90.0–206.0 s (116.0 s), was characterised" in w for w in body["warnings"]
    )
    lost = [(k, k + 100) for k in range(300, n - 100, 400)]  # 1 s lost every 4 s
    t = host_arrival_times(np.random.default_rng(13), n_samples=n, sampling_rate_hz=FS, lost=lost)
    keep = np.ones(n, dtype=bool)
    for a, b in lost:
        keep[a:b] = False
    rec = _upload(client, _csv("time_ms,gyr_x,gyr_y,gyr_z", t * 1e3, _still_gyr(14, n)[keep]), gyr_unit="deg/s")
    body = _noise(client, rec["id"])
    assert not body["ok"]
    (reason,) = [r for r in body["reasons"] if r.startswith("the timing:")]
    assert "no stretch without a gap lasts 5 s" in reason and "evenly spaced" in reason
    assert "a faster serial baud rate" in reason


def _six_poses(seed: int, *, time: bool) -> bytes:
    """Six rests of about 30 s in the six orientations, joined by 3 s turns at a steady rate."""
    acc, gyr = _six_poses_arrays(seed)
    if time:
        return _csv("time_s,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z", np.arange(len(acc)) / FS, acc, gyr)
    return _csv("acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z", acc, gyr)


def _six_poses_arrays(seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    ups = np.array([(0, 0, 1), (1, 0, 0), (0, 0, -1), (-1, 0, 0), (0, 1, 0), (0, -1, 0)], dtype=float)
    acc, gyr = [], []
    for k, (up, rest_s) in enumerate(zip(ups, (30, 28, 33, 26, 29, 27))):
        if k:
            s = np.linspace(0.0, 1.0, int(3 * FS))[:, None]
            turn = (1 - s) * ups[k - 1] + s * up
            acc.append(9.81 * turn / np.linalg.norm(turn, axis=1, keepdims=True) + rng.normal(0, 0.02, (len(s), 3)))
            gyr.append(np.array([30.0, 0.0, 0.0]) + rng.normal(0, 0.1, (len(s), 3)))
        m = int(rest_s * FS)
        acc.append(9.81 * up + simulate_still(rng, n_samples=m, sampling_rate_hz=FS, N=2e-3, B=0, K=0))
        gyr.append(simulate_still(rng, n_samples=m, sampling_rate_hz=FS, N=N_DEG, B=0, K=0, bias=[0.3, -0.2, 0.1]))
    return np.vstack(acc), np.vstack(gyr)


def test_no_still_segment_spans_a_gap(client):
    acc, gyr = _six_poses_arrays(18)
    t = np.arange(len(acc)) / FS
    keep = np.ones(len(acc), dtype=bool)
    keep[1_500:1_700] = False  # 2 s lost in the middle of the first rest (0–30 s)
    rec = _upload(client, _csv("time_s,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z", t[keep], acc[keep], gyr[keep]))
    [gap] = rec["timing"]["gaps"]
    assert gap["index"] == 1_500 and gap["missing_s"] == pytest.approx(2.0)
    assert any("1 gap in the time column" in n for n in rec["notes"])
    assert not any(s["start"] < gap["index"] < s["end"] for s in rec["segments"])
    first = [s for s in rec["segments"] if s["up"] == "+z"]
    assert len(first) == 2 and first[0]["end"] <= gap["index"] <= first[1]["start"]
    r = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]})
    assert r.status_code == 201 and r.json()["ok"], r.text


@pytest.mark.parametrize("columns", [None, "t,-,-,-,gyr_x,gyr_y,gyr_z"])
def test_noise_of_six_poses_uses_the_longest_rest_and_is_not_ok(client, columns):
    # With the accelerometer, and of the gyroscope alone (whose spread stays small while it turns
    # at a steady rate): never a term fitted across the pose changes.
    rec = _upload(client, _six_poses(15, time=True), gyr_unit="deg/s", **({"columns": columns} if columns else {}))
    body = _noise(client, rec["id"])
    assert not body["ok"]
    assert any("holds 6 rests separated by moves" in r and "only the longest" in r for r in body["reasons"])
    assert 31 <= body["duration_s"] <= 33.5  # the 33 s rest, its edges trimmed to the half second
    for k in ("random_walk", "bias_instability"):  # no pose change seen as a slow term
        assert all(v is None or v < 1e-3 for v in body["model"]["gyr"][k])
    np.testing.assert_allclose(body["model"]["gyr"]["noise_density"], N_RAD, rtol=0.15)


def test_poses_without_a_time_column_need_no_rate_and_the_noise_asks_for_one(client):
    rec = _upload(client, _six_poses(16, time=False))
    assert rec["sampling_rate_hz"] is None and rec["duration_s"] is None and rec["timing"]["source"] == "none"
    assert rec["overview"]["t_s"] is None and rec["overview"]["start"][0] == 0
    assert sorted(s["up"] for s in rec["segments"]) == sorted(["+x", "-x", "+y", "-y", "+z", "-z"])
    r = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]})
    assert r.status_code == 201 and r.json()["ok"], r.text
    r = client.post("/api/v1/calibrations", json={"method": "noise", "recording_id": rec["id"]})
    assert r.status_code == 422 and "needs the sensor's sampling rate" in r.json()["detail"]
    assert "sampling_rate_hz" in r.json()["detail"]
    r = client.post("/api/v1/calibrations", json={"method": "cube", "recording_id": rec["id"]})
    assert r.status_code == 422 and "sampling rate" in r.json()["detail"]


def test_a_magnetometer_turn_without_a_time_column_calibrates_the_compass(client):
    rng = np.random.default_rng(17)
    d = rng.normal(size=(3_000, 3))
    mag = 48.0 * d / np.linalg.norm(d, axis=1, keepdims=True) + [12.0, -7.0, 30.0] + rng.normal(0, 0.3, (3_000, 3))
    rec = _upload(client, _csv("mag_x,mag_y,mag_z", mag))
    assert rec["channels"] == ["mag"] and rec["sampling_rate_hz"] is None
    r = client.post("/api/v1/calibrations", json={"method": "auto", "recording_id": rec["id"]})
    assert r.status_code == 201, r.text
    assert r.json()["method"] == "magnetometer" and r.json()["ok"]
