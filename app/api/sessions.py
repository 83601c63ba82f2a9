"""Routes of /api/v1/sessions: the guided wizard's server side (issue 6, docs/rest.md)."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter, Depends, Request

from app.api.deps import (
    SESSION_TOKEN_PREFIX,
    OwnerDep,
    ReaderDep,
    SettingsDep,
    StoreDep,
    Unauthorized,
    bearer_token,
    new_session_token,
    session_of_token,
    session_owner,
)
from app.api.schemas.calibrations import CalibrationOut
from app.api.schemas.sessions import CaptureIn, CaptureOut, SessionCreated, SessionIn, SessionOut
from app.guided import sessions
from app.store import NotFoundError
from app.words import render_body

router = APIRouter(prefix="/api/v1/sessions", tags=["sessions"])


def session_of(session_id: str, request: Request, store: StoreDep) -> sessions.Session:
    """The session the bearer token opens; 401 without a valid token, 404 for another session's id."""
    token = bearer_token(request)
    if token is None or not token.startswith(SESSION_TOKEN_PREFIX):
        raise Unauthorized(
            "a session call needs its token: send `Authorization: Bearer <token>` "
            "(the token POST /api/v1/sessions returned)"
        )
    if session_of_token(request, token) != session_id:
        raise NotFoundError(f"no session with id {session_id!r} for this token")
    return sessions.load(store, session_id)


@router.post("", status_code=201, response_model=SessionCreated)
def create_session(body: SessionIn, store: StoreDep, owner: OwnerDep, settings: SettingsDep) -> dict[str, Any]:
    """Start a wizard session; the token in the answer opens it (with TRICAL_API_KEYS set, starting
    one needs a key)."""
    token, digest = new_session_token()
    fields = body.model_dump()
    fields["target_mg"] = fields["target_mg"] or settings.free_target_mg
    return dict(sessions.view(sessions.create(store, fields, digest, owner=owner)), token=token)


@router.get("/{session_id}", response_model=SessionOut)
def get_session(reader: ReaderDep, session: sessions.Session = Depends(session_of)) -> dict[str, Any]:
    """A session: its captures, the positions that remain, its calibration once solved."""
    return render_body(sessions.view(session), *reader)


@router.post("/{session_id}/captures", status_code=201, response_model=CaptureOut)
def add_capture(
    *, body: CaptureIn, session: sessions.Session = Depends(session_of), store: StoreDep, reader: ReaderDep
) -> dict[str, Any]:
    """Check the raw samples of one still pose and store them (409 when that pose is done)."""
    capture, view = sessions.add_capture(store, session, body.model_dump())
    return render_body({"capture": capture, "session": view}, *reader)


@router.post("/{session_id}/solve", status_code=201, response_model=CalibrationOut, response_model_exclude_unset=True)
def solve_session(
    *, session: sessions.Session = Depends(session_of), store: StoreDep, reader: ReaderDep
) -> dict[str, Any]:
    """Compute and store the calibration of a complete session; its token reads it."""
    assert session.id is not None, "a session read from the store has its id"
    return render_body(
        store.add_calibration(sessions.solve(store, session), owner=session_owner(session.id), session_id=session.id),
        *reader,
    )
