"""The wizard's modules keep their roles: the flows and the state change data and call the server,
only the render loops and the flows' views (their render hooks) write the page; no page module branches
on a flow, a method or a model type (each is looked up once in a table); the page applies no model; and
no script decides on an error's message text or bare status."""

from __future__ import annotations

import re
from pathlib import Path

JS = Path(__file__).resolve().parents[2] / "static" / "js"
DOM = re.compile(r"\bdocument\.|\bwindow\.|\$\(|\.innerHTML|\.textContent\s*=|\.hidden\s*=|\.focus\(")


def test_only_the_render_loops_and_the_views_touch_the_page():
    for name in (
        "flow_six.js",
        "flow_cube.js",
        "flow_free.js",
        "wizard_state.js",
        "compass_flow.js",
        "mag_sphere.js",
        "result.js",
    ):
        text = (JS / name).read_text()
        assert not DOM.findall(text), (name, DOM.findall(text))
    wizard = (JS / "wizard.js").read_text()
    assert "function render(" in wizard
    # The flow is the module the server's protocol table names, imported by that name (no table of flows here).
    from app.guided.capture_rules import WIZARD_PROTOCOLS

    assert "import(`./${root.dataset.flow}.js`)" in wizard
    for protocol in WIZARD_PROTOCOLS:
        if protocol.flow:
            assert "export default" in (JS / f"{protocol.flow}.js").read_text(), protocol.flow
            assert "export default" in (JS / f"{protocol.flow}_view.js").read_text(), protocol.flow
    # Each flow brings its view's render hooks; the compass page renders through the same loop.
    for name in ("flow_six_view.js", "flow_cube_view.js", "flow_free_view.js", "compass_view.js"):
        assert "VIEW_DEFAULTS" in (JS / name).read_text(), name
    for name in ("wizard.js", "wizard_compass.js"):
        text = (JS / name).read_text()
        assert "renderShared(" in text and "newState(" in text, name
    noise = (JS / "wizard_noise.js").read_text()  # its own cards, the same state, files and live region
    assert "newState(" in noise and "renderDownloads(" in noise and "renderVoice(" in noise


# The branch sites of bench/code_shape.py: a flow flag, or a method, model type, protocol or flow compared
# with a literal.
BRANCH = re.compile(r"if \((cube|free)\)|(type|method|protocol|flow) !?==+ [\"']")


def test_no_page_module_branches_on_a_flow_or_a_kind_of_result():
    for name in (
        "wizard.js",
        "wizard_render.js",
        "wizard_compass.js",
        "wizard_noise.js",
        "result_view.js",
        "correction_view.js",
        "use_calibration.js",
        "result_kinds.js",
        "result.js",
    ):
        text = (JS / name).read_text()
        assert not BRANCH.findall(text), (name, BRANCH.findall(text))


def test_the_page_applies_no_model():
    # The norms per position are drawn from the server's readings (and a cube's from POST …/apply):
    # no inverse of X, K or S, no X⁻¹(m − y) on the page.
    for path in JS.glob("*.js"):
        text = path.read_text()
        assert not re.search(r"\binvert3\b|triangularAsAffine|function calibrate\(model", text), path.name


def test_errors_are_told_apart_by_their_code():
    for path in JS.glob("*.js"):
        text = path.read_text()
        assert not re.search(r"err(or)?\.message\.(startsWith|includes|match|indexOf)", text), path.name
        assert not re.search(r"err(or)?\.status\s*===?\s*[1-9]", text), (
            path.name
        )  # only 0 (network) may be told by status
    for name in ("flow_six.js", "flow_cube.js"):
        assert 'err.code === "already_captured"' in (JS / name).read_text()
    assert 'err.code === "wrong_turn"' in (JS / "flow_cube.js").read_text()


def test_the_page_scripts_keep_the_code_s_line_length():
    """The page's JavaScript keeps the Python's line length (120, pyproject.toml's ruff)."""
    long = [
        f"{path.name}:{n}"
        for path in sorted(JS.glob("*.js"))
        for n, line in enumerate(path.read_text().splitlines(), 1)
        if len(line) > 120
    ]
    assert not long, long
