"""The phone's door: the HTTPS listener ``trical serve`` (and so ``make run``) opens on every interface for the
phone that scanned the start page's QR code, and for nothing else on the network (docs/architecture.md,
*A phone's way in*).

A phone's browser gives a page its motion sensors only in a secure context, and the desktop's listener stays
on loopback over HTTP. So a second listener serves the same application over TLS at TRICAL_PHONE_PORT
(app.config) with the certificate trical already makes; every request through it needs a session of this door:

- the start page, opened on this computer, draws a QR code of ``https://<LAN address>:<port>/phone?pass=CODE``;
  the code is new for each view of the page, lets in one device, and only for ``PASS_TTL_S``;
- the phone that opens it first is given a session (an HttpOnly, Secure cookie for ``SESSION_TTL_S``) and sent
  on to the start page; the same phone may scan the code again;
- any other request — another device with the used code, an expired or made-up code, a peer without one — is refused
  with 401 (app.api.middleware.PhoneDoorGate), which says what to do. ``/static/`` (the page's public scripts
  and styles, no data) is open, so that the refusal page has its style.
"""

from __future__ import annotations

import secrets
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from app.reach.tls import url_host

PASS_TTL_S = 600.0
"""How long a start page's code lets a phone in: long enough to find the phone and pass its browser's warning."""
SESSION_TTL_S = 12 * 3600.0
"""How long a phone let in stays in: a day's calibrations without scanning again."""
ENTRY_PATH = "/phone"
"""The address of the QR code: ``ENTRY_PATH?pass=CODE``."""
COOKIE = "trical_phone"
OPEN_PREFIX = "/static/"
"""Served to anyone at the door: the page's own scripts and styles, which hold no data."""
PASS_ALPHABET = "23456789abcdefghjkmnpqrstuvwxyz"
"""A code's letters: none two people read alike (no 0/o, 1/l/i), lower case to type on a phone."""
PASS_LENGTH = 10
"""31¹⁰ ≈ 8·10¹⁴ codes: out of reach of guessing within a code's ten minutes."""

SCOPE_KEY = "trical.phone_door"
"""The key of a request's ASGI scope that holds the door it came through (set by :func:`through`, the door's
listener's own application; a request of the desktop's listener has none)."""

REFUSALS = {
    "none": "this address lets in only the phone that scanned the QR code on trical's start page",
    "unknown": f"this code is not one the start page shows now (a code works for {PASS_TTL_S / 60:g} minutes)",
    "used": "this code has let in another device already (a code lets in one phone)",
}
"""Why the door refused a request, the cause first; the remedy is :data:`REMEDY`."""
REMEDY = "open trical's start page on the computer that runs it, reload it for a new code and scan that with this phone"


@dataclass
class PhoneDoor:
    """The door's passes and sessions, kept in memory: they die with the server, as a code on a screen should.

    Attributes
    ----------
    port : int
        Where the door listens (every interface).
    desktop_origin : str
        The desktop listener's ``scheme://host:port``: where a link the phone sends to "my computer" points
        (the computer that runs trical; the door would refuse it).
    fingerprint : str
        The SHA-256 fingerprint of the door's certificate, as the phone's browser shows it.
    clock : callable
        Seconds, monotonic (a test's clock may be given).
    """

    port: int
    desktop_origin: str
    fingerprint: str
    clock: Callable[[], float] = time.monotonic
    _passes: dict[str, tuple[float, str | None]] = field(default_factory=dict)
    _sessions: dict[str, float] = field(default_factory=dict)
    _lock: threading.Lock = field(default_factory=threading.Lock)

    def origin(self, host: str) -> str:
        """``https://host:port`` of the door at ``host`` (an address of this machine)."""
        return f"https://{url_host(host)}:{self.port}"

    def entry_url(self, host: str) -> str:
        """The address of a new code at ``host``: what the start page's QR code holds."""
        return f"{self.origin(host)}{ENTRY_PATH}?pass={self.new_pass()}"

    def new_pass(self) -> str:
        """A new code, good for :data:`PASS_TTL_S` and one device."""
        code = "".join(secrets.choice(PASS_ALPHABET) for _ in range(PASS_LENGTH))
        with self._lock:
            self._forget_expired()
            self._passes[code] = (self.clock() + PASS_TTL_S, None)
        return code

    def enter(self, code: str) -> tuple[str | None, str | None]:
        """Let in the device that brings ``code``.

        Returns
        -------
        (session, refusal) : tuple of str or None
            A new session's cookie value and None, or None and why the code lets nobody in (a key of
            :data:`REFUSALS`). The first device to bring a code is let in; the code then lets in no other.
        """
        code = code.strip().lower()
        with self._lock:
            self._forget_expired()
            expires, used_by = self._passes.get(code, (None, None))
            if expires is None:
                return None, "unknown"  # never made, or made and forgotten when it expired: the same to its holder
            if used_by is not None:
                return None, "used"
            session = secrets.token_urlsafe(32)
            self._passes[code] = (expires, session)
            self._sessions[session] = self.clock() + SESSION_TTL_S
            return session, None

    def admits(self, session: str | None) -> bool:
        """Whether ``session`` (the cookie's value) is a live session of this door."""
        if not session:
            return False
        with self._lock:
            expires = self._sessions.get(session)
            return expires is not None and expires > self.clock()

    def _forget_expired(self) -> None:
        now = self.clock()
        self._passes = {code: kept for code, kept in self._passes.items() if kept[0] > now}
        self._sessions = {session: until for session, until in self._sessions.items() if until > now}


def through(app, door: PhoneDoor):
    """The application as the door's listener serves it: each request's scope carries the door it came through
    (under :data:`SCOPE_KEY`), so that the application's gate (app.api.middleware.PhoneDoorGate) keeps it and a
    page knows a phone's request from the desktop's."""

    async def door_app(scope, receive, send):
        await app({**scope, SCOPE_KEY: door} if scope["type"] == "http" else scope, receive, send)

    return door_app
