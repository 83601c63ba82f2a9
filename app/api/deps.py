"""Dependencies shared by the routers: settings, the caller's identity and the store.

They are ``async def``: FastAPI runs a plain ``def`` dependency in a worker thread, a hop to the thread pool
and back for each of them on every request; these read the request and the application's state, and only
the caller's identity may ask the store (for a session's or a link's token), in a worker thread then.
"""

from __future__ import annotations

import hashlib
import hmac
import secrets
from typing import Annotated, cast

from fastapi import Depends, Request
from starlette.concurrency import run_in_threadpool

from app.config import Settings
from app.store import NotFoundError, Store
from app.words import reader_of


class Unauthorized(Exception):
    """No valid API key was sent while TRICAL_API_KEYS is set (mapped to 401 in app.api.errors)."""


async def get_settings(request: Request) -> Settings:
    return cast(Settings, request.app.state.settings)  # app.main's create_app sets it


def bearer_token(request: Request) -> str | None:
    """The token of an ``Authorization: Bearer <token>`` header, if any."""
    scheme, _, token = request.headers.get("authorization", "").partition(" ")
    return token.strip() if scheme.lower() == "bearer" and token.strip() else None


SESSION_TOKEN_PREFIX = "tks_"
"""Wizard session tokens start with this, so they are never mistaken for API keys."""


def new_session_token() -> tuple[str, str]:
    """A session token (192 random bits) and the hash the store keeps instead of it."""
    token = SESSION_TOKEN_PREFIX + secrets.token_urlsafe(24)
    return token, token_hash(token)


def token_hash(token: str) -> str:
    return hashlib.sha256(token.encode()).hexdigest()


def session_owner(session_id: str) -> str:
    """The owner of what a wizard session creates: only its token reads it."""
    return f"session:{session_id}"


def session_of_token(request: Request, token: str | None) -> str | None:
    """The session a ``tks_…`` token opens; None for any other token. A session token that opens
    no session is a 401."""
    if token is None or not token.startswith(SESSION_TOKEN_PREFIX):
        return None
    session_id = app_store(request).session_id_for_token(token_hash(token))
    if session_id is None:
        raise Unauthorized("the session token is not valid: start a new session with POST /api/v1/sessions")
    return session_id


LINK_TOKEN_PREFIX = "lnk_"
"""A short link's code as a bearer token (``lnk_<code>``): it reads its one calibration as its owner."""


def link_owner(request: Request, token: str | None) -> tuple[bool, str | None]:
    """(True, the owner) when ``token`` is a link's that holds for the calibration this request names;
    (False, None) for any other token. An expired link, or one used for another calibration, is a 401."""
    if token is None or not token.startswith(LINK_TOKEN_PREFIX):
        return False, None
    try:
        link = app_store(request).open_link(token[len(LINK_TOKEN_PREFIX) :])
    except NotFoundError as exc:
        raise Unauthorized(str(exc)) from None
    if request.path_params.get("calibration_id") != link["calibration_id"]:
        raise Unauthorized("a link reads its own calibration only: open the address it came with")
    return True, link["owner"]


def not_a_link(request: Request) -> None:
    """Refuse a short link's token where a request would read more than the link's one calibration (a comparison
    names another, a check a recording): a link reads its own calibration only."""
    token = bearer_token(request)
    if token is not None and token.startswith(LINK_TOKEN_PREFIX):
        raise Unauthorized(
            "a link reads its own calibration only: check or compare calibrations with the API key or the session "
            "that made them"
        )


def asks_the_store(token: str | None) -> bool:
    """Whether telling who holds ``token`` reads the store (a session's or a link's token): done in a worker
    thread then, and in memory for an API key or no token."""
    return token is not None and token.startswith((SESSION_TOKEN_PREFIX, LINK_TOKEN_PREFIX))


async def get_owner(request: Request) -> str | None:
    """Who is calling (:func:`owner_of`); the store is asked, in a worker thread, only for a session's or a
    link's token."""
    if asks_the_store(bearer_token(request)):
        return await run_in_threadpool(owner_of, request)
    return owner_of(request)


def owner_of(request: Request) -> str | None:
    """Who is calling: None when API keys are off, else a stable id derived from the key.

    With TRICAL_API_KEYS set every API call needs one of the keys; each key sees only what it
    created (the store filters by owner, so another key's resource is a 404). A wizard session's
    token (``tks_…``) is an identity of its own, whether or not keys are set: it reads what its
    session created and nothing else (docs/rest.md, sessions).
    """
    token = bearer_token(request)
    is_link, owner = link_owner(request, token)
    if is_link:
        return owner
    session_id = session_of_token(request, token)
    if session_id is not None:
        return session_owner(session_id)
    keys = request.app.state.settings.api_keys
    if not keys:
        return None
    if token is None:
        raise Unauthorized("this server needs an API key: send `Authorization: Bearer <key>`")
    owner = key_owner(token, keys)
    if owner is None:
        raise Unauthorized("the API key is not valid for this server")
    return owner


def key_owner(token: str, keys: tuple[str, ...]) -> str | None:
    """The owner id of an API key among ``keys`` (compared in constant time), else None."""
    if not any(hmac.compare_digest(token.encode(), key.encode()) for key in keys):
        return None
    return "key:" + token_hash(token)[:32]


def verified_identity(request: Request) -> str | None:
    """The caller's identity when its bearer token proves one, else None; never raises.

    A valid API key or a ``tks_…`` token that opens a session gives the same id as
    :func:`get_owner`; no token, a made-up one or an expired session gives None, so that the
    rate limit counts such calls against the client's address (app.main).
    """
    token = bearer_token(request)
    if token is None:
        return None
    try:
        session_id = session_of_token(request, token)
    except Unauthorized:
        return None
    if session_id is not None:
        return session_owner(session_id)
    keys = request.app.state.settings.api_keys
    return key_owner(token, keys) if keys else None


def app_store(request: Request) -> Store:
    """The application's store; routes pass the caller's owner (get_owner) to each of its methods."""
    return cast(Store, request.app.state.store)  # app.main's create_app sets it


async def get_store(request: Request) -> Store:
    """The application's store (:func:`app_store`), as a route's dependency."""
    return app_store(request)


StoreDep = Annotated[Store, Depends(get_store)]
"""A route's store (``store: StoreDep``)."""
OwnerDep = Annotated[str | None, Depends(get_owner)]
"""Who calls the route (``owner: OwnerDep``): None when API keys are off."""
SettingsDep = Annotated[Settings, Depends(get_settings)]
"""The service's settings (``settings: SettingsDep``)."""


async def get_reader(request: Request) -> tuple[str, str | None]:
    """Who reads the answer (app.words.reader_of): ``("page", its path)`` from the page, else ``("api", None)``."""
    return reader_of(request.headers)


ReaderDep = Annotated[tuple[str, str | None], Depends(get_reader)]
"""Who reads a route's answer (``reader: ReaderDep``): its messages go through app.words.render_body."""
