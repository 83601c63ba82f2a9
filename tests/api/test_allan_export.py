"""GET /api/v1/calibrations/{id}/export?format=allan_svg over real HTTP, from a real trical server
on a real SQLite file: the noise calibration's Allan deviation plot as an SVG image, and a clear 422
for a calibration that is not a noise characterisation."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import httpx
import pytest

from app.io.exports.allan_plot import allan_svg
from app.store import open_store
from tests.live_server import LiveServer
from tests.noise_bodies import noise_body


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """One server for the module's tests (each stores its own calibrations): a start costs seconds."""
    tmp_path = tmp_path_factory.mktemp("allan")
    s = LiveServer({"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}"}).start()
    yield s, tmp_path
    s.stop()


def test_allan_svg_downloads_over_http(server):
    s, tmp_path = server
    store = open_store(f"sqlite:///{tmp_path / 'trical.db'}", tmp_path / "recordings")
    stored = store.add_calibration(noise_body(("acc", "gyr"), seconds=300), owner=None)
    r = httpx.get(f"{s.url}/api/v1/calibrations/{stored['id']}/export", params={"format": "allan_svg"})
    assert r.status_code == 200, r.text
    assert r.headers["content-type"].startswith("image/svg+xml")
    assert f'filename="allan_{stored["id"]}.svg"' in r.headers["content-disposition"]
    assert r.text == allan_svg(stored)
    root = ET.fromstring(r.content)
    assert [p.get("data-sensor") for p in root.iter("{http://www.w3.org/2000/svg}g") if p.get("class") == "panel"] == [
        "acc",
        "gyr",
    ]


def test_allan_svg_of_another_method_is_refused_with_a_reason(server):
    s, _ = server
    readings = [
        {"up": up, "mean": [9.80665 * (up == f"+{a}") - 9.80665 * (up == f"-{a}") for a in "xyz"]}
        for up in ("-x", "+x", "-y", "+y", "-z", "+z")
    ]
    cal = httpx.post(f"{s.url}/api/v1/calibrations", json={"method": "six_position", "readings": readings})
    assert cal.status_code == 201, cal.text
    r = httpx.get(f"{s.url}/api/v1/calibrations/{cal.json()['id']}/export", params={"format": "allan_svg"})
    assert r.status_code == 422
    assert r.json()["code"] == "export_refused"
    assert "noise characterisation" in r.json()["detail"] and "use one of json" in r.json()["detail"]
