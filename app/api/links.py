"""Routes of short links: make one for a calibration (its owner), and open one (anyone with the code)."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Request

from app.api.deps import LINK_TOKEN_PREFIX, OwnerDep, SettingsDep, StoreDep, Unauthorized, bearer_token
from app.api.schemas.links import LinkOpened, LinkOut
from app.reach.addresses import reachable_origin
from app.reach.qr import qr_svg_data_uri

router = APIRouter(tags=["links"])


def link_address(request: Request, code: str) -> str:
    """The link's page, /s/CODE, at the address the other machine opens (app.reach.addresses: TRICAL_PUBLIC_URL's
    origin when set, else the address the phone reached the server at, a loopback one as its LAN address)."""
    return f"{reachable_origin(request)}/s/{code}"


@router.post(
    "/api/v1/calibrations/{calibration_id}/links",
    status_code=201,
    response_model=LinkOut,
    summary="A short link that reads the calibration for a while",
)
def create_link(
    calibration_id: str, request: Request, store: StoreDep, owner: OwnerDep, settings: SettingsDep
) -> dict[str, Any]:
    """A short link to the calibration, for another device to open until it expires (TRICAL_LINK_TTL_MIN)."""
    if (bearer_token(request) or "").startswith(LINK_TOKEN_PREFIX):
        raise Unauthorized("a link cannot make another link: send it from the device that made the calibration")
    link = store.add_link(calibration_id, owner=owner, ttl_s=60.0 * settings.link_ttl_min)
    url = link_address(request, link["code"])
    return {**link, "url": url, "qr": qr_svg_data_uri(url)}


@router.get("/api/v1/links/{code}", response_model=LinkOpened, summary="The calibration a link opens")
def open_link(code: str, store: StoreDep) -> dict[str, Any]:
    """The calibration a link's code opens and until when; the code, as ``Bearer lnk_<code>``, then reads it."""
    link = store.open_link(code)
    return {
        "code": code.upper(),
        "calibration_id": link["calibration_id"],
        "expires_at": link["expires_at"],
        "token": LINK_TOKEN_PREFIX + code.upper(),
    }
