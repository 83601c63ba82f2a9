"""POST/GET /api/v1/calibrations with explicit readings: the seed's numbers through the API."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from tests.conftest import seed_table
from tests.processes import run_ok

CANONICAL = ["-x", "+x", "-y", "+y", "-z", "+z"]
GT_ORDER = ["+y", "-y", "+x", "-x", "+z", "-z"]


def six_request(table, labels, **extra):
    return {
        "method": "six_position",
        "readings": [{"up": lab, "mean": row.tolist()} for lab, row in zip(labels, table[:6])],
        "gravity": 9.81,
        **extra,
    }


def test_table1_through_the_api(client):
    t1 = seed_table(1)
    r = client.post("/api/v1/calibrations", json=six_request(t1, CANONICAL, holdout=t1.tolist(), device_id="huawei"))
    assert r.status_code == 201, r.text
    body = r.json()
    assert body["id"].startswith("cal_") and body["method"] == "six_position" and body["ok"] is True
    assert body["model"]["type"] == "affine"
    np.testing.assert_allclose(
        body["model"]["X"],
        [[1.00381, -0.00227028, -0.0141925], [-0.00324982, 1.00003, 0.00734762], [-0.019297, 0.0362144, 0.988311]],
        atol=1e-5,
    )
    np.testing.assert_allclose(body["model"]["y"], [0.353222, 0.363473, -1.18129], atol=1e-5)
    m = body["metrics"]
    assert m["fit_error_max"] == pytest.approx(0.010601, abs=1e-6)
    assert m["fit_error_max_raw"] == pytest.approx(0.17386, abs=1e-5)
    assert m["holdout_count"] == 27
    assert m["holdout_norm_error_max"] == pytest.approx(0.0315425, abs=3e-7)  # see tests/calibration/test_affine.py
    assert m["holdout_norm_error_max_raw"] == pytest.approx(0.122075, abs=1e-6)
    assert {"norm_error_max", "norm_error_max_raw", "condition_number"} <= m.keys()
    assert body["uncertainty"]["dof"] == 2 and len(body["uncertainty"]["X"]) == 3
    assert len(body["readings"]) == 6 and body["readings"][0]["up"] == "-x"
    assert client.get(f"/api/v1/calibrations/{body['id']}").json() == body


def test_table3_gt_through_the_api(client):
    t3 = seed_table(3)
    r = client.post("/api/v1/calibrations", json=six_request(t3, GT_ORDER, holdout=t3.tolist()))
    assert r.status_code == 201, r.text
    m = r.json()["metrics"]
    assert m["fit_error_max"] == pytest.approx(0.0158458, abs=1e-7)
    assert m["fit_error_max_raw"] == pytest.approx(0.0725016, abs=1e-7)
    assert m["holdout_norm_error_max"] == pytest.approx(0.0138985, abs=1e-7)
    assert m["holdout_norm_error_max_raw"] == pytest.approx(0.0582853, abs=1e-7)


def test_orientations_method_matches_six_position(client):
    t1 = seed_table(1)
    req = six_request(t1, CANONICAL)
    a = client.post("/api/v1/calibrations", json=req).json()
    b = client.post("/api/v1/calibrations", json={**req, "method": "orientations"}).json()
    np.testing.assert_allclose(a["model"]["X"], b["model"]["X"], atol=1e-12)
    assert b["method"] == "orientations"


def test_list_by_device(client):
    t1 = seed_table(1)
    ids = {
        client.post("/api/v1/calibrations", json=six_request(t1, CANONICAL, device_id=d)).json()["id"]: d
        for d in ("phone-a", "phone-b", "phone-a")
    }
    items = client.get("/api/v1/calibrations", params={"device_id": "phone-a"}).json()["items"]
    assert {i["id"] for i in items} == {k for k, d in ids.items() if d == "phone-a"}
    assert len(client.get("/api/v1/calibrations").json()["items"]) == 3


def test_apply_and_exports(client, tmp_path):
    t1 = seed_table(1)
    cal = client.post("/api/v1/calibrations", json=six_request(t1, CANONICAL)).json()
    applied = client.post(f"/api/v1/calibrations/{cal['id']}/apply", json={"samples": t1.tolist()})
    assert applied.status_code == 200
    X, y = np.array(cal["model"]["X"]), np.array(cal["model"]["y"])
    expected = np.linalg.solve(X, (t1 - y).T).T
    np.testing.assert_allclose(applied.json()["samples"], expected, atol=1e-12)

    js = client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": "json"})
    assert js.status_code == 200 and "attachment" in js.headers["content-disposition"]
    doc = js.json()
    assert doc["schema_version"] == 1 and doc["input_unit"] == "m/s^2" and doc["gravity"] == 9.81
    M, o = np.array(doc["correction"]["M"]), np.array(doc["correction"]["o"])
    np.testing.assert_allclose((t1 - o) @ M.T, expected, atol=1e-12)

    header = client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": "c"})
    assert header.status_code == 200 and header.headers["content-type"].startswith("text/x-c")
    # Compile the header with the machine's C compiler and apply it with its own function.
    cc = shutil.which("cc") or shutil.which("gcc")
    assert cc, "a C compiler (gcc) is needed to test the C header export"
    (tmp_path / "cal.h").write_text(header.text)
    rows = ",".join("{{{!r},{!r},{!r}}}".format(*r) for r in t1.tolist())
    (tmp_path / "main.c").write_text(
        '#include <stdio.h>\n#include "cal.h"\n'
        f"static const float raw[{len(t1)}][3] = {{{rows}}};\n"
        "int main(void){float a[3];for(int i=0;i<%d;++i){trical_acc_apply(raw[i],a);"
        'printf("%%.9g %%.9g %%.9g\\n",a[0],a[1],a[2]);}return 0;}\n' % len(t1)
    )
    run_ok(
        [cc, "-std=c99", "-Wall", "-Werror", "-o", str(tmp_path / "apply"), str(tmp_path / "main.c")],
        timeout_s=120,
        cwd=tmp_path,
    )
    out = run_ok([str(tmp_path / "apply")], timeout_s=30).stdout
    firmware = np.loadtxt(out.splitlines())
    # Single precision on the device: agreement to float32 rounding of m/s² values.
    np.testing.assert_allclose(firmware, expected, atol=2e-5)


def test_no_dof_intervals_are_null_not_nan(client):
    req = {
        "method": "orientations",
        "readings": [
            {"up": "+x", "mean": [9.9, 0.1, 0.0]},
            {"up": "+y", "mean": [0.1, 9.7, 0.1]},
            {"up": "+z", "mean": [0.0, 0.2, 9.8]},
            {"up": "-x", "mean": [-9.7, 0.1, 0.0]},
        ],
    }
    r = client.post("/api/v1/calibrations", json=req)
    assert r.status_code == 201
    unc = r.json()["uncertainty"]
    assert unc["X"] is None and unc["dof"] == 0 and "degrees of freedom" in unc["note"]
