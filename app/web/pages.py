"""The pages: the start page (upload a log or paste six readings, see the result)."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import HTMLResponse
from fastapi.templating import Jinja2Templates

from app.io.exporters import FORMAT_NAMES
from app.qr import qr_svg_data_uri

router = APIRouter(include_in_schema=False)


def _templates(request: Request) -> Jinja2Templates:
    cached = getattr(request.app.state, "templates", None)
    if cached is None:
        cached = request.app.state.templates = Jinja2Templates(directory=request.app.state.settings.templates_dir)
    return cached


@router.get("/", response_class=HTMLResponse)
def index(request: Request):
    """Start page; with TRICAL_PUBLIC_URL set, a QR code of it for a phone."""
    public_url = request.app.state.settings.public_url
    return _templates(request).TemplateResponse(request, "index.html", {
        "labels": ["-x", "+x", "-y", "+y", "-z", "+z"],
        "formats": list(FORMAT_NAMES.items()),
        "public_url": public_url,
        "public_qr": qr_svg_data_uri(public_url) if public_url else None,
        "https_hint": not public_url and request.url.scheme != "https",
    })
