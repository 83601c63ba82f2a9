"""Real HTTP against `trical serve`, and durability across kill -9."""

from __future__ import annotations

import httpx

from tests.api.test_calibrations import CANONICAL, six_request
from tests.conftest import seed_table
from tests.live_server import LiveServer


def test_acknowledged_calibrations_survive_kill_9(tmp_path):
    env = {"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}"}
    server = LiveServer(env).start()
    try:
        acknowledged = []
        with httpx.Client(base_url=server.url, timeout=10) as http:
            assert http.get("/healthz").json() == {"status": "ok"}
            for i in range(20):
                r = http.post("/api/v1/calibrations", json=six_request(seed_table(1), CANONICAL, device_id=f"d{i % 3}"))
                assert r.status_code == 201
                acknowledged.append(r.json())
        server.kill()  # right after the last 201
        server.start()
        with httpx.Client(base_url=server.url, timeout=10) as http:
            for body in acknowledged:
                assert http.get(f"/api/v1/calibrations/{body['id']}").json() == body
    finally:
        server.stop()


def test_acknowledged_captures_survive_kill_9_and_the_session_resumes(tmp_path):
    """A reload after a crash finds every pose the server acknowledged (issue 6: nothing acknowledged is lost)."""
    import numpy as np

    from tests.api.test_sessions import auth
    from tests.phone_poses import pose_samples

    server = LiveServer({"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}"}).start()
    try:
        rng = np.random.default_rng(9)
        with httpx.Client(base_url=server.url, timeout=10) as http:
            s = http.post("/api/v1/sessions", json={"protocol": "six"}).json()
            for label in ("+z", "-x", "+y"):
                r = http.post(
                    f"/api/v1/sessions/{s['id']}/captures", json=pose_samples(label, rng), headers=auth(s["token"])
                )
                assert r.status_code == 201
            before = r.json()["session"]
        server.kill()  # right after the last 201
        server.start()
        with httpx.Client(base_url=server.url, timeout=10) as http:
            after = http.get(f"/api/v1/sessions/{s['id']}", headers=auth(s["token"])).json()
        assert after == before and after["remaining"] == ["+x", "-y", "-z"]
    finally:
        server.stop()
