"""The Allan deviation picture (app/io/exports/allan_plot.py) in real headless Chromium at 320, 390 and
1280 px: it decodes as an image, scales to the width, and leaves a screenshot in test-artifacts/."""

from __future__ import annotations

import base64

import pytest

from app.io.exports.allan_plot import allan_svg
from tests.e2e.conftest import shot


@pytest.mark.parametrize("width", [320, 390, 1280])
def test_renders_in_chromium(browser, noise_three, noise_short, width):
    context = browser.new_context(viewport={"width": width, "height": 800}, device_scale_factor=2)
    page = context.new_page()
    errors: list[str] = []
    page.on("console", lambda msg: errors.append(msg.text) if msg.type == "error" else None)
    images = "".join(
        f'<img id="{name}" alt="Allan deviation" style="display:block;width:100%;max-width:600px;height:auto" '
        f'src="data:image/svg+xml;base64,{base64.b64encode(allan_svg(b).encode()).decode()}">'
        for name, b in (("all", noise_three), ("short", noise_short))
    )
    page.set_content(f"<!doctype html><body style='margin:8px'>{images}</body>")
    page.wait_for_function("[...document.images].every((i) => i.complete)")
    for name in ("all", "short"):
        natural = page.evaluate(
            f"[document.getElementById('{name}').naturalWidth, document.getElementById('{name}').width]"
        )
        assert natural[0] > 0, f"Chromium could not decode the {name} SVG"
        assert natural[1] == min(width - 16, 600)
    assert shot(page, f"allan_plot_{width}").stat().st_size > 10_000
    assert errors == []
    context.close()
