"""`trical serve --https` in real Chromium: a secure context, and the start page's QR code drawn under the CSP."""

from __future__ import annotations

import sys

from tests.e2e.conftest import shot
from tests.live_server import LiveServer, free_port


def test_https_start_page_shows_the_qr_code(browser, tmp_path):
    port = free_port()
    env = {"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}", "HOST": "", "TRICAL_PUBLIC_URL": ""}
    server = LiveServer(
        env,
        port=port,
        https_ca=tmp_path / "tls" / "cert.pem",
        command=[
            sys.executable,
            "-m",
            "app.cli",
            "serve",
            "--https",
            "--port",
            str(port),
            "--phone-port",
            str(free_port()),
        ],
    ).start()
    # The browser has not been told to trust the self-signed certificate: the user's "proceed".
    context = browser.new_context(viewport={"width": 360, "height": 640}, ignore_https_errors=True)
    try:
        page = context.new_page()
        errors: list[str] = []
        page.on("console", lambda msg: errors.append(msg.text) if msg.type == "error" else None)
        page.goto(server.url + "/")
        assert page.evaluate("window.isSecureContext") is True
        page.wait_for_function("document.getElementById('phone-qr').complete")
        assert page.evaluate("document.getElementById('phone-qr').naturalWidth") > 100  # the data: SVG was drawn
        assert page.get_attribute("#phone-qr", "alt").startswith("QR code of https://")
        assert page.text_content("#phone-h") == "Open on your phone"
        shot(page, "https_start_page_qr")
        assert errors == []  # no Content-Security-Policy refusal
    finally:
        context.close()
        server.stop()
