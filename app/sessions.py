"""Guided wizard sessions (issue 6): create, capture a pose, solve — between the API and the store.

A session belongs to whoever holds its token.  Each capture holds the raw samples of one pose
(kept in the store); the server checks them itself (app.calibration.capture) rather than trusting
the page.  Solving runs the six-position closed form (000_cb2cbc1c5eaccf1a.txt, section 3.3.1)
on the capture means, with the warnings a phone's browser calls for.
"""

from __future__ import annotations

import math

import numpy as np

from app import workflow
from app.calibration import CANONICAL_SIX, CalibrationError, InsufficientDataError
from app.calibration.capture import check_still_capture
from app.store import ConflictError

PROTOCOL_POSITIONS: dict[str, tuple[str, ...]] = {"six": CANONICAL_SIX}
"""The positions of each protocol the server can guide."""

MAX_ROTATION_DEG_S = 5.0
"""A still capture whose mean rotation rate exceeds this (°/s) was turning, whatever the
accelerometer says; a phone gyroscope's bias is well below it."""

GYR_TO_DEG_S = {"deg/s": 1.0, "rad/s": 180.0 / math.pi}

OS_CALIBRATION_WARNING = (
    "the phone's system may already calibrate what the browser reports (Android and iOS apply their "
    "own accelerometer corrections): this calibration corrects the browser's values, apply it to those"
)


def new_session(fields: dict) -> dict:
    """The stored body of a new session, from the request's fields (app.api.schemas.SessionIn)."""
    protocol = fields["protocol"]
    if protocol not in PROTOCOL_POSITIONS:
        raise CalibrationError(
            f"the guided {protocol} flow is not available on this server yet: record the cube sequence "
            "(DESIGN.md section 4) and upload it to POST /api/v1/recordings, then use method `cube`"
        )
    gravity, notes = workflow.reference_gravity(fields["unit"], fields.get("gravity"), fields.get("latitude_deg"),
                                                fields.get("height_m"))
    return {
        "protocol": protocol,
        "positions": list(PROTOCOL_POSITIONS[protocol]),
        "capture_s": fields["capture_s"],
        "unit": fields["unit"],
        "gravity": gravity,
        "notes": notes,
        "device_id": fields.get("device_id"),
        "label": fields.get("label"),
    }


def view(session: dict) -> dict:
    """A session as the API shows it: with the positions that remain, in protocol order."""
    done = {c["position"] for c in session["captures"]}
    return dict(session, remaining=[p for p in session["positions"] if p not in done])


def _remaining_text(session: dict) -> str:
    remaining = view(session)["remaining"]
    return ", ".join(remaining) if remaining else "none"


def add_capture(store, session: dict, capture: dict) -> tuple[dict, dict]:
    """Check one pose's samples and store them; returns the capture summary and the new session view.

    Raises
    ------
    CalibrationError
        The samples are not a still pose of this protocol, or not in the session's unit.
    ConflictError
        The pose is captured already and ``redo`` is false (the message names what remains).
    """
    if capture.get("unit") not in (None, session["unit"]):
        raise CalibrationError(f"this session takes samples in {session['unit']}; got {capture['unit']}")
    checked = check_still_capture(capture["acc"], capture["t_ms"], gravity=session["gravity"],
                                  expected=capture.get("position"))
    if capture.get("gyr") is not None:
        rate = np.linalg.norm(np.mean(np.asarray(capture["gyr"], dtype=float), axis=0))
        rate *= GYR_TO_DEG_S[capture.get("gyr_unit", "deg/s")]
        if rate > MAX_ROTATION_DEG_S:
            raise CalibrationError(f"the device was turning during the capture ({rate:.3g} °/s): "
                                   "leave it resting until the capture ends")
    summary = checked.to_dict()
    acc = np.asarray(capture["acc"], dtype=float)
    summary["quantization_step"] = workflow.quantization_step(acc) if session["unit"] == "m/s^2" else None
    summary["sign"] = capture.get("sign") or {"convention": "w3c", "detected_from": "default"}
    if checked.position not in session["positions"]:  # pragma: no cover - six covers every axis
        raise CalibrationError(f"{checked.position} is not a position of the {session['protocol']} protocol")
    try:
        summary = store.add_capture(session["id"], summary, {k: capture.get(k) for k in ("t_ms", "acc", "gyr", "gyr_unit")},
                                    replace=bool(capture.get("redo")))
    except ConflictError:
        raise ConflictError(
            f"{checked.position} is already captured; remaining: {_remaining_text(session)}. "
            "Turn the device to a remaining pose, or send redo=true to capture it again"
        ) from None
    return summary, view(store.get_session(session["id"]))


def solve(session: dict) -> dict:
    """The six-position calibration of a complete session (000 section 3.3.1), as a calibration body.

    Raises
    ------
    InsufficientDataError
        Poses remain to be captured.
    """
    remaining = view(session)["remaining"]
    if remaining:
        raise InsufficientDataError(f"capture {', '.join(remaining)} first: the session has "
                                    f"{len(session['captures'])} of {len(session['positions'])} positions")
    captures = {c["position"]: c for c in session["captures"]}
    readings = [workflow.Reading(mean=tuple(captures[p]["mean"]), up=p, std=tuple(captures[p]["std"]),
                                 count=captures[p]["count"]) for p in session["positions"]]
    result, extra = workflow.calibrate_known("six_position", readings, unit=session["unit"],
                                             gravity=session["gravity"])
    notes = list(session.get("notes", ()))
    steps = {c.get("quantization_step") for c in captures.values()} - {None}
    if steps:
        notes.append(f"the browser rounds its sensor values to {max(steps):g} m/s²: each position's mean "
                     "averages many samples, so it is still finer than the rounding")
    notes.append(OS_CALIBRATION_WARNING)
    ios = sorted({c["sign"]["detected_from"] for c in captures.values() if c.get("sign", {}).get("convention") == "ios"})
    if ios:
        notes.append(f"the browser reported the iOS sign convention (detected from {', '.join(ios)}); "
                     "the samples were flipped to the W3C convention before fitting")
    rates = [c["sampling_rate_hz"] for c in captures.values()]
    extra = dict(extra, sampling_rate_hz_min=min(rates), sampling_rate_hz_max=max(rates))
    return workflow.calibration_body(
        result, extra, unit=session["unit"], notes=notes, device_id=session.get("device_id"),
        label=session.get("label"), session_id=session["id"],
        captures=[{k: captures[p][k] for k in ("position", "mean", "std", "count", "sampling_rate_hz")}
                  for p in session["positions"]],
    )
