"""The pages: the start page (upload a log or paste six readings, see the result) and the wizard."""

from __future__ import annotations

import math
import re
from typing import Any

from fastapi import APIRouter, Request
from fastapi.responses import HTMLResponse
from fastapi.templating import Jinja2Templates

from app.calibration import CANONICAL_SIX
from app.guided.capture_rules import CAPTURE_S_DEFAULT, CAPTURE_S_RANGE, WIZARD_PROTOCOLS
from app.io.imports import FIRMWARE_NAMES
from app.io.readers.kinds import ACCEPTED_SUFFIXES
from app.reach.addresses import phone_url
from app.reach.phone_door import PASS_TTL_S
from app.reach.qr import qr_svg_data_uri

from .tables import SOURCES, page_tables

router = APIRouter(include_in_schema=False)


PROTOCOLS = {p.name: p for p in WIZARD_PROTOCOLS}
"""The protocols the wizard's pages offer, by name (app.guided.capture_rules: their words, template and flow)."""

SOURCE_PROTOCOLS = {"phone": tuple(p.name for p in WIZARD_PROTOCOLS if p.phone), "board": tuple(PROTOCOLS)}
"""The flows each source can do: a phone's motion events have no noise page (it records a board)."""

NOISE_LENGTHS_S = (10, 30, 60, 120, 300, 600, 1800, 3600, 7200)
"""The lengths of the noise page's still recording (s); a short one shows the white noise only."""
NOISE_DEFAULT_S = 300


def _templates(request: Request) -> Jinja2Templates:
    cached = getattr(request.app.state, "templates", None)
    if cached is None:
        cached = request.app.state.templates = Jinja2Templates(directory=request.app.state.settings.templates_dir)
    return cached


def not_found_page(request: Request) -> HTMLResponse:
    """The 404 page (templates/not_found.html): the address asked for, and links to the start page and the
    history; app.api.errors answers a browser's unknown address with it."""
    return _templates(request).TemplateResponse(
        request, "not_found.html", {"path": request.url.path[:200]}, status_code=404
    )


@router.get("/", response_class=HTMLResponse)
def index(request: Request):
    """Start page: Start on a phone with motion sensors; on a desktop, the QR code and address of
    the phone page (always), and the upload."""
    phone = phone_url(request)  # no QR code to nowhere: the page says why and what to do
    return _templates(request).TemplateResponse(
        request,
        "index.html",
        {
            "labels": list(CANONICAL_SIX),
            "tables": page_tables(),
            "phone_url": phone.url,
            "no_phone_url": phone.why_none,
            "phone_qr": qr_svg_data_uri(phone.url) if phone.url else None,
            # The door's code: its lifetime, and the certificate the phone's browser will warn of.
            "door": phone.door,
            "pass_minutes": f"{PASS_TTL_S / 60:g}",
            "accept": ",".join(ACCEPTED_SUFFIXES),
        },
    )


def phone_door_refused_page(request: Request, detail: str) -> HTMLResponse:
    """The phone's door's refusal (app.api.middleware.PhoneDoorGate), as a page: why, and what to do."""
    return _templates(request).TemplateResponse(
        request, "phone_door.html", {"detail": detail[:1].upper() + detail[1:]}, status_code=401
    )


def _capture_s(text: str | None) -> tuple[float | None, str | None]:
    """The seconds captured per position, or the reason the query value is refused."""
    if text is None or text == "":
        return CAPTURE_S_DEFAULT, None
    low, high = CAPTURE_S_RANGE
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or not low <= value <= high:
        return None, f"capture_s={text} is not a number of seconds between {low:g} and {high:g}"
    return value, None


def default_source(protocol: str) -> str:
    """The source a flow reads when the address names none: a phone, unless the phone cannot do it."""
    return "phone" if protocol in SOURCE_PROTOCOLS["phone"] else "board"


