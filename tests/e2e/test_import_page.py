"""The history page brings in a calibration a device already holds, in real Chromium against a real server: a real
INAV `diff all` chosen in the page's import card is stored as the device's calibration and opens on its own page,
whose verdict says what was read; a file of no accepted kind is refused in the page's words."""

from __future__ import annotations

import re
from pathlib import Path

from tests.e2e.axe import axe_context
from tests.e2e.test_layout import layout_problems

REAL = Path(__file__).resolve().parents[1] / "data" / "real" / "imports"


def every_width(page, state: str) -> list[str]:
    """The layout's problems of the state at a small phone's, a phone's and a desktop's width (with a screenshot of
    each: test-artifacts/layout_<state>_<width>.png), back at the desktop's after."""
    problems = []
    for width in (320, 390, 1280):
        page.set_viewport_size({"width": width, "height": 844})
        problems += layout_problems(page, state, width)
    return problems


def test_an_inav_diff_all_is_brought_in_from_the_history_page(browser, server, tmp_path):
    context = axe_context(browser, viewport={"width": 1280, "height": 844}, device_scale_factor=1)
    try:
        page = context.new_page()
        errors: list[str] = []
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        page.goto(server.url + "/history")
        notes = tmp_path / "notes.txt"
        notes.write_text("hello\n")
        page.set_input_files("#import-file", str(notes))
        page.click("#import-submit")
        page.wait_for_function("document.querySelector('#import-msg').textContent.startsWith('Not brought in')")
        said = page.text_content("#import-msg")
        assert "the Firmware menu" in said and "`firmware`" not in said, said
        problems = every_width(page, "history_import_refused")
        page.set_input_files("#import-file", str(REAL / "inav_2.4_matekf411_diff_all.txt"))
        page.fill("#import-device", "mini-ar-wing")
        page.click("#import-submit")
        page.wait_for_function("/^\\/c\\/cal_/.test(location.pathname)")
        page.wait_for_selector("#verdict-words")
        page.wait_for_function("document.querySelector('#verdict-words').textContent.length > 0")
        assert page.text_content("#verdict-words").startswith("Apply it")
        meta = page.text_content("#cal-meta")
        assert "mini-ar-wing" in meta and "read from INAV 2.4.0 (INAV CLI diff/dump (MATEKF411))" in meta, meta
        assert re.search(r"/c/cal_[0-9a-f]{32}$", page.url)
        problems += every_width(page, "calibration_imported")
        assert problems == [], "\n".join(problems)
        assert not errors, errors
    finally:
        context.close()
