"""The address another machine opens this server at: the start page's QR code for a phone, and a short
link's page (*Send to my computer*) for a computer. One rule for both: TRICAL_PUBLIC_URL when set, else
the address the request reached the server at, with this machine's LAN address in place of a loopback
one (another machine cannot open 127.0.0.1)."""

from __future__ import annotations

from starlette.requests import Request

from app.reach.tls import lan_addresses

LOOPBACK = ("127.0.0.1", "localhost", "::1")


def reachable_url(request: Request) -> str:
    """The address another machine opens: TRICAL_PUBLIC_URL as given, else ``scheme://host[:port]/`` of
    this request (its Host), a loopback host replaced by this machine's first LAN address."""
    public_url = request.app.state.settings.public_url
    if public_url:
        return public_url
    host = request.url.hostname or "127.0.0.1"
    if host in LOOPBACK:
        host = lan_addresses()[0]
    port = f":{request.url.port}" if request.url.port else ""
    return f"{request.url.scheme}://{'[' + host + ']' if ':' in host else host}{port}/"


def another_machine_can_open(url: str) -> bool:
    """Whether the address :func:`reachable_url` gave is one another machine can open: not a loopback one, which
    it stays where this machine has no LAN address (no Wi-Fi or Ethernet connection) and no public URL is set."""
    host = url.partition("://")[2].split("/")[0].rsplit(":", 1)[0].strip("[]")
    return host not in LOOPBACK


def reachable_origin(request: Request) -> str:
    """``scheme://host[:port]`` of :func:`reachable_url`, without its path (TRICAL_PUBLIC_URL may carry one)."""
    scheme, _, rest = reachable_url(request).partition("://")
    return f"{scheme}://{rest.split('/')[0]}"
