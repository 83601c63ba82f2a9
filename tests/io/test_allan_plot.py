"""The Allan deviation picture of a noise calibration (app/io/exports/allan_plot.py): it parses as XML, has
its panels, lines, marks and values; the fitted slopes pass through the right points when their
coordinates are read back through the axis transform; null terms are left out with a note (its rendering in Chromium:
tests/e2e/test_allan_plot.py)."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from app.io.errors import ExportError
from app.io.exports.allan_plot import FLOOR, allan_svg, number, to_allan_svg
from app.io.exports.exporters import export_calibration
from tests.noise_bodies import noise_body

NS = {"s": "http://www.w3.org/2000/svg"}


def parse(svg: str) -> ET.Element:
    return ET.fromstring(svg.encode())


class Transform:
    """A panel's log–log transform, read back from its plot area."""

    def __init__(self, panel: ET.Element):
        rect = panel.find("s:rect[@class='plot-area']", NS)
        self.left, self.top = float(rect.get("x")), float(rect.get("y"))
        self.width, self.height = float(rect.get("width")), float(rect.get("height"))
        self.tau = [int(v) for v in rect.get("data-log-tau").split()]
        self.adev = [int(v) for v in rect.get("data-log-adev").split()]

    def tau_of(self, px: float) -> float:
        a, b = self.tau
        return 10 ** (a + (px - self.left) / self.width * (b - a))

    def sigma_of(self, py: float) -> float:
        a, b = self.adev
        return 10 ** (b - (py - self.top) / self.height * (b - a))


