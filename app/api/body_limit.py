"""A cap on JSON request bodies under /api/ (TRICAL_MAX_JSON_MB), enforced before anything parses them.

A pure ASGI middleware: a declared ``Content-Length`` above the cap is answered 413 at once, without
reading the body; a chunked body is counted as its pieces arrive, and the 413 goes out as soon as the
count passes the cap, so at most one piece beyond the cap is ever held. (Starlette's
``BaseHTTPMiddleware`` cannot do this: the body would be read before the check.) Multipart uploads
are left to their own limit, TRICAL_MAX_UPLOAD_MB (app.api.recordings.save_upload).
"""

from __future__ import annotations

import json

from starlette.datastructures import Headers
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from app.api.errors import PayloadTooLarge


class JsonBodyLimit:
    """Refuse request bodies above ``limit_bytes`` with 413 ``payload_too_large``."""

    def __init__(self, app: ASGIApp, limit_bytes: int, limit_mb: float, prefix: str = "/api/"):
        self.app = app
        self.limit_bytes = limit_bytes
        self.limit_mb = limit_mb
        self.prefix = prefix

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or not scope["path"].startswith(self.prefix):
            await self.app(scope, receive, send)
            return
        headers = Headers(scope=scope)
        if headers.get("content-type", "").lower().startswith("multipart/"):
            await self.app(scope, receive, send)
            return
        length = headers.get("content-length", "")
        if length.isdigit() and int(length) > self.limit_bytes:
            await self._refuse(send)
            return

        received = 0
        refused = False
        started = False

        async def counting_receive() -> Message:
            nonlocal received, refused
            if refused:
                return {"type": "http.disconnect"}
            message = await receive()
            if message["type"] == "http.request":
                received += len(message.get("body", b""))
                if received > self.limit_bytes:
                    refused = True
                    if not started:
                        await self._refuse(send)
                    # The app sees a client that went away; whatever it answers is dropped below.
                    return {"type": "http.disconnect"}
            return message

        async def guarded_send(message: Message) -> None:
            nonlocal started
            if refused:
                return
            if message["type"] == "http.response.start":
                started = True
            await send(message)

        await self.app(scope, counting_receive, guarded_send)

    async def _refuse(self, send: Send) -> None:
        exc = PayloadTooLarge(self.limit_mb, "json")
        body = json.dumps({"detail": str(exc), "code": exc.code}).encode()
        await send(
            {
                "type": "http.response.start",
                "status": 413,
                "headers": [
                    (b"content-type", b"application/json"),
                    (b"content-length", str(len(body)).encode()),
                    (b"connection", b"close"),
                ],
            }
        )
        await send({"type": "http.response.body", "body": body})
