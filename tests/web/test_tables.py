"""The pages take their constants from Python: app.web.tables.page_tables() is built from the core's
and the sessions' own constants, rendered into the page as JSON, and not copied into the scripts."""

from __future__ import annotations

import json
import re
from html.parser import HTMLParser
from pathlib import Path

import numpy as np

from app.calibration import CANONICAL_SIX, STANDARD_GRAVITY
from app.calibration.cube.protocols import CUBE24_ROTATIONS, CUBE24_UPS, cube24
from app.calibration.cube.turns import TURN_WORDS
from app.calibration.magnetometer import coverage
from app.calibration.magnetometer.fit import MIN_COVERAGE, MIN_READINGS
from app.calibration.shared.capture import STILL_MAX_STD_G
from app.calibration.shared.orientations import LABEL_MAX_ANGLE_DEG, UP_VECTORS
from app.guided import capture_rules
from app.web.tables import COVERAGE_TO_SOLVE, POSE_NAMES, SOURCES, face_words, page_tables

JS = Path(__file__).resolve().parents[2] / "static" / "js"


class _Scripts(HTMLParser):
    """The <script> elements of a page: their attributes and text."""

    def __init__(self):
        super().__init__()
        self.scripts: list[tuple[dict, str]] = []
        self._open: dict | None = None

    def handle_starttag(self, tag, attrs):
        if tag == "script":
            self._open = dict(attrs)
            self.scripts.append((self._open, ""))

    def handle_data(self, data):
        if self._open is not None:
            attrs, text = self.scripts[-1]
            self.scripts[-1] = (attrs, text + data)

    def handle_endtag(self, tag):
        if tag == "script":
            self._open = None


def rendered_tables(html: str) -> tuple[dict, dict]:
    parser = _Scripts()
    parser.feed(html)
    found = [(attrs, text) for attrs, text in parser.scripts if attrs.get("id") == "trical-tables"]
    assert len(found) == 1, parser.scripts
    return found[0][0], json.loads(found[0][1])


def test_the_tables_are_the_core_s_constants():
    t = page_tables()
    assert t["gravity"] == STANDARD_GRAVITY
    assert t["poses"]["order"] == list(CANONICAL_SIX)
    assert {k: tuple(float(x) for x in v) for k, v in t["poses"]["up"].items()} == UP_VECTORS
    assert t["poses"]["names"] == {label: POSE_NAMES[label] for label in CANONICAL_SIX}
    protocol = cube24()
    assert t["cube24"]["rotations"] == list(CUBE24_ROTATIONS) and t["cube24"]["ups"] == list(CUBE24_UPS)
    np.testing.assert_array_equal(t["cube24"]["attitudes"], protocol.attitudes.round())
    np.testing.assert_allclose(t["cube24"]["attitudes"], protocol.attitudes, atol=1e-12)
    assert t["cube24"]["turnWords"] == TURN_WORDS


def test_the_compass_faces_are_coverage_py_s():
    t = page_tables()["compass"]
    np.testing.assert_allclose(t["faceCentres"], coverage.FACE_CENTRES, atol=1e-12)
    np.testing.assert_allclose(t["vertices"], coverage.ICOSAHEDRON_VERTICES, atol=1e-12)
    assert t["faces"] == coverage.ICOSAHEDRON_FACES.tolist() and t["faceNames"] == list(coverage.FACE_NAMES)
    assert t["minReadings"] == MIN_READINGS and t["coverageToSolve"] == COVERAGE_TO_SOLVE
    assert MIN_COVERAGE < COVERAGE_TO_SOLVE < 1.0  # a turn the page solves is not refused for coverage alone
    assert sorted(t["faceWords"]) == ["board", "phone"]
    assert all(len(set(words)) == 20 for words in t["faceWords"].values())


def test_the_compass_faces_in_words():
    assert face_words("+z+y") == "screen, towards the top"
    assert face_words("-x-y-z") == "back, bottom-left corner"
    assert face_words("+x+y+z") == "screen, top-right corner"
    assert face_words("-z+x") == "back, towards the right"
    assert face_words("+x-y") == "right edge, towards the bottom"
    # A board's: its component side and the arrows printed on it.
    assert face_words("+z+y", "board") == "component side, towards the Y arrow"
    assert face_words("-z-x", "board") == "underside, towards the back of the X arrow"
    assert face_words("+x+y+z", "board") == "component side, the corner the X and Y arrows point to"
    assert face_words("-x-y-z", "board") == "underside, the corner away from the X and Y arrows"
    assert face_words("+x-y-z", "board") == "underside, the corner the X arrow points to, away from the Y arrow"


