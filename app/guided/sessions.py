"""Guided wizard sessions (issue 6): create, capture a pose, solve — between the API and the store.

A session belongs to whoever holds its token.  Each capture holds the raw samples of one pose
(kept in the store); the server checks them itself (app.calibration.shared.capture) rather than trusting
the page.

A session is a :class:`Session`, read from the store's row and written to it in one place
(:meth:`Session.from_row`, :meth:`Session.body`); its protocol is a strategy of app.guided.protocols, looked up
once when the session is read: what it asks for next, how it checks a capture, when the session may be
solved and how (``six``, ``free``, ``cube24``: the module's docstring says each).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from app.calibration import CalibrationError
from app.guided.protocols import SESSION_PROTOCOLS, SessionProtocol
from app.store import ConflictError
from app.workflows.gravity import reference_gravity
from app.workflows.recordings import quantization_step


@dataclass(frozen=True)
class Session:
    """A wizard session: its protocol (the strategy), the positions it asks for, its captures' summaries in the
    order they were taken, the target (free), the device and what the calibration will say of it.

    ``id`` and ``created_at`` are the store's (None before it stored the session).
    """

    protocol: SessionProtocol
    positions: tuple[str, ...]
    capture_s: float
    unit: str
    gravity: float
    notes: tuple[str, ...] = ()
    device_id: str | None = None
    label: str | None = None
    source: str = "phone"
    target_mg: float | None = None
    id: str | None = None
    created_at: str | None = None
    calibration_id: str | None = None
    captures: tuple[dict, ...] = ()

    @classmethod
    def new(cls, fields: dict) -> Session:
        """A new session from the request's fields (app.api.schemas.sessions.SessionIn, ``target_mg`` filled in)."""
        protocol = SESSION_PROTOCOLS[fields["protocol"]]
        gravity, notes = reference_gravity(
            fields["unit"], fields.get("gravity"), fields.get("latitude_deg"), fields.get("height_m")
        )
        return cls(
            protocol=protocol,
            positions=protocol.positions,
            capture_s=fields["capture_s"],
            unit=fields["unit"],
            gravity=gravity,
            notes=tuple(notes),
            device_id=fields.get("device_id"),
            label=fields.get("label"),
            source=fields.get("source", "phone"),
            target_mg=protocol.target_mg(fields),
        )

    @classmethod
    def from_row(cls, row: dict) -> Session:
        """The session the store returns (``store.get_session``: its body, ``calibration_id`` and ``captures``)."""
        return cls(
            protocol=SESSION_PROTOCOLS[row["protocol"]],
            positions=tuple(row["positions"]),
            capture_s=row["capture_s"],
            unit=row["unit"],
            gravity=row["gravity"],
            notes=tuple(row.get("notes", ())),
            device_id=row.get("device_id"),
            label=row.get("label"),
            source=row.get("source", "phone"),
            target_mg=row.get("target_mg"),
            id=row.get("id"),
            created_at=row.get("created_at"),
            calibration_id=row.get("calibration_id"),
            captures=tuple(row.get("captures", ())),
        )

    def body(self) -> dict:
        """The stored body (``store.add_session``); ``target_mg`` only for a protocol that has one."""
        body = {
            "protocol": self.protocol.name,
            "positions": list(self.positions),
            "capture_s": self.capture_s,
            "unit": self.unit,
            "gravity": self.gravity,
            "notes": list(self.notes),
            "device_id": self.device_id,
            "label": self.label,
            "source": self.source,
        }
        if self.target_mg is not None:
            body["target_mg"] = self.target_mg
        return body

    def row(self) -> dict:
        """The body with what the store adds: ``id``, ``created_at``, ``calibration_id`` and ``captures``."""
        return dict(
            self.body(),
            id=self.id,
            created_at=self.created_at,
            calibration_id=self.calibration_id,
            captures=list(self.captures),
        )

    @property
    def done(self) -> list[str]:
        """The positions captured, in the order they were taken."""
        return [c["position"] for c in self.captures]

    @property
    def means(self) -> list[list[float]]:
        """The captures' mean readings, in the order they were taken."""
        return [c["mean"] for c in self.captures]

    def capture(self, position: str) -> dict:
        """The summary of the capture of ``position``."""
        return next(c for c in self.captures if c["position"] == position)

    def remaining(self) -> list[str]:
        return self.protocol.remaining(self)


def create(store, fields: dict, token_hash: str, *, owner: str | None) -> Session:
    """Store a new session from the request's fields; ``token_hash`` opens it."""
    stored = store.add_session(Session.new(fields).body(), token_hash, owner=owner)
    return Session.from_row(stored)


def load(store, session_id: str) -> Session:
    """The stored session with its captures (NotFoundError when there is none)."""
    return Session.from_row(store.get_session(session_id))


def view(session: Session) -> dict:
    """A session as the API shows it: with the positions that remain, in protocol order, and what its
    protocol adds (free: ``progress``)."""
    return dict(session.row(), remaining=session.remaining(), **session.protocol.progress(session))


def add_capture(store, session: Session, capture: dict) -> tuple[dict, dict]:
    """Check one pose's samples and store them; returns the capture summary and the new session view.

    Raises
    ------
    CalibrationError
        The samples are not a still pose of this protocol (or, in the cube flow, the turn that led
        to it was not the protocol's), or not in the session's unit.
    ConflictError
        The pose is captured already and ``redo`` is false (the message names what remains).
    """
    if capture.get("unit") not in (None, session.unit):
        raise CalibrationError(f"this session takes samples in {session.unit}; got {capture['unit']}")
    summary = session.protocol.check(session, capture)
    acc = np.asarray(capture["acc"], dtype=float)
    summary["quantization_step"] = quantization_step(acc) if session.unit == "m/s^2" else None
    summary["sign"] = capture.get("sign") or {"convention": "w3c", "detected_from": "default"}
    samples = {k: capture.get(k) for k in ("t_ms", "acc", "gyr", "gyr_unit", "motion")}
    try:
        summary = store.add_capture(session.id, summary, samples, replace=bool(capture.get("redo")))
    except ConflictError:
        remaining = ", ".join(session.remaining()) or "none"
        raise ConflictError(
            f"{summary['position']} is already captured; remaining: {remaining}. "
            "Turn the device to a remaining pose, or send redo=true to capture it again"
        ) from None
    assert session.id is not None, "a session read from the store has its id"
    return summary, view(load(store, session.id))


def solve(store, session: Session) -> dict:
    """The calibration of a complete session, as its plain body (its protocol's method: app.guided.protocols).

    Raises
    ------
    InsufficientDataError
        Poses remain to be captured (free: fewer than FREE_FIT_FROM).
    """
    return session.protocol.solve(store, session).body()
