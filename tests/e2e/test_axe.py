"""The axe helper finds what it should: a known violation on a page made for it, and axe's own
version from the packaged file (so a layout test's empty list means axe ran)."""

from __future__ import annotations

from tests.e2e.axe import axe_context, axe_source, violations


def test_axe_reports_a_missing_alt_text_and_runs_on_a_trical_page(browser, server):
    assert axe_source().startswith("/*! axe v4.")
    context = axe_context(browser)
    try:
        page = context.new_page()
        page.goto(server.url + "/")
        assert isinstance(violations(page), list)
        assert page.evaluate("() => axe.version").startswith("4.")
        page.set_content('<!doctype html><html lang="en"><title>t</title><main><img src="x.png"></main></html>')
        found = violations(page)
        assert "image-alt" in {v["id"] for v in found}
    finally:
        context.close()
