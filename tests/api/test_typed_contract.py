"""The typed contract: every method's response is described field by field in /openapi.json, and
every error carries a stable `code` beside its `detail`."""

from __future__ import annotations

import io

import numpy as np
import pytest
from pydantic import BaseModel, TypeAdapter

from app.api.schemas.calibrations import RESPONSE_MODELS, CalibrationOut
from simulations.autocal import simulate_recording
from simulations.cube import FIELD_UT, simulate_session
from simulations.magnetometer import simulate_session as simulate_turn_session
from tests.conftest import seed_table

G = 9.81
SIX = [
    ([G + 0.1, 0.05, -0.02], "+x"),
    ([-G + 0.12, 0.03, 0.01], "-x"),
    ([0.02, G - 0.05, 0.1], "+y"),
    ([0.01, -G - 0.02, 0.08], "-y"),
    ([0.05, 0.02, G + 0.2], "+z"),
    ([0.04, 0.01, -G + 0.15], "-z"),
]


def undescribed(value, path: str = "") -> list[str]:
    """Fields of a validated response that its model does not describe (extra="allow" keeps them)."""
    out: list[str] = []
    if isinstance(value, BaseModel):
        out += [f"{path}.{k}" for k in (value.__pydantic_extra__ or {})]
        for name in type(value).model_fields:
            out += undescribed(getattr(value, name), f"{path}.{name}")
    elif isinstance(value, list):
        for i, v in enumerate(value):
            out += undescribed(v, f"{path}[{i}]")
    elif isinstance(value, dict):
        for k, v in value.items():
            out += undescribed(v, f"{path}.{k}")
    return out


def _upload(client, name: str, content: bytes, **data):
    r = client.post(
        "/api/v1/recordings",
        files={"file": (name, content, "application/octet-stream")},
        data={k: str(v) for k, v in data.items()},
    )
    assert r.status_code == 201, r.text
    return r.json()["id"]


@pytest.fixture(scope="module")
def cube_csv() -> bytes:
    s = simulate_session(np.random.default_rng(21), sampling_rate_hz=100.0)
    buf = io.StringIO()
    np.savetxt(
        buf,
        np.hstack([s.acc, s.gyr, s.mag]),
        delimiter=",",
        comments="",
        fmt="%.9g",
        header="acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z,mag_x,mag_y,mag_z",
    )
    return buf.getvalue().encode()


def _requests(client, cube_csv):
    t1, t2 = seed_table(1), seed_table(2)
    yield {"method": "six_position", "readings": [{"mean": m, "up": u} for m, u in SIX], "gravity": G}
    yield {
        "method": "orientations",
        "readings": [{"mean": m, "up": u} for m, u in SIX] * 2,
        "gravity": G,
        "holdout": t1.tolist(),
    }
    yield {"method": "auto", "means": [m for m, _ in SIX], "gravity": G}  # → six_position, with its choice
    yield {"method": "auto", "means": t2[:20].tolist(), "gravity": 9.806}  # free poses → triangular
    yield {"method": "nonorthogonal", "means": t1[:20].tolist(), "gravity": 9.806, "holdout": t1.tolist()}
    yield {"method": "triangular", "means": t2[:9].tolist(), "gravity": 9.806}  # no residual dof: nulls
    for solver in ("lm", "gradient", "fixed16", "fixed32"):
        yield {
            "method": "triangular",
            "solver": solver,
            "means": t2[:20].tolist(),
            "gravity": 9.806,
            "holdout": t2.tolist(),
        }
    rec = _upload(client, "cube.csv", cube_csv, sampling_rate_hz=100, acc_unit="raw", gyr_unit="raw", mag_unit="raw")
    yield {"method": "cube", "recording_id": rec, "protocol": "cube24", "field_ut": FIELD_UT}
    x, _ = simulate_recording(
        np.random.default_rng(11),
        duration_s=6 * 3600,
        sampling_rate_hz=10.0,
        rest_median_s=30,
        move_median_s=10,
        posture_fraction=0.3,
    )
    buf = io.BytesIO()
    np.save(buf, x)
    rec = _upload(client, "wrist.npy", buf.getvalue(), sampling_rate_hz=10, acc_unit="g")
    yield {"method": "autocal", "recording_id": rec}
    yield {"method": "noise", "recording_id": _upload(client, "still.csv", _still_csv(), sampling_rate_hz=100)}
    mag, _, _ = simulate_turn_session(5, n=120)
    yield {"method": "magnetometer", "mag": mag.tolist(), "field_ut": 48.0}
    from tests.temperature_logs import warm_up_csv

    yield {
        "method": "temperature",
        "recording_id": _upload(client, "warm.csv", warm_up_csv(duration_s=600, sampling_rate_hz=20)),
    }
    import tempfile

    from tests.flight_compass_logs import seeded_flight, write_flight_compass_logs

    with tempfile.TemporaryDirectory() as folder:
        log, _ = write_flight_compass_logs(folder, seeded_flight(4, rate_hz=10.0))
        rec = _upload(client, "flight.bin", log.read_bytes())
    yield {"method": "compass_flight", "recording_id": rec}
    import base64

    from tests.conftest import DATA

    params = (DATA / "real" / "imports" / "px4_1.12_flight1_cal.params").read_bytes()
    yield {"method": "imported", "file_base64": base64.b64encode(params).decode("ascii"), "device_id": "fc-1"}


