"""Method `cube` (Särkkä et al.) through the API: a simulated 24-position session uploaded as a CSV log."""

from __future__ import annotations

import io

import numpy as np
import pytest

from simulations.cube import FIELD_UT, simulate_session, true_parameters
from tests.processes import run_ok

FS = 100.0


def session_csv(session, *, with_gyr=True) -> bytes:
    cols = [session.acc] + ([session.gyr] if with_gyr else []) + [session.mag]
    names = (
        ["acc_x", "acc_y", "acc_z"] + (["gyr_x", "gyr_y", "gyr_z"] if with_gyr else []) + ["mag_x", "mag_y", "mag_z"]
    )
    buf = io.StringIO()
    np.savetxt(buf, np.hstack(cols), delimiter=",", header=",".join(names), comments="", fmt="%.9g")
    return buf.getvalue().encode()


def upload_session(client, session, **kw):
    r = client.post(
        "/api/v1/recordings",
        files={"file": ("cube.csv", session_csv(session, **kw), "text/csv")},
        data={"sampling_rate_hz": str(FS), "acc_unit": "raw", "gyr_unit": "raw", "mag_unit": "raw"},
    )
    assert r.status_code == 201, r.text
    return r.json()


@pytest.fixture(scope="module")
def good_session():
    return simulate_session(np.random.default_rng(21), sampling_rate_hz=FS)


def test_cube24_session_through_the_api(client, good_session, tmp_path):
    rec = upload_session(client, good_session)
    assert rec["channels"] == ["acc", "gyr", "mag"]
    r = client.post(
        "/api/v1/calibrations",
        json={"method": "cube", "recording_id": rec["id"], "protocol": "cube24", "field_ut": FIELD_UT},
    )
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["ok"], body["reasons"]
    model, unc = body["model"], body["uncertainty"]
    assert model["type"] == "cube" and set(model["acc"]) >= {"S", "b", "D", "misalignment", "alpha_deg", "beta_deg"}
    for sensor in ("acc", "gyr", "mag"):
        S, b = true_parameters(sensor)
        assert np.all(np.abs(np.array(model[sensor]["S"]) - S) <= 3 * np.array(unc[sensor]["S"])), sensor
        assert np.all(np.abs(np.array(model[sensor]["b"]) - b) <= 3 * np.array(unc[sensor]["b"])), sensor
    assert len(body["sequence"]) == 23 and all(step["ok"] for step in body["sequence"])
    # raw = S f + b: applying the gyroscope model inverts it.
    f = np.array([[0.1, -0.2, 0.3]])
    S, b = np.array(model["gyr"]["S"]), np.array(model["gyr"]["b"])
    raw = f @ S.T + b
    out = client.post(f"/api/v1/calibrations/{body['id']}/apply", json={"samples": raw.tolist(), "sensor": "gyr"})
    np.testing.assert_allclose(out.json()["samples"], f, atol=1e-9)
    check_cube_exports(client, body, tmp_path)


