"""Over HTTP: POST /api/v1/calibrations accepts the method table's methods and no other, and the export
route accepts, per stored calibration, the formats its method's entry offers."""

from __future__ import annotations

from app import methods

G = 9.80665
SIX = [
    {"up": up, "mean": [G * (up == f"+{a}") - G * (up == f"-{a}") for a in "xyz"]}
    for up in ("-x", "+x", "-y", "+y", "-z", "+z")
]


def test_a_method_with_no_entry_is_a_422_naming_the_methods(client):
    for body in ({"method": "auto_compass", "readings": SIX}, {"method": "affine", "readings": SIX}):
        r = client.post("/api/v1/calibrations", json=body)
        assert r.status_code == 422 and r.json()["code"] == "invalid_request", r.text
        detail = r.json()["detail"]
        assert body["method"] in detail and all(f"'{name}'" in detail for name in methods.METHODS), detail
    r = client.post("/api/v1/calibrations", json={"readings": SIX})
    assert r.status_code == 422
    assert r.json()["detail"] == f"the field `method` is required: one of {', '.join(methods.METHODS)}"


def test_the_openapi_request_and_response_unions_are_the_table(client):
    spec = client.get("/openapi.json").json()
    post = spec["paths"]["/api/v1/calibrations"]["post"]
    request = post["requestBody"]["content"]["application/json"]["schema"]
    assert set(request["discriminator"]["mapping"]) == set(methods.METHODS)
    response = post["responses"]["201"]["content"]["application/json"]["schema"]
    assert set(response["discriminator"]["mapping"]) == {
        m.name for m in methods.TABLE if m.response != methods.AS_CHOSEN
    }
    export = spec["paths"]["/api/v1/calibrations/{calibration_id}/export"]["get"]
    (fmt,) = [p for p in export["parameters"] if p["name"] == "format"]
    assert "method noise: kalibr, openvins, vins, json, csv, allan_svg" in fmt["description"]


def test_the_export_route_accepts_the_formats_of_the_calibration_s_method(client):
    cal = client.post("/api/v1/calibrations", json={"method": "six_position", "readings": SIX})
    assert cal.status_code == 201, cal.text
    url = f"/api/v1/calibrations/{cal.json()['id']}/export"
    offered = methods.BY_NAME["six_position"].formats
    for fmt in offered:
        r = client.get(url, params={"format": fmt})
        assert r.status_code == 200, (fmt, r.text)
    for fmt in sorted(set(methods.ALL_FORMATS) - set(offered)):
        r = client.get(url, params={"format": fmt})
        assert r.status_code == 422 and r.json()["code"] == "export_refused", (fmt, r.text)
        detail = r.json()["detail"]
        assert (
            f"format '{fmt}' does not fit this calibration, an accelerometer calibration (method six_position)"
            in detail
            and detail.endswith(f"use one of {', '.join(offered)}")
        ), detail
    r = client.get(url, params={"format": "docx"})
    assert r.status_code == 422 and "unknown export format 'docx'" in r.json()["detail"]