def _still_csv() -> bytes:
    """Two minutes of a still IMU (accelerometer and gyroscope) at 100 Hz."""
    from simulations.noise import simulate_still

    rng = np.random.default_rng(13)
    acc = simulate_still(rng, n_samples=12_000, sampling_rate_hz=100.0, N=2e-3, B=3e-4, K=1e-4, bias=[0.1, -0.2, G])
    gyr = simulate_still(rng, n_samples=12_000, sampling_rate_hz=100.0, N=1e-3, B=1e-4, K=1e-5)
    buf = io.StringIO()
    np.savetxt(
        buf, np.hstack([acc, gyr]), delimiter=",", comments="", fmt="%.9g", header="acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z"
    )
    return buf.getvalue().encode()


def test_every_method_s_response_is_described_field_by_field(client, cube_csv):
    adapter = TypeAdapter(CalibrationOut)
    seen = set()
    for request in _requests(client, cube_csv):
        r = client.post("/api/v1/calibrations", json=request)
        assert r.status_code == 201, r.text
        body = r.json()
        validated = adapter.validate_python(body)
        assert type(validated) is RESPONSE_MODELS[body["method"]]
        assert undescribed(validated) == [], request["method"]
        assert (body.get("choice") is not None) == (request["method"] == "auto")
        # What is read back is what was returned, and it validates the same way.
        again = client.get(f"/api/v1/calibrations/{body['id']}").json()
        assert again == body
        seen.add(body["method"])
    assert seen == set(RESPONSE_MODELS)
    listed = client.get("/api/v1/calibrations").json()["items"]
    assert len(listed) == 17 and all(undescribed(adapter.validate_python(b)) == [] for b in listed)


def test_openapi_documents_each_method_s_response(client):
    spec = client.get("/openapi.json").json()
    schemas = spec["components"]["schemas"]
    response = spec["paths"]["/api/v1/calibrations"]["post"]["responses"]["201"]["content"]["application/json"][
        "schema"
    ]
    assert response["discriminator"]["propertyName"] == "method"
    assert set(response["discriminator"]["mapping"]) == set(RESPONSE_MODELS)
    for name in ("SixPositionOut", "TriangularOut", "CubeOut", "AutocalOut", "AffineMetrics", "TriangularModel"):
        assert name in schemas
    assert {"X", "y", "type"} <= set(schemas["AffineModel"]["properties"])
    assert {"fit_error_max", "norm_error_max", "condition_number"} <= set(schemas["AffineMetrics"]["properties"])
    assert schemas["TriangularOut"]["properties"]["solver"]
    assert "additionalProperties" not in schemas["CalibrationList"]


@pytest.mark.parametrize(
    "request_body, status, code",
    [
        ({}, 422, "invalid_request"),
        ({"method": "six_position", "readings": [{"mean": [0, 0, 9.8], "up": "+q"}]}, 422, "invalid_request"),
        ({"method": "six_position", "readings": [{"mean": m, "up": u} for m, u in SIX[:5]]}, 422, "insufficient_data"),
        ({"method": "triangular", "means": [[0, 0, 9.8]] * 5}, 422, "insufficient_data"),
        ({"method": "auto", "means": [[0, 0, 9.8], [9.8, 0, 0], [0, 7, 7]]}, 422, "insufficient_data"),
        ({"method": "nonorthogonal", "means": [[0, 0, 9.8]] * 5}, 422, "insufficient_data"),
        ({"method": "orientations", "readings": [{"mean": [0, 0, 9.8], "up": "+z"}] * 3}, 422, "insufficient_data"),
        ({"method": "six_position", "readings": [{"mean": m, "up": "+x"} for m, _ in SIX]}, 422, "calibration_refused"),
        ({"method": "cube", "recording_id": "rec_missing"}, 404, "not_found"),
    ],
)
def test_errors_carry_a_stable_code(client, request_body, status, code):
    r = client.post("/api/v1/calibrations", json=request_body)
    assert r.status_code == status, r.text
    assert r.json()["code"] == code and r.json()["detail"]


def test_other_errors_carry_codes(client):
    assert client.get("/api/v1/nothing").json()["code"] == "http_error"
    assert client.get("/api/v1/calibrations/cal_missing/export").json()["code"] == "not_found"
    r = client.post("/api/v1/recordings", files={"file": ("x.bin", b"\x00\x01\x02" * 100, "application/octet-stream")})
    assert r.status_code in (415, 422) and r.json()["code"] in ("unsupported_media", "unreadable_log")
    six = client.post(
        "/api/v1/calibrations",
        json={
            "method": "six_position",
            "unit": "raw",
            "readings": [{"mean": [v * 100 for v in m], "up": u} for m, u in SIX],
        },
    )
    r = client.get(f"/api/v1/calibrations/{six.json()['id']}/export", params={"format": "ardupilot"})
    assert r.status_code == 422 and r.json()["code"] == "export_refused"
    r = client.get(f"/api/v1/calibrations/{six.json()['id']}/export", params={"format": "nope"})
    assert r.status_code == 422 and r.json()["code"] == "export_refused"
