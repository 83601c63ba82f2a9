"""The one place that maps errors to HTTP responses: ``{"detail": "...", "code": "..."}`` with a 4xx status.

``detail`` is for a person; ``code`` is what a client decides on (``wrong_turn``, ``already_captured`` …).

Bad input never yields a 500; an unexpected failure is logged with its traceback and answered
with a 500 whose message holds no internals.
"""

from __future__ import annotations

import logging

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException

from app.api.deps import Unauthorized
from app.api.schemas import METHODS
from app.calibration import CalibrationError, InsufficientDataError
from app.io.errors import ExportError, LogFormatError
from app.store import ConflictError, NotFoundError

log = logging.getLogger("trical")


class PayloadTooLarge(Exception):
    """An upload exceeds TRICAL_MAX_UPLOAD_MB."""

    def __init__(self, limit_mb: float):
        super().__init__(
            f"the upload is larger than the limit of {limit_mb:g} MiB (TRICAL_MAX_UPLOAD_MB): "
            "split the recording or raise the limit"
        )


def _location(loc) -> str:
    parts: list[str] = []
    for item in loc:
        if item in ("body", "query", "path", "form") and not parts:
            continue
        if item in METHODS and len(parts) == 0:
            continue  # the discriminator's branch, not a field
        if isinstance(item, int):
            parts.append(f"[{item}]")
        else:
            parts.append(("." if parts else "") + str(item))
    return "".join(parts) or "body"


def describe_validation(exc: RequestValidationError) -> str:
    """One readable sentence per problem, e.g. ``readings[2].up: Input should be '+x', ...``."""
    messages = []
    for err in exc.errors():
        if err.get("type") == "json_invalid":
            messages.append(f"the body is not valid JSON ({err.get('ctx', {}).get('error', 'parse error')})")
            continue
        if err.get("type") == "missing" and tuple(err.get("loc", ())) == ("body",):
            messages.append("the request needs a JSON body")
            continue
        if err.get("type") == "union_tag_not_found":
            messages.append(f"the field `{err.get('ctx', {}).get('discriminator', 'method').strip(chr(39))}` is "
                            f"required: one of {', '.join(METHODS)}")
            continue
        msg = err.get("msg", "invalid").removeprefix("Value error, ")
        messages.append(f"{_location(err.get('loc', ()))}: {msg}")
    return "; ".join(dict.fromkeys(messages)) or "invalid request"


def _json(status: int, detail, code: str, headers=None) -> JSONResponse:
    return JSONResponse({"detail": detail, "code": code}, status_code=status, headers=headers)


_LOG_FORMAT_CODES = {415: "unsupported_media", 413: "payload_too_large"}


def install_error_handlers(app: FastAPI) -> None:
    """Register the mapping of every error class to its HTTP status."""

    @app.exception_handler(RequestValidationError)
    async def _validation(request: Request, exc: RequestValidationError):
        return _json(422, describe_validation(exc), "invalid_request")

    @app.exception_handler(CalibrationError)
    async def _calibration(request: Request, exc: CalibrationError):
        if isinstance(exc, InsufficientDataError):
            return _json(422, str(exc), "insufficient_data")
        return _json(422, str(exc), getattr(exc, "code", "calibration_refused"))

    @app.exception_handler(LogFormatError)
    async def _log_format(request: Request, exc: LogFormatError):
        return _json(exc.status, str(exc), _LOG_FORMAT_CODES.get(exc.status, "unreadable_log"))

    @app.exception_handler(ExportError)
    async def _export(request: Request, exc: ExportError):
        return _json(422, str(exc), "export_refused")

    @app.exception_handler(NotFoundError)
    async def _not_found(request: Request, exc: NotFoundError):
        return _json(404, str(exc.args[0]) if exc.args else "not found", "not_found")

    @app.exception_handler(ConflictError)
    async def _conflict(request: Request, exc: ConflictError):
        return _json(409, str(exc), "already_captured")

    @app.exception_handler(Unauthorized)
    async def _unauthorized(request: Request, exc: Unauthorized):
        return _json(401, str(exc), "unauthorized", headers={"WWW-Authenticate": "Bearer"})

    @app.exception_handler(PayloadTooLarge)
    async def _too_large(request: Request, exc: PayloadTooLarge):
        return _json(413, str(exc), "payload_too_large")

    @app.exception_handler(StarletteHTTPException)
    async def _http(request: Request, exc: StarletteHTTPException):
        return _json(exc.status_code, exc.detail, "http_error", headers=exc.headers)

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception):
        log.exception("unexpected error on %s %s", request.method, request.url.path)
        return _json(500, "internal error: the request was not completed; nothing was stored", "internal_error")
