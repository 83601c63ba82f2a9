"""The address another machine opens this server at: the start page's QR code for a phone, and a short
link's page (*Send to my computer*) for a computer. TRICAL_PUBLIC_URL when set; else, for a phone, the phone's
door (app.reach.phone_door) with a new code where ``trical serve`` opened one, and for the computer a phone at
the door sends to, the desktop's listener; else the address the request reached the server at, with this
machine's LAN address in place of a loopback one (another machine cannot open 127.0.0.1)."""

from __future__ import annotations

from typing import NamedTuple

from starlette.requests import Request

from app.reach.phone_door import SCOPE_KEY, PhoneDoor
from app.reach.tls import lan_addresses, url_host

LOOPBACK = ("127.0.0.1", "localhost", "::1")


def reachable_url(request: Request) -> str:
    """The address another machine opens: TRICAL_PUBLIC_URL as given, else ``scheme://host[:port]/`` of
    this request (its Host), a loopback host replaced by this machine's first LAN address."""
    public_url = request.app.state.settings.public_url
    if public_url:
        return public_url
    door = request.scope.get(SCOPE_KEY)
    if door is not None:  # a phone at the door sends to the computer that runs trical, which the door would refuse
        return door.desktop_origin + "/"
    host = request.url.hostname or "127.0.0.1"
    if host in LOOPBACK:
        host = lan_addresses()[0]
    port = f":{request.url.port}" if request.url.port else ""
    return f"{request.url.scheme}://{url_host(host)}{port}/"


class PhoneAddress(NamedTuple):
    """What the start page offers a phone: the address, or why there is none; and the door whose new code the
    address holds (its certificate and the code's lifetime are told beside it)."""

    url: str | None
    why_none: str | None = None
    """``"no_lan"`` (this machine has no LAN address) or ``"no_door"`` (the door closed, the desktop on loopback)."""
    door: PhoneDoor | None = None


def phone_url(request: Request) -> PhoneAddress:
    """The address the start page's QR code gives a phone: TRICAL_PUBLIC_URL as given; else the phone's door at
    this machine's LAN address, with a new code for the desktop's page (a phone's own request came in already);
    else :func:`reachable_url`, unless ``trical serve`` listens on loopback alone (its door closed:
    ``--phone-port 0`` or a port taken)."""
    state = request.app.state
    if state.phone_door is not None and not state.settings.public_url:
        return _at_the_door(request, state.phone_door)
    url = reachable_url(request)
    if state.settings.public_url is None and state.listens_on in LOOPBACK:
        return PhoneAddress(None, "no_door")
    return PhoneAddress(url) if another_machine_can_open(url) else PhoneAddress(None, "no_lan")


def _at_the_door(request: Request, door: PhoneDoor) -> PhoneAddress:
    lan = lan_addresses()[0]
    if lan in LOOPBACK:
        return PhoneAddress(None, "no_lan")
    if request.scope.get(SCOPE_KEY) is door:
        return PhoneAddress(door.origin(lan) + "/")
    return PhoneAddress(door.entry_url(lan), door=door)


def another_machine_can_open(url: str) -> bool:
    """Whether the address :func:`reachable_url` gave is one another machine can open: not a loopback one, which
    it stays where this machine has no LAN address (no Wi-Fi or Ethernet connection) and no public URL is set."""
    host = url.partition("://")[2].split("/")[0].rsplit(":", 1)[0].strip("[]")
    return host not in LOOPBACK


def reachable_origin(request: Request) -> str:
    """``scheme://host[:port]`` of :func:`reachable_url`, without its path (TRICAL_PUBLIC_URL may carry one)."""
    scheme, _, rest = reachable_url(request).partition("://")
    return f"{scheme}://{rest.split('/')[0]}"
