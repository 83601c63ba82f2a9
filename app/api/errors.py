"""The one place that maps errors to HTTP responses: ``{"detail": "...", "code": "..."}``.

``detail`` says in words what is wrong and how to fix it; ``code`` is stable, for programs (the
pages decide on it, never on the words). ``detail`` is in the API's words, or in the page's when the
request comes from the page (``X-Trical-Client: page``, app.words). Bad input never yields a 500; an unexpected failure
is logged with its traceback and answered with a 500 whose message holds no internals.

=====================  ======  ==========================================================
code                   status  when
=====================  ======  ==========================================================
invalid_request        422     the body or a parameter fails validation
insufficient_data      422     well-formed input that holds too little to determine the model
calibration_refused    422     other input that cannot be calibrated as given
wrong_turn             422     a cube wizard capture whose turn does not match the protocol
not_still              422     a wizard capture during which the device moved
pose_too_close         422     a free wizard pose within 10° of one already captured
unreadable_log         422     a log that cannot be read (format, columns, units)
bad_line               422     a line of a log that is not numbers where numbers are read: the detail
                               names the line, the column and the text
columns_ambiguous      422     a table whose columns its data let be read more than one way: the body
                               adds ``candidates`` (each ``sensors`` and its ``columns`` value),
                               ``preview`` (the table's first lines) and ``file`` (the file asked about);
                               send one as ``columns`` (of several files: ``NAME=COLUMNS;…``)
unsupported_media      415     an upload that is not a log trical reads
payload_too_large      413     an upload or JSON body over its limit
export_refused         422     an export format that does not fit the calibration
not_found              404     no such resource for this caller
already_captured       409     a wizard pose captured already (send redo)
unauthorized           401     a missing or invalid API key or session token; at the phone's door
                               (app.reach.phone_door), a request without the door's session
rate_limited           429     too many requests (with Retry-After)
http_error             4xx     any other HTTP error (unknown route, method not allowed); an unknown
                               address outside /api/ asked for by a browser (Accept: text/html)
                               is answered by the 404 page instead (templates/not_found.html)
internal_error         500     a failure of trical itself; nothing was stored
=====================  ======  ==========================================================
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping
from typing import Any, ClassVar

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import HTMLResponse, JSONResponse, Response
from starlette.exceptions import HTTPException as StarletteHTTPException

from app.api.deps import Unauthorized
from app.calibration import CalibrationError
from app.io.errors import ExportError, LogFormatError
from app.io.readers.columns import ColumnsAmbiguous
from app.methods import describe_errors
from app.store import ConflictError, NotFoundError
from app.words import asked, reader_of, render

log = logging.getLogger("trical")

LOG_FORMAT_CODES = {413: "payload_too_large", 415: "unsupported_media"}


class PayloadTooLarge(Exception):
    """An upload above TRICAL_MAX_UPLOAD_MB, or a JSON body above TRICAL_MAX_JSON_MB (the latter refused
    by app.api.body_limit before it is parsed)."""

    code = "payload_too_large"
    LIMITS: ClassVar[dict[str, tuple[str, str, str]]] = {
        "upload": ("the upload", "TRICAL_MAX_UPLOAD_MB", "split the recording or raise the limit"),
        "json": (
            "the JSON body",
            "TRICAL_MAX_JSON_MB",
            "send fewer samples per request (e.g. upload long "
            "recordings with POST /api/v1/recordings) or raise the limit",
        ),
    }

    def __init__(self, limit_mb: float, kind: str = "upload"):
        what, variable, fix = self.LIMITS[kind]
        super().__init__(f"{what} is larger than the limit of {limit_mb:g} MiB ({variable}): {fix}")


def describe_validation(exc: RequestValidationError) -> str:
    """One readable sentence per problem, e.g. ``readings[2].up: Input should be '+x', ...``."""
    return describe_errors(exc.errors())


def error_response(
    status: int,
    detail: str,
    code: str,
    headers: Mapping[str, str] | None = None,
    request: Request | None = None,
    extra: dict[str, Any] | None = None,
) -> JSONResponse:
    """The error body every failure of the API answers with, its ``detail`` in the words of who reads it, and
    ``asks``: the parameters the detail asks for (app.words.asked), when it names any, so that a page can
    show their controls without reading the words; ``extra``, what a refusal carries beside its words (a
    columns_ambiguous refusal's candidates and preview)."""
    body = {"detail": detail, "code": code, **(extra or {})}
    if asks := asked(detail):
        body["asks"] = asks
    if request is not None:
        body["detail"] = render(detail, *reader_of(request.headers))
    return JSONResponse(body, status_code=status, headers=headers)


API_PREFIX = "/api/"
"""Every address under it answers JSON, whoever asks."""


def wants_page(request: Request) -> bool:
    """A browser asking for a page: an address outside the API whose request accepts HTML (``Accept: text/html``,
    as a browser's navigation sends); any other caller, and every address under ``/api/``, is answered JSON."""
    if request.url.path.startswith(API_PREFIX) or request.url.path == API_PREFIX.rstrip("/"):
        return False
    return "text/html" in (request.headers.get("accept") or "").lower()


def install_error_handlers(app: FastAPI, not_found_page: Callable[[Request], HTMLResponse] | None = None) -> None:
    """Register the mapping of every error class to its HTTP status and code; ``not_found_page`` (the pages' 404
    page, given by app.main: the API does not import the pages) answers a browser's unknown address."""

    @app.exception_handler(RequestValidationError)
    async def _validation(request: Request, exc: RequestValidationError) -> JSONResponse:
        return error_response(422, describe_validation(exc), "invalid_request", request=request)

    @app.exception_handler(CalibrationError)
    async def _calibration(request: Request, exc: CalibrationError) -> JSONResponse:
        return error_response(
            422, str(exc), exc.code, request=request
        )  # calibration_refused, insufficient_data, not_still…

    @app.exception_handler(LogFormatError)
    async def _log_format(request: Request, exc: LogFormatError) -> JSONResponse:
        extra = (
            {"candidates": exc.candidates, "preview": exc.preview, "file": exc.file}
            if isinstance(exc, ColumnsAmbiguous)
            else None
        )
        return error_response(
            exc.status,
            str(exc),
            exc.code or LOG_FORMAT_CODES.get(exc.status, "unreadable_log"),
            request=request,
            extra=extra,
        )

    @app.exception_handler(ExportError)
    async def _export(request: Request, exc: ExportError) -> JSONResponse:
        return error_response(422, str(exc), "export_refused", request=request)

    @app.exception_handler(NotFoundError)
    async def _not_found(request: Request, exc: NotFoundError) -> JSONResponse:
        return error_response(404, str(exc.args[0]) if exc.args else "not found", "not_found", request=request)

    @app.exception_handler(ConflictError)
    async def _conflict(request: Request, exc: ConflictError) -> JSONResponse:
        return error_response(409, str(exc), "already_captured", request=request)

    @app.exception_handler(Unauthorized)
    async def _unauthorized(request: Request, exc: Unauthorized) -> JSONResponse:
        return error_response(401, str(exc), "unauthorized", {"WWW-Authenticate": "Bearer"}, request=request)

    @app.exception_handler(PayloadTooLarge)
    async def _too_large(request: Request, exc: PayloadTooLarge) -> JSONResponse:
        return error_response(413, str(exc), "payload_too_large", request=request)

    @app.exception_handler(StarletteHTTPException)
    async def _http(request: Request, exc: StarletteHTTPException) -> Response:
        if exc.status_code == 404 and not_found_page is not None and wants_page(request):
            return not_found_page(request)
        return error_response(exc.status_code, exc.detail, "http_error", exc.headers, request=request)

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception) -> JSONResponse:
        log.exception("unexpected error on %s %s", request.method, request.url.path)
        return error_response(
            500, "internal error: the request was not completed; nothing was stored", "internal_error", request=request
        )
