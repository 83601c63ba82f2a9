"""The wizard's modules keep their roles: the flows and the state change data and call the server,
only wizard.js writes the page; and no script decides on an error's message text or bare status."""

from __future__ import annotations

import re
from pathlib import Path

JS = Path(__file__).resolve().parents[2] / "static" / "js"
DOM = re.compile(r"\bdocument\.|\bwindow\.|\$\(|\.innerHTML|\.textContent\s*=|\.hidden\s*=|\.focus\(")


def test_only_wizard_js_touches_the_page():
    for name in ("flow_six.js", "flow_cube.js", "wizard_state.js", "compass_flow.js", "mag_sphere.js"):
        text = (JS / name).read_text()
        assert not DOM.findall(text), (name, DOM.findall(text))
    wizard = (JS / "wizard.js").read_text()
    assert "flow_six.js" in wizard and "flow_cube.js" in wizard and "function render(" in wizard


def test_errors_are_told_apart_by_their_code():
    for path in JS.glob("*.js"):
        text = path.read_text()
        assert not re.search(r"err(or)?\.message\.(startsWith|includes|match|indexOf)", text), path.name
        assert not re.search(r"err(or)?\.status\s*===?\s*[1-9]", text), path.name  # only 0 (network) may be told by status
    for name in ("flow_six.js", "flow_cube.js"):
        assert 'err.code === "already_captured"' in (JS / name).read_text()
    assert 'err.code === "wrong_turn"' in (JS / "flow_cube.js").read_text()
