"""A real ArduPilot Copter 3.3 log (tests/data/real/flight/log171.bin: TimeMS, Temp, IMU2/IMU3 and MAG2/MAG3 as
their own messages) uploaded over HTTP: it was refused as damaged (issue 32); it is read with every instance."""

from __future__ import annotations

from pathlib import Path

LOG171 = Path(__file__).resolve().parents[1] / "data" / "real" / "flight" / "log171.bin"


def test_copter_3_3_log_uploads_with_its_instances_listed(client):
    r = client.post(
        "/api/v1/recordings",
        files={"file": (LOG171.name, LOG171.read_bytes())},
        data={"instance": "1", "mag_instance": "1"},
    )
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["format"] == "dataflash"
    assert rec["flight"]["imu"]["instance"] == 1 and rec["flight"]["mag"]["instance"] == 1
    listed = {(i["sensor"], i["instance"]): i for i in rec["flight"]["instances"]}
    assert set(listed) == {(s, k) for s in ("acc", "gyr", "mag") for k in range(3)}
    assert listed[("acc", 1)]["n_samples"] == 11916 and listed[("mag", 1)]["n_samples"] == 2384
    assert listed[("mag", 1)]["device_id"] == 131874  # COMPASS_DEV_ID2: the internal compass, SPI
    assert 27.0 < listed[("acc", 1)]["temperature_min_c"] < listed[("acc", 1)]["temperature_max_c"] < 33.0
