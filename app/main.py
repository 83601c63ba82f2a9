"""The application: ``create_app()`` wires routers, static files, templates and error handlers.

``uvicorn app.main:app`` serves it with settings from the environment.
"""

from __future__ import annotations

import base64
import hashlib
import logging
import re

from fastapi import FastAPI
from fastapi.middleware.gzip import GZipMiddleware
from fastapi.openapi.docs import get_swagger_ui_html
from fastapi.responses import HTMLResponse
from fastapi.staticfiles import StaticFiles
from swagger_ui_bundle import swagger_ui_path

from app import __version__
from app.api import router as api_router
from app.api.body_limit import JsonBodyLimit
from app.api.errors import install_error_handlers
from app.api.middleware import DeclaredUploadLimit, PhoneDoorGate, RateLimit, SecurityHeaders
from app.api.ratelimit import RateLimiter
from app.config import Settings
from app.store import open_store
from app.web import router as web_router
from app.web.pages import not_found_page, phone_door_refused_page

SECURITY_HEADERS = {
    "X-Content-Type-Options": "nosniff",
    "X-Frame-Options": "DENY",
    "Referrer-Policy": "no-referrer",
    # The wizard reads the motion sensors of its own origin only.
    "Permissions-Policy": "accelerometer=(self), gyroscope=(self), magnetometer=(self), camera=(), microphone=()",
}
CONTENT_SECURITY_POLICY = (
    "default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data:; "
    "connect-src 'self'; frame-ancestors 'none'; base-uri 'none'; form-action 'self'"
)
"""No CORS middleware: cross-origin browser calls are refused by default (docs/architecture.md, issue 7)."""

SWAGGER_UI_ASSETS = "/static/swagger-ui"
"""Swagger UI's script, stylesheet and icon, served by trical from the swagger-ui-bundle-v2 package: /docs
needs no network beyond this server."""


def swagger_ui_page(openapi_url: str, title: str) -> tuple[bytes, str]:
    """The /docs page and its Content-Security-Policy.

    Swagger UI starts from one inline script that FastAPI writes into the page. Rather than loosen
    ``script-src`` for that page ('unsafe-inline') or rewrite FastAPI's page to add a per-request
    nonce, the policy of /docs is the site's policy plus the SHA-256 of that one script: the page is
    the same for every request, so its hash is computed once here, and a script injected into the
    page by any other means is still refused.
    """
    page = get_swagger_ui_html(
        openapi_url=openapi_url,
        title=title,
        swagger_js_url=f"{SWAGGER_UI_ASSETS}/swagger-ui-bundle.js",
        # Swagger UI's stylesheet, imported by trical's, which adds contrast and touch target sizes.
        swagger_css_url="/static/css/docs.css",
        swagger_favicon_url=f"{SWAGGER_UI_ASSETS}/favicon-32x32.png",
        # No badge that would ask an outside validator about the description; no link inside each
        # operation's expand button (a control nested in a control, which screen readers cannot reach).
        swagger_ui_parameters={"validatorUrl": None, "deepLinking": False},
    ).body
    page = bytes(page)  # a Response's body: bytes (a memoryview only to the type stubs)
    # The page's language, and its content in a main landmark (the element Swagger UI fills).
    for old, new in (
        (b"<html>", b'<html lang="en">'),
        (b'<div id="swagger-ui">\n    </div>', b'<main id="swagger-ui"></main>'),
    ):
        if page.count(old) != 1:
            raise RuntimeError(f"FastAPI's Swagger UI page no longer holds {old!r} once")
        page = page.replace(old, new)
    inline = re.findall(rb"<script>(.*?)</script>", page, flags=re.DOTALL)
    if len(inline) != 1:
        raise RuntimeError(f"expected one inline script in FastAPI's Swagger UI page, found {len(inline)}")
    digest = base64.b64encode(hashlib.sha256(inline[0]).digest()).decode()
    policy = CONTENT_SECURITY_POLICY.replace("script-src 'self'", f"script-src 'self' 'sha256-{digest}'")
    return page, policy


def create_app(settings: Settings | None = None) -> FastAPI:
    """Build the FastAPI application; the database is created and migrated here."""
    settings = settings or Settings.from_env()
    app = FastAPI(
        title="trical",
        version=__version__,
        # /docs is served below from local assets; /redoc stays FastAPI's own page (it loads its script
        # from a CDN, so it works only online and is left out of the site's policy).
        docs_url=None,
        summary="Calibration of accelerometers (and gyroscopes and magnetometers) of phones and IMU boards.",
    )
    app.state.settings = settings
    app.state.store = open_store(settings.database_url, settings.recordings_dir)
    app.state.phone_door = None  # the phone's door, when `trical serve` opens one (app.cli.serve)
    app.state.listens_on = None  # the desktop listener's address, when `trical serve` runs it

    # Innermost first: each add_middleware wraps what was added before it. Pure ASGI layers
    # (app.api.middleware): no task or stream of their own per request.
    app.add_middleware(DeclaredUploadLimit, limit_bytes=settings.max_upload_bytes, limit_mb=settings.max_upload_mb)
    # A request through the phone's door (app.reach.phone_door) passes only with its session; the refusal
    # inside the security headers, which it carries as every page does.
    app.add_middleware(PhoneDoorGate, refusal_page=phone_door_refused_page)
    app.add_middleware(SecurityHeaders, headers=SECURITY_HEADERS, policy=CONTENT_SECURITY_POLICY)
    if settings.rate_limit_per_minute > 0:
        app.add_middleware(
            RateLimit, limiter=RateLimiter(settings.rate_limit_per_minute), per_minute=settings.rate_limit_per_minute
        )
    # Responses of 1 KiB or more compressed for clients that accept gzip (the pages, their scripts,
    # calibration bodies and exports); inside the JSON cap, which stays the outermost layer.
    app.add_middleware(GZipMiddleware, minimum_size=1024)
    # Outermost, so that an oversized JSON body is refused before any other layer touches it.
    app.add_middleware(JsonBodyLimit, limit_bytes=settings.max_json_bytes, limit_mb=settings.max_json_mb)
    install_error_handlers(app, not_found_page)
    app.include_router(api_router)
    app.include_router(web_router)
    assert app.openapi_url is not None, "the app serves its OpenAPI document"
    docs_page, docs_policy = swagger_ui_page(app.openapi_url, f"{app.title} - Swagger UI")

    @app.get("/docs", include_in_schema=False)
    def swagger_ui() -> HTMLResponse:
        return HTMLResponse(docs_page, headers={"Content-Security-Policy": docs_policy})

    # Before /static, which would otherwise take these paths.
    app.mount(SWAGGER_UI_ASSETS, StaticFiles(directory=swagger_ui_path), name="swagger-ui")
    app.mount("/static", StaticFiles(directory=settings.static_dir), name="static")
    logging.getLogger("trical").setLevel(logging.INFO)
    return app


def __getattr__(name: str):
    # `app` is built on first access so that importing app.main has no side effects.
    if name == "app":
        globals()["app"] = create_app()
        return globals()["app"]
    raise AttributeError(name)
