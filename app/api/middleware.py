"""The application's own layers around every request, as pure ASGI middleware: the security headers, the
declared size of an upload, the rate limit, the phone's door.

They were ``@app.middleware("http")`` functions (Starlette's ``BaseHTTPMiddleware``), which run the rest of
the application in a task of its own and pass its response through a memory stream: a task group, a stream
and a streamed response per request and per layer: 1.2 ms of the 6.7–7.0 ms of server CPU time a six-position
calibration took under load (bench/load_six.py). These classes look at the request's headers and at
the response's start message only, and pass everything else through as it comes: the same statuses,
headers and bodies. (A response that a ``BaseHTTPMiddleware`` had turned into a stream was gzip-compressed
whatever its size; now only a response of ``GZipMiddleware``'s minimum size or more is, as app.main says.)
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from starlette.concurrency import run_in_threadpool
from starlette.datastructures import Headers, MutableHeaders
from starlette.requests import Request
from starlette.responses import RedirectResponse, Response
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from app.api.deps import asks_the_store, bearer_token, verified_identity
from app.api.errors import PayloadTooLarge, error_response, wants_page
from app.api.ratelimit import RateLimiter, retry_after
from app.reach.phone_door import COOKIE, ENTRY_PATH, OPEN_PREFIX, REFUSALS, REMEDY, SCOPE_KEY, SESSION_TTL_S


class SecurityHeaders:
    """Adds ``headers`` to every HTTP response that does not set them itself, and ``policy`` as its
    ``Content-Security-Policy`` outside ``/redoc`` (whose script comes from a CDN)."""

    def __init__(self, app: ASGIApp, headers: Mapping[str, str], policy: str):
        self.app = app
        self.headers = dict(headers)
        self.policy = policy

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        with_policy = not scope["path"].startswith("/redoc")

        async def send_with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                headers = MutableHeaders(scope=message)
                for name, value in self.headers.items():
                    headers.setdefault(name, value)
                if with_policy:
                    headers.setdefault("Content-Security-Policy", self.policy)
            await send(message)

        await self.app(scope, receive, send_with_headers)


class DeclaredUploadLimit:
    """Refuses, before its body is read, a request whose declared ``Content-Length`` is above
    ``limit_bytes`` + 64 KiB (the multipart form around the file); chunked uploads are counted while they
    are copied (app.api.recordings.save_upload)."""

    def __init__(self, app: ASGIApp, limit_bytes: int, limit_mb: float):
        self.app = app
        self.limit_bytes = limit_bytes
        self.limit_mb = limit_mb

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http":
            length = Headers(scope=scope).get("content-length")
            if length and length.isdigit() and int(length) > self.limit_bytes + 64 * 1024:
                refusal = error_response(413, str(PayloadTooLarge(self.limit_mb)), "payload_too_large")
                await refusal(scope, receive, send)
                return
        await self.app(scope, receive, send)


class RateLimit:
    """``limiter``'s token bucket per caller on /api/: the verified caller's (a valid key or session token),
    else the client's address; a request over the limit is a 429 with ``Retry-After``. Any other token,
    made up or expired, counts against the client's address like no token at all."""

    def __init__(self, app: ASGIApp, limiter: RateLimiter, per_minute: float):
        self.app = app
        self.limiter = limiter
        self.per_minute = per_minute

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or not scope["path"].startswith("/api/"):
            await self.app(scope, receive, send)
            return
        request = Request(scope)
        # The store is asked, in a worker thread, only for a session's token; a key is checked in memory.
        if asks_the_store(bearer_token(request)):
            identity = await run_in_threadpool(verified_identity, request)
        else:
            identity = verified_identity(request)
        client = identity or "addr:" + (request.client.host if request.client else "unknown")
        wait = self.limiter.acquire(client)
        if wait > 0:
            refusal = error_response(
                429,
                f"too many requests: at most {self.per_minute:g} a minute "
                f"(TRICAL_RATE_LIMIT_PER_MINUTE); retry in {retry_after(wait)} s",
                "rate_limited",
                {"Retry-After": retry_after(wait)},
            )
            await refusal(scope, receive, send)
            return
        await self.app(scope, receive, send)


class PhoneDoorGate:
    """Keeps the phone's door (app.reach.phone_door): a request that came through it passes with the door's
    session cookie, or to ``/static/``; ``/phone?pass=CODE`` lets a device in (a session cookie, then the start
    page); any other is a 401 that says why and what to do — ``refusal_page`` for a browser's page, the API's
    error body otherwise. A request of the desktop's listener passes untouched."""

    def __init__(self, app: ASGIApp, refusal_page: Callable[[Request, str], Response] | None = None):
        self.app = app
        self.refusal_page = refusal_page

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        door = scope.get(SCOPE_KEY) if scope["type"] == "http" else None
        if door is None:
            await self.app(scope, receive, send)
            return
        request = Request(scope)
        session = request.cookies.get(COOKIE)
        refusal: str | None = "none"
        if scope["path"] == ENTRY_PATH:
            # The same phone scanning again is in already; another device brings the code.
            fresh, refusal = (None, None) if door.admits(session) else door.enter(request.query_params.get("pass", ""))
            if refusal is None:
                entered = RedirectResponse("/", status_code=303)
                if fresh is not None:
                    entered.set_cookie(
                        COOKIE, fresh, max_age=int(SESSION_TTL_S), path="/", secure=True, httponly=True, samesite="lax"
                    )
                await entered(scope, receive, send)
                return
        elif door.admits(session) or scope["path"].startswith(OPEN_PREFIX):
            await self.app(scope, receive, send)
            return
        detail = f"{REFUSALS[refusal or 'none']}: {REMEDY}"
        if self.refusal_page is not None and wants_page(request):
            response = self.refusal_page(request, detail)
        else:
            response = error_response(401, detail, "unauthorized", {"WWW-Authenticate": 'Pass realm="trical phone"'})
        await response(scope, receive, send)