def test_the_page_s_thresholds_stay_inside_the_server_s_checks():
    capture = page_tables()["capture"]
    # Still for the page means still for the server: the page leaves "still" before the server's limits.
    assert capture["spreadLow"] < capture["spreadHigh"] < STILL_MAX_STD_G * STANDARD_GRAVITY
    assert capture["gyrLow"] < capture["gyrHigh"] == capture_rules.MAX_ROTATION_DEG_S
    assert capture["maxAngleDeg"] == LABEL_MAX_ANGLE_DEG  # the six flow's pose angle is the server's
    assert page_tables()["cube24"]["maxAngleDeg"] < capture_rules.CUBE_FACE_MAX_ANGLE_DEG


def test_the_pages_render_the_tables_as_data_the_csp_never_runs(client):
    for path in ("/wizard", "/wizard?protocol=cube24", "/wizard?protocol=compass", "/"):
        r = client.get(path)
        assert r.status_code == 200 and "script-src 'self'" in r.headers["content-security-policy"]
        attrs, tables = rendered_tables(r.text)
        assert attrs == {"type": "application/json", "id": "trical-tables"}, path
        assert tables == json.loads(json.dumps(page_tables())), path
    assert "trical-tables" not in client.get("/wizard?protocol=cube12").text  # no script on a refused address


def test_the_scripts_hold_no_copy_of_the_tables():
    sources = {p.name: p.read_text() for p in JS.glob("*.js")}
    assert "tables.js" in sources
    for name, text in sources.items():
        for words in TURN_WORDS.values():
            assert words not in text, (name, words)
        for pose_name in [*POSE_NAMES.values(), *SOURCES["board"]["poseNames"].values(), *SOURCES["board"]["sides"]]:
            assert f'"{pose_name}"' not in text, (name, pose_name)
        assert "9.80665" not in text, name
        assert not re.search(r'"z\+",\s*"z\+",\s*"z\+"', text), name  # the cube24 rotations
        assert not re.search(r'\["-x",\s*"\+x",\s*"-y"', text), name  # the six poses
        assert not re.search(r"gyrHigh:\s*\d|spreadLow:\s*\d|maxAngleDeg:\s*\d", text), name


def test_the_capture_duration_bounds_are_the_sessions_(client):
    low, high = capture_rules.CAPTURE_S_RANGE
    assert client.post("/api/v1/sessions", json={"capture_s": high + 0.1}).status_code == 422
    assert client.post("/api/v1/sessions", json={"capture_s": low}).status_code == 201
    assert client.post("/api/v1/sessions", json={}).json()["capture_s"] == capture_rules.CAPTURE_S_DEFAULT
    assert client.get(f"/wizard?capture_s={high + 0.1}").status_code == 400
    assert client.get(f"/wizard?capture_s={low}").status_code == 200


def test_each_source_s_default_use_is_one_its_calibrations_offer():
    """The one rule of the use offered first (app/web/uses.py DEFAULT_USES): a board's calibration goes into its
    firmware (the C header), a flight log's into that firmware's parameters, a phone's into a phone app."""
    from app.io.readers import SOURCES
    from app.web.uses import CALIBRATION_USES, DEFAULT_USES, uses_table

    assert set(DEFAULT_USES) == set(SOURCES)
    first = {source: next(u for u in CALIBRATION_USES if u["key"] in keys) for source, keys in DEFAULT_USES.items()}
    assert {s: (u["key"], u["format"]) for s, u in first.items()} == {
        "board": ("firmware", "c"),
        "px4": ("px4", "px4"),
        "ardupilot": ("ardupilot", "ardupilot"),
        "phone": ("app", "json"),
    }
    assert uses_table()["defaults"] == {s: list(k) for s, k in DEFAULT_USES.items()}


def test_each_kind_of_result_tells_the_page_what_it_shows():
    """The page's presenter says what the page shows of each result class (app/web/result_pages.py PageFacts);
    the server sends it by model type, and the page draws it with the drawings it names: each set of uses exists,
    results sharing a model type agree, and each drawing, plot box and plot format the facts name is on the page."""
    from app.calibration.registry import class_of, registered_types
    from app.web.result_pages import page_facts, page_kinds
    from app.web.uses import USE_SETS

    kinds = page_kinds()
    assert page_tables()["kinds"] == kinds
    classes = [class_of({"model": {"type": t}, "method": t}) for t in registered_types()]
    assert set(kinds) == {"", *(cls.MODEL_TYPE for cls in classes)}
    for cls in classes:
        same_type = [c for c in classes if c.MODEL_TYPE == cls.MODEL_TYPE]
        assert {page_facts(c) for c in same_type} == {page_facts(cls)}, cls
    kinds_js = (JS / "result_kinds.js").read_text()
    templates = "".join(p.read_text() for p in (JS.parents[1] / "templates").glob("*.html"))
    for facts in kinds.values():
        assert facts["uses"] in USE_SETS
        for drawing in (facts["model"], facts["norms"], facts["caption"]):
            assert not drawing or re.search(rf"\b{drawing}: \w+", kinds_js), drawing
        if facts["plot"]:
            assert f'id="{facts["box"][1:]}"' in templates and facts["plot"] in USE_SETS[facts["uses"]][1]
    assert kinds[""]["correction"] and not kinds["noise"]["correction"]