def check_cube_exports(client, body, tmp_path, headers=None):
    """Every full-matrix export of a cube calibration holds each sensor's f = S⁻¹ (raw − b) (Särkkä et al. eq. (1)),
    applied here with the target's own means (a C compiler, a YAML parser, a CSV reader), and gives
    what trical's apply gives; offset/scale targets refuse raw units with the reason."""
    import csv
    import shutil

    import yaml

    def export(fmt):
        r = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": fmt}, headers=headers)
        assert r.status_code == 200, (fmt, r.text)
        return r

    rng = np.random.default_rng(5)
    sensors = [s for s in ("acc", "gyr", "mag") if body["model"].get(s)]
    raw = {
        s: np.array(body["model"][s]["b"]) + rng.normal(0, 0.3, (7, 3)) * np.abs(np.diag(body["model"][s]["S"]))
        for s in sensors
    }
    expected = {
        s: np.array(
            client.post(
                f"/api/v1/calibrations/{body['id']}/apply",
                json={"samples": raw[s].tolist(), "sensor": s},
                headers=headers,
            ).json()["samples"]
        )
        for s in sensors
    }

    corrections = export("json").json()["corrections"]
    assert list(corrections) == sensors
    for s in sensors:
        M, o = np.array(corrections[s]["M"]), np.array(corrections[s]["o"])
        np.testing.assert_allclose((raw[s] - o) @ M.T, expected[s], rtol=1e-12, atol=1e-12)

    doc = yaml.safe_load(export("yaml").text)
    table = {
        row[0]: [float(v) for v in row[1:]]
        for row in csv.reader(
            line for line in export("csv").text.splitlines() if not line.startswith(("#", "quantity"))
        )
    }
    for s in sensors:
        p = "" if s == "acc" else f"{s}_"
        for M, o in (
            (doc[p + "matrix"], doc[p + "offset"]),
            ([table[f"{p}M_{a}"] for a in "xyz"], table[p + "offset"]),
        ):
            np.testing.assert_allclose((raw[s] - np.array(o)) @ np.array(M).T, expected[s], rtol=1e-12, atol=1e-12)

    cc = shutil.which("cc") or shutil.which("gcc")
    assert cc, "a C compiler (gcc) is needed to test the C header export"
    (tmp_path / "cal.h").write_text(export("c").text)
    calls = "".join(
        f'for(int i=0;i<7;++i){{trical_{s}_apply(raw_{s}[i],f);printf("%.9g %.9g %.9g\\n",f[0],f[1],f[2]);}}'
        for s in sensors
    )
    arrays = "".join(
        f"static const float raw_{s}[7][3] = {{"
        + ",".join("{{{!r},{!r},{!r}}}".format(*r) for r in raw[s].tolist())
        + "};\n"
        for s in sensors
    )
    (tmp_path / "main.c").write_text(
        '#include <stdio.h>\n#include "cal.h"\n' + arrays + "int main(void){float f[3];" + calls + "return 0;}\n"
    )
    run_ok(
        [cc, "-std=c99", "-Wall", "-Werror", "-o", str(tmp_path / "apply"), str(tmp_path / "main.c")],
        timeout_s=120,
        cwd=tmp_path,
    )
    out = np.loadtxt(run_ok([str(tmp_path / "apply")], timeout_s=30).stdout.splitlines())
    # The header builds as C89 too (no inline keyword, no loop declarations), and a file that uses one sensor's
    # apply function is not warned about the others'.
    (tmp_path / "one.c").write_text(
        '#include "cal.h"\nvoid one(const float m[3], float f[3]) { trical_acc_apply(m, f); }\n'
    )
    run_ok(
        [
            cc,
            "-std=c89",
            "-pedantic",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-c",
            "-o",
            str(tmp_path / "one.o"),
            str(tmp_path / "one.c"),
        ],
        timeout_s=60,
        cwd=tmp_path,
    )
    for k, s in enumerate(sensors):
        # Single precision on the device: each float32 rounding (2⁻²⁴ relative) of m, o and M carried
        # through f = M (m − o), with a margin of 4.
        M, o = np.array(corrections[s]["M"]), np.array(corrections[s]["o"])
        bound = 4 * 2.0**-24 * (np.abs(raw[s]) + np.abs(o) + np.abs(raw[s] - o)) @ np.abs(M).T * 3
        assert np.all(np.abs(out[7 * k : 7 * (k + 1)] - expected[s]) <= bound), s
    for fmt in ("ardupilot", "px4"):
        r = client.get(f"/api/v1/calibrations/{body['id']}/export", params={"format": fmt}, headers=headers)
        if body["unit"] == "raw":
            assert r.status_code == 422 and "counts" in r.json()["detail"]
        else:
            assert r.status_code == 200 and "acc" in r.text.lower()


def test_wrong_rotation_is_named(client):
    s = simulate_session(np.random.default_rng(12), sampling_rate_hz=FS, wrong_rotations={18: "y+"})
    rec = upload_session(client, s)
    body = client.post(
        "/api/v1/calibrations", json={"method": "cube", "recording_id": rec["id"], "field_ut": FIELD_UT}
    ).json()
    assert body["ok"] is False and body["first_wrong_rotation"] == 18
    assert any("18" in reason for reason in body["reasons"])


def test_cube_bad_input(client, good_session):
    no_gyr = upload_session(client, good_session, with_gyr=False)
    r = client.post("/api/v1/calibrations", json={"method": "cube", "recording_id": no_gyr["id"], "field_ut": FIELD_UT})
    assert r.status_code == 422 and "no gyroscope columns" in r.json()["detail"]
    rec = upload_session(client, good_session)
    r = client.post(
        "/api/v1/calibrations",
        json={"method": "cube", "recording_id": rec["id"], "protocol": "ferraris", "field_ut": FIELD_UT},
    )
    assert r.status_code == 422 and "ferraris" in r.json()["detail"]
    r = client.post("/api/v1/calibrations", json={"method": "cube", "recording_id": rec["id"]})
    assert r.status_code == 422 and "field_ut" in r.json()["detail"]
    r = client.post(
        "/api/v1/calibrations", json={"method": "cube", "recording_id": rec["id"], "protocol": "dodecahedron"}
    )
    assert r.status_code == 422 and "protocol" in r.json()["detail"]
    r = client.post(
        "/api/v1/calibrations",
        json={"method": "cube", "recording_id": rec["id"], "field_ut": FIELD_UT, "protocol": {"rotations": "nonsense"}},
    )
    assert r.status_code == 422