@router.get("/wizard", response_class=HTMLResponse)
def wizard(
    request: Request,
    protocol: str = "six",
    capture_s: str | None = None,
    source: str | None = None,
    check: str | None = None,
):
    """The guided calibration with the phone's own motion sensors (``source=phone``, the default) or
    a board's lines over Web Serial or Bluetooth (``source=board``): the page is that source's from
    its first screen (app/web/tables.py SOURCES holds its words). ``check`` (the compass's only): the turn checks
    that stored calibration (POST …/{id}/check with its readings) instead of making a new one."""
    seconds, problem = _capture_s(capture_s)
    source = source if source is not None else default_source(protocol)
    if protocol not in PROTOCOLS:
        problem = f"The protocol “{protocol}” is unknown: choose one below."
    elif source not in SOURCES:
        problem = f"The source “{source[:40]}” is unknown: source is phone or board; choose one below."
    elif protocol not in SOURCE_PROTOCOLS[source]:
        problem = f"A {source} cannot do “{PROTOCOLS[protocol].words}” on this page: choose one below."
    elif check is not None and (protocol != "compass" or not CALIBRATION_ID.match(check)):
        problem = (
            f"“{check[:40]}” is not a compass calibration's id to check: open the check from the calibration's page "
            "(Check it on a new recording), or choose a calibration below."
        )
    shown = source if source in SOURCES else "phone"
    context: dict[str, Any] = {
        "protocol": protocol,
        "flow": PROTOCOLS.get(protocol),
        "capture_s": seconds,
        "problem": problem,
        "source": shown,
        "words": SOURCES[shown],
        "choices": [(s, p, PROTOCOLS[p].words) for s in SOURCES for p in SOURCE_PROTOCOLS[s]],
        "capture_s_default": CAPTURE_S_DEFAULT,
        "capture_s_range": CAPTURE_S_RANGE,
        "poses": [
            (label, SOURCES[shown]["poseNames"][label], SOURCES[shown]["poseShort"][label]) for label in CANONICAL_SIX
        ],
        "tables": None if problem else page_tables(),
        "check_id": check,
    }
    if problem:
        page = "wizard.html"
    else:
        page = PROTOCOLS[protocol].template
        context.update(noise_lengths=NOISE_LENGTHS_S, noise_default=NOISE_DEFAULT_S)
    return _templates(request).TemplateResponse(request, page, context, status_code=400 if problem else 200)


CALIBRATION_ID = re.compile(r"^cal_[0-9a-f]{32}$")
"""A calibration's id as the store makes it (app/store/repository.py new_id)."""


@router.get("/c/{calibration_id}", response_class=HTMLResponse)
def calibration_page(request: Request, calibration_id: str, device: str | None = None):
    """A stored calibration's own page (``/c/latest?device=NAME``: that device's latest one). The
    page reads it through the API with the token the browser keeps for it, so the owner's scope is
    the API's; an id of another form is a 404 that says where to look."""
    latest = calibration_id == "latest"
    problem = None
    if latest and not device:
        problem = "/c/latest needs the device: /c/latest?device=NAME (the names are in your calibrations)."
    elif not latest and not CALIBRATION_ID.match(calibration_id):
        problem = (
            f"“{calibration_id[:80]}” is not a calibration's id: an id is cal_ and 32 hexadecimal digits. "
            "Your calibrations are listed in the history."
        )
    return _templates(request).TemplateResponse(
        request,
        "calibration.html",
        {
            "calibration_id": None if latest else calibration_id,
            "device": device if latest else None,
            "problem": problem,
            "tables": None if problem else page_tables(),
        },
        status_code=404 if problem else 200,
    )


LINK_CODE = re.compile(r"^[2-9A-HJKMNP-Za-hjkmnp-z]{10}$")
"""A short link's code (app/store/repository.py LINK_ALPHABET, either case)."""


@router.get("/s/{code}", response_class=HTMLResponse)
def link_page(request: Request, code: str):
    """A short link sent from the phone: the calibration it opens, read with the link until it expires."""
    problem = (
        None
        if LINK_CODE.match(code)
        else (f"“{code[:40]}” is not a link's code: a code is ten letters and digits, as the phone showed it.")
    )
    return _templates(request).TemplateResponse(
        request,
        "calibration.html",
        {
            "calibration_id": None,
            "device": None,
            "link": None if problem else code.upper(),
            "problem": problem,
            "tables": None if problem else page_tables(),
        },
        status_code=404 if problem else 200,
    )


@router.get("/history", response_class=HTMLResponse)
def history_page(request: Request, device: str | None = None):
    """The owner's calibrations, newest first (device, method, verdict, date), filtered by device."""
    return _templates(request).TemplateResponse(
        request,
        "history.html",
        {
            "device": device or "",
            "tables": page_tables(),
            "import_firmwares": list(FIRMWARE_NAMES.items()),
        },
    )
