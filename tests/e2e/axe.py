"""axe-core in real Chromium, from the copy of axe.min.js that the axe-playwright-python package ships
(no CDN): ``violations(page)`` injects it and returns what ``axe.run()`` found.

The pages' Content-Security-Policy refuses inline scripts, so the script tag that carries axe is
refused too: pages checked with axe are opened in a context made by ``axe_context`` (Playwright's
``bypass_csp``). The policy itself is checked by the tests that run without it (test_phone_qr.py,
test_docs_offline.py and every test that asserts ``page.errors == []``).
"""

from __future__ import annotations

from functools import cache
from importlib.resources import files


@cache
def axe_source() -> str:
    return (files("axe_playwright_python") / "axe.min.js").read_text(encoding="utf-8")


def axe_context(browser, **options):
    """A browser context in which axe can be injected into trical's pages."""
    return browser.new_context(bypass_csp=True, **options)


def violations(page, options: dict | None = None) -> list[dict]:
    """``axe.run(document, options)``'s violations on the page as it is now."""
    if not page.evaluate("() => typeof window.axe === 'object'"):
        page.add_script_tag(content=axe_source())
    return page.evaluate("async (options) => (await axe.run(document, options)).violations", options or {})


def describe(found: list[dict]) -> str:
    """One line per violation and up to three of its elements, for a failure message."""
    lines = []
    for v in found:
        targets = ["  ".join(" ".join(n["target"]) for n in v["nodes"][:3])]
        lines.append(f"{v['id']} ({v['impact']}, {len(v['nodes'])} elements): {v['help']}: {targets[0]}")
    return "\n".join(lines)
