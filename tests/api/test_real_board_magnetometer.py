"""The compass on a maker's real board log, beside the maker's own fit (issue 22, point 5).

A QMC5883L on an Arduino UNO turned by hand, logged over a serial port in raw counts at 50 Hz
(tests/data/real/magnetometer/README.md: every tenth row, 5 Hz), and the fit its authors made of it
with their implementation of Dorveaux et al.'s iterative calibration (IEEE CDC 2009),
h = A m + B with |h| = 1, on the samples after the first 60 s (the board at rest).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from tests.conftest import DATA

REAL = DATA / "real" / "magnetometer"
LOG = REAL / "tomisuarez2_qmc5883l_turn_every10.csv"
PEER = json.loads((REAL / "tomisuarez2_qmc5883l_peer.json").read_text())
REST_ROWS = int(PEER["skipped_s"] * 5)  # the first 60 s at 5 Hz: the board at rest


def _counts() -> np.ndarray:
    return np.loadtxt(LOG, delimiter=",", skiprows=4)  # three comment lines and the header


def test_the_compass_on_a_qmc5883l_hand_turn_beside_the_maker_s_fit(client):
    r = client.post(
        "/api/v1/recordings",
        files={"file": (LOG.name, LOG.read_bytes(), "text/csv")},
        data={"columns": "mag_x,mag_y,mag_z", "mag_unit": "raw", "sampling_rate_hz": "5"},
    )
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["channels"] == ["mag"] and rec["n_samples"] == 2275 and rec["units"] == {"mag": "raw"}
    r = client.post("/api/v1/calibrations", json={"method": "magnetometer", "recording_id": rec["id"]})
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["ok"] and body["verdict"]["apply"] and body["metrics"]["coverage"] == 1.0
    m = _counts()
    turn = m[REST_ROWS:]
    A, B = np.asarray(PEER["A"]), np.asarray(PEER["B"])
    # The hard iron: trical's offset is within 2 counts of the maker's (-A⁻¹B) on each axis, of a field of
    # ~1070 counts.
    np.testing.assert_allclose(body["model"]["b"], -np.linalg.solve(A, B), rtol=0, atol=2.0)
    np.testing.assert_allclose(body["model"]["b"], [6194.89, 251.84, 3475.68], rtol=0, atol=0.01)
    # The field strength after calibration, relative RMS over the turn: the maker's 2.900 %, trical's 2.898 %
    # (raw: 18.9 % about the same centre): the same, at the sensor's own noise (trical's noise figure: 2.8 %).
    F = body["metrics"]["field_ut"]
    ours = np.linalg.norm((turn - body["model"]["b"]) @ np.asarray(body["model"]["M"]).T, axis=1) / F
    peer = np.linalg.norm(turn @ A.T + B, axis=1)
    raw = np.linalg.norm(turn - body["model"]["b"], axis=1)

    def rms(x):
        return float(np.sqrt(np.mean((x - 1.0) ** 2)))

    assert rms(peer) == pytest.approx(0.02900, abs=5e-5)
    assert rms(ours) == pytest.approx(0.02898, abs=5e-5)
    assert rms(raw / raw.mean()) == pytest.approx(0.189, abs=1e-3)
    # On directions left out of the fit (20 faces in turn), trical expects 2.8 % of the field.
    assert body["metrics"]["cv_error_ut"] / F == pytest.approx(0.0283, abs=5e-4)
    assert body["metrics"]["noise_ut"] / F == pytest.approx(0.0279, abs=5e-4)
