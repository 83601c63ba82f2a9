"""The noise of a maker's real still board log, beside the maker's own figure (issue 22, point 5).

An MPU-6050 resting still, logged over a serial port in raw counts at 100 Hz (the first 30 s of the
repository's validation session, tests/data/real/README.md), and the white-noise variance R the
same repository read from the Allan deviation of a 6-hour still recording of the same board.
"""

from __future__ import annotations

import json

import numpy as np

from tests.conftest import DATA

LOG = DATA / "real" / "mpu6050_session2_still_30s.csv"
PEER = json.loads((DATA / "real" / "mpu6050_noise_peer.json").read_text())


def test_noise_density_of_a_still_mpu6050_beside_the_maker_s(client):
    r = client.post(
        "/api/v1/recordings",
        files={"file": (LOG.name, LOG.read_bytes(), "text/csv")},
        data={"columns": "acc_x,acc_y,acc_z", "acc_unit": "raw", "lsb_per_g": "16384", "sampling_rate_hz": "100"},
    )
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["n_samples"] == 3000 and rec["units"] == {"acc": "g"}
    r = client.post("/api/v1/calibrations", json={"method": "noise", "recording_id": rec["id"]})
    assert r.status_code == 201, r.text
    acc = r.json()["model"]["acc"]
    assert acc["noise_density_unit"] == "m/s²/√Hz"
    # The maker's R (6 h of the same board) as a noise density, sqrt(R / fs): 3.30, 3.05, 4.63 mm/s²/√Hz;
    # trical's from these 30 s: 3.26, 2.95, 4.63 — within 4 % on every axis.
    peer = np.sqrt(np.asarray(PEER["R"]) / PEER["sampling_rate_hz"])
    np.testing.assert_allclose(peer, [3.303e-3, 3.046e-3, 4.633e-3], rtol=0, atol=1e-6)
    np.testing.assert_allclose(acc["noise_density"], [3.26e-3, 2.95e-3, 4.63e-3], rtol=0, atol=1e-5)
    assert np.all(np.abs(np.asarray(acc["noise_density"]) / peer - 1) < 0.04)
