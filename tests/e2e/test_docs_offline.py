"""/docs in real Chromium with every request off the server's origin refused: Swagger UI's script,
stylesheet and icon come from trical itself, and the page runs under its Content-Security-Policy."""

from __future__ import annotations

from urllib.parse import urlsplit

from tests.e2e.conftest import shot


def test_docs_render_with_no_request_off_the_origin(page, server):
    origin = urlsplit(server.url)
    seen: list[str] = []
    refused: list[str] = []

    def only_the_server(route):
        url = route.request.url
        seen.append(url)
        parts = urlsplit(url)
        if (parts.scheme, parts.hostname, parts.port) == (origin.scheme, "127.0.0.1", origin.port):
            route.continue_()
        else:
            refused.append(url)
            route.abort()

    page.context.route("**/*", only_the_server)
    page.goto(server.url + "/docs")
    page.wait_for_selector(".opblock", timeout=20_000)
    shot(page, "docs_offline")
    paths = page.eval_on_selector_all(".opblock .opblock-summary-path", "els => els.map(e => e.textContent)")
    assert "/api/v1/calibrations" in {p.replace("\u200b", "") for p in paths}, paths
    assert refused == []
    assert any(u.endswith("/static/swagger-ui/swagger-ui-bundle.js") for u in seen), seen
    assert any(u.endswith("/openapi.json") for u in seen), seen
    assert page.errors == []  # a Content-Security-Policy refusal would be logged here