def points(d: str) -> list[tuple[float, float]]:
    nums = [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?", d)]
    return list(zip(nums[::2], nums[1::2]))


def panel(root: ET.Element, sensor: str) -> ET.Element:
    return root.find(f".//s:g[@class='panel'][@data-sensor='{sensor}']", NS)


def test_svg_parses_and_has_one_panel_per_sensor_with_title_desc_and_axis_labels(noise_three):
    root = parse(allan_svg(noise_three))
    assert root.tag == "{http://www.w3.org/2000/svg}svg" and root.get("role") == "img"
    assert "Allan deviation" in root.find("s:title", NS).text
    desc = root.find("s:desc", NS).text
    assert [p.get("data-sensor") for p in root.iterfind(".//s:g[@class='panel']", NS)] == ["acc", "gyr", "mag"]
    texts = ["".join(t.itertext()) for t in root.iter("{http://www.w3.org/2000/svg}text")]
    assert texts.count("τ (s)") == 3
    assert {"Allan deviation (m/s²)", "Allan deviation (rad/s)", "Allan deviation (µT)"} <= set(texts)
    for sensor in ("acc", "gyr", "mag"):
        p = panel(root, sensor)
        assert len(p.findall(".//s:path[@class='adev']", NS)) == 3
        assert len(p.findall(".//s:path[@class='band']", NS)) == 3
        for cls in ("white-noise", "random-walk", "bias-instability"):
            assert len(p.findall(f".//s:path[@class='fit {cls}']", NS)) == 3
        for key in ("noise_density", "random_walk", "bias_instability"):
            for v in noise_three["model"][sensor][key]:
                assert number(v) in desc
    # one sensor alone
    only = parse(allan_svg(noise_three, "gyr"))
    assert [p.get("data-sensor") for p in only.iterfind(".//s:g[@class='panel']", NS)] == ["gyr"]


def test_axes_are_distinguishable_without_colour(noise_three):
    p = panel(parse(allan_svg(noise_three)), "gyr")
    dashes = {
        path.get("data-axis"): path.get("stroke-dasharray") for path in p.iterfind(".//s:path[@class='adev']", NS)
    }
    assert len(set(dashes.values())) == 3
    marks = p.findall(".//s:g[@class='mark noise-density']", NS)
    shapes = {m.get("data-axis"): m[1].tag.split("}")[1] for m in marks}  # the ring, then the axis' marker
    assert shapes == {"x": "circle", "y": "rect", "z": "path"}


def test_ticks_are_decades_at_the_transformed_positions(noise_three):
    p = panel(parse(allan_svg(noise_three)), "acc")
    tr = Transform(p)
    taus = [(int(t.get("data-log10")), float(t.get("x1"))) for t in p.iterfind("s:line[@class='tick tau']", NS)]
    assert [k for k, _ in taus] == list(range(tr.tau[0], tr.tau[1] + 1))
    for k, x in taus:
        assert tr.tau_of(x) == pytest.approx(10.0**k, rel=1e-3)
    for t in p.iterfind("s:line[@class='tick adev']", NS):
        assert tr.sigma_of(float(t.get("y1"))) == pytest.approx(10.0 ** int(t.get("data-log10")), rel=1e-3)
    labels = {t.get("data-log10"): t.text for t in p.iterfind("s:text[@class='tick-label tau']", NS)}
    assert labels["0"] == "1" and labels["1"] == "10" and labels["-2"] == "10⁻²"


def test_curves_and_fitted_slopes_pass_through_the_right_points(noise_three):
    root = parse(allan_svg(noise_three))
    for sensor in ("acc", "gyr", "mag"):
        p = panel(root, sensor)
        tr = Transform(p)
        model, curve = noise_three["model"][sensor], noise_three["adev"][sensor]
        for i, axis in enumerate("xyz"):
            line = p.find(f".//s:path[@class='adev'][@data-axis='{axis}']", NS)
            back = [(tr.tau_of(x), tr.sigma_of(y)) for x, y in points(line.get("d"))]
            assert [t for t, _ in back] == pytest.approx(curve["tau_s"], rel=2e-3)
            assert [s for _, s in back] == pytest.approx([row[i] for row in curve["value"]], rel=2e-3)

            n, k, b = model["noise_density"][i], model["random_walk"][i], model["bias_instability"][i]
            white = p.find(f".//s:path[@class='fit white-noise'][@data-axis='{axis}']", NS)
            for x, y in points(white.get("d")):  # σ(τ) = N / √τ
                assert tr.sigma_of(y) * math.sqrt(tr.tau_of(x)) == pytest.approx(n, rel=2e-3)
            walk = p.find(f".//s:path[@class='fit random-walk'][@data-axis='{axis}']", NS)
            for x, y in points(walk.get("d")):  # σ(τ) = K √(τ / 3)
                assert tr.sigma_of(y) / math.sqrt(tr.tau_of(x) / 3) == pytest.approx(k, rel=2e-3)
            floor = p.find(f".//s:path[@class='fit bias-instability'][@data-axis='{axis}']", NS)
            for _x, y in points(floor.get("d")):  # σ = 0.664 B
                assert tr.sigma_of(y) == pytest.approx(FLOOR * b, rel=2e-3)

            marks = {
                m.get("class"): m
                for m in p.iterfind(f".//s:g[@data-axis='{axis}']", NS)
                if m.get("class", "").startswith("mark")
            }
            tau_min = curve["tau_s"][int(np.argmin([row[i] for row in curve["value"]]))]
            for cls, (tau, sigma) in {
                "mark noise-density": (1.0, n),
                "mark random-walk": (3.0, k),
                "mark bias-instability": (tau_min, FLOOR * b),
            }.items():
                ring = marks[cls].find("s:circle", NS)
                assert tr.tau_of(float(ring.get("cx"))) == pytest.approx(tau, rel=2e-3)
                assert tr.sigma_of(float(ring.get("cy"))) == pytest.approx(sigma, rel=2e-3)


def test_marks_are_labelled_with_their_values_and_units(noise_three):
    p = panel(parse(allan_svg(noise_three)), "gyr")
    model = noise_three["model"]["gyr"]
    for cls, key, head in (
        ("noise-density", "noise_density", "N at τ = 1 s"),
        ("random-walk", "random_walk", "K at τ = 3 s"),
        ("bias-instability", "bias_instability", "B (floor 0.664 B)"),
    ):
        label = ["".join(t.itertext()) for t in p.find(f"s:g[@class='label {cls}']", NS)]
        assert label[0] == head
        assert label[1] == "in " + model[f"{key}_unit"]
        assert label[2:] == [f"{g} {a}  {number(v)}" for g, a, v in zip("●■▲", "xyz", model[key])]


def test_null_terms_are_not_drawn_and_the_panel_says_so(noise_short):
    root = parse(allan_svg(noise_short))
    p = panel(root, "gyr")
    assert p.findall(".//s:path[@class='fit random-walk']", NS) == []
    assert p.findall(".//s:g[@class='mark random-walk']", NS) == []
    assert p.find("s:g[@class='label random-walk']", NS) is None
    assert {m.get("data-axis") for m in p.iterfind(".//s:path[@class='fit white-noise']", NS)} == {"x", "z"}
    note = " ".join(t.text for t in p.iterfind("s:text[@class='note']", NS))
    assert "random walk K of x, y, z" in note and "noise density N of y" in note and "too short" in note
    assert "Not available: noise density N of y; random walk K of x, y, z." in root.find("s:desc", NS).text


def test_refuses_what_it_cannot_draw(noise_three):
    with pytest.raises(ExportError, match="noise characterisation"):
        allan_svg({"id": "cal_1", "method": "six_position", "model": {"type": "affine"}})
    with pytest.raises(ExportError, match="no 'mag' sensor: choose one of gyr"):
        allan_svg(noise_body(("gyr",), seconds=120), "mag")
    out = export_calibration(noise_three, "allan_svg")
    assert out == to_allan_svg(noise_three)
    assert out.media_type == "image/svg+xml" and out.filename == "allan_cal_noise_fixture.svg"
