"""Methods `nonorthogonal` (Georgieva et al. Approach 1) and `triangular` (Farago et al.) through the API."""

from __future__ import annotations

import numpy as np
import pytest

from tests.conftest import seed_table


def test_dataset1_positions_1_20_through_the_api(client):
    # Georgieva et al. section 2.4, Dataset 1, positions 1–20 (the paper's scales correspond to g = 9.806).
    r = client.post(
        "/api/v1/calibrations",
        json={
            "method": "nonorthogonal",
            "means": seed_table(1)[:20].tolist(),
            "gravity": 9.806,
            "holdout": seed_table(1).tolist(),
        },
    )
    assert r.status_code == 201, r.text
    body = r.json()
    m = body["model"]
    assert m["type"] == "nonorthogonal" and body["ok"]
    np.testing.assert_allclose(m["s"], [0.304496, 0.321482, -1.08995], atol=2e-4)
    np.testing.assert_allclose(np.abs(m["b"]), [1.00457, 1.00147, 0.989292], atol=2e-4)
    np.testing.assert_allclose([m["phi"], m["psi"], m["theta"]], [1.57646, 1.57096, 1.57301], atol=1e-4)
    assert set(body["uncertainty"]) >= {"s", "b", "phi", "psi", "theta"}
    assert body["metrics"]["holdout_count"] == 27


@pytest.mark.parametrize("solver", ["lm", "gradient", "fixed16", "fixed32"])
def test_triangular_solvers_and_c_export(client, solver):
    t2 = seed_table(2)
    r = client.post(
        "/api/v1/calibrations",
        json={"method": "triangular", "solver": solver, "means": t2[:20].tolist(), "gravity": 9.806},
    )
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["model"]["type"] == "triangular" and body["solver"] == solver
    K, o = np.array(body["model"]["K"]), np.array(body["model"]["o"])
    assert np.allclose(np.triu(K, 1), 0)
    applied = client.post(f"/api/v1/calibrations/{body['id']}/apply", json={"samples": t2.tolist()}).json()
    np.testing.assert_allclose(applied["samples"], (t2 + o) @ K.T, atol=1e-12)  # Farago et al. eq. (6)
    doc = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "json"}).json()
    M, off = np.array(doc["correction"]["M"]), np.array(doc["correction"]["o"])
    np.testing.assert_allclose((t2 - off) @ M.T, applied["samples"], atol=1e-9)
    assert client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": "c"}).status_code == 200


def test_means_from_a_recording(client):
    from tests.api.test_recordings import LOG, upload

    rec = upload(client, LOG.read_bytes(), sampling_rate_hz=150).json()
    r = client.post("/api/v1/calibrations", json={"method": "triangular", "recording_id": rec["id"]})
    # Six segments cannot determine nine parameters.
    assert r.status_code == 422 and "9" in r.json()["detail"]


@pytest.mark.parametrize("method", ["nonorthogonal", "triangular"])
def test_bad_input(client, method):
    t1 = seed_table(1)
    few = client.post("/api/v1/calibrations", json={"method": method, "means": t1[:8].tolist()})
    assert few.status_code == 422 and "9" in few.json()["detail"]
    same = client.post("/api/v1/calibrations", json={"method": method, "means": [t1[0].tolist()] * 12})
    assert same.status_code == 422
    nan = client.post(
        "/api/v1/calibrations",
        content=f'{{"method": "{method}", "means": [[NaN, 1, 2]]}}',
        headers={"Content-Type": "application/json"},
    )
    assert nan.status_code == 422 and "finite" in nan.json()["detail"]
    # All positions in one hemisphere (z up or sideways, never down): ok = false with the reason.
    upper = t1[[i for i in range(27) if t1[i, 2] > -1.0]]
    r = client.post("/api/v1/calibrations", json={"method": method, "means": upper.tolist(), "gravity": 9.806})
    assert r.status_code in (201, 422), r.text
    if r.status_code == 201:
        assert not r.json()["ok"] and any("hemisphere" in x for x in r.json()["reasons"])
    else:
        assert "hemisphere" in r.json()["detail"]


@pytest.mark.parametrize("method", ["nonorthogonal", "triangular"])
def test_the_response_advises_the_next_poses_typed(client, method):
    from pydantic import TypeAdapter

    from app.api.schemas.calibrations import CalibrationOut
    from app.api.schemas.still_readings import PoseAdviceOut

    r = client.post(
        "/api/v1/calibrations", json={"method": method, "means": seed_table(1)[:14].tolist(), "gravity": 9.806}
    )
    assert r.status_code == 201, r.text
    body = r.json()
    advice = body["advice"]
    assert len(advice) == 3
    for a in advice:
        PoseAdviceOut.model_validate(a)
        assert np.linalg.norm(a["up"]) == pytest.approx(1.0) and 0 < a["gain"] < 1 and " up (" in a["words"]
    assert [a["gain"] for a in advice] == sorted((a["gain"] for a in advice), reverse=True)
    typed = TypeAdapter(CalibrationOut).validate_python(body)
    assert [a.words for a in typed.advice] == [a["words"] for a in advice]
    assert client.get(f"/api/v1/calibrations/{body['id']}").json()["advice"] == advice
