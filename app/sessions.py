"""Guided wizard sessions (issue 6): create, capture a pose, solve — between the API and the store.

A session belongs to whoever holds its token.  Each capture holds the raw samples of one pose
(kept in the store); the server checks them itself (app.calibration.capture) rather than trusting
the page.

- ``six``: poses in any order; solving runs the six-position closed form
  (Georgieva et al. (ESGI'95), section 3.3.1) on the capture means.
- ``cube24``: positions 1–24 in order (docs/methods.md); each capture after the first brings
  the rates of the move that led to it, and the turn is checked at once against the protocol
  (Särkkä et al. (IEEE Sensors J. 2017), VII-A-1, app.calibration.cube.turns); solving joins the moves and
  the still positions into one recording and runs Särkkä et al.'s method on it.
"""

from __future__ import annotations

import numpy as np

from app import workflow
from app.calibration import CANONICAL_SIX, CalibrationError, InsufficientDataError
from app.calibration.errors import NotStillError
from app.calibration.capture import check_still_capture, on_uniform_grid
from app.calibration.cube.protocols import CUBE24_UPS, cube24
from app.store import ConflictError

PROTOCOL_POSITIONS: dict[str, tuple[str, ...]] = {
    "six": CANONICAL_SIX,
    "cube24": tuple(str(k) for k in range(1, len(CUBE24_UPS) + 1)),
}
"""The positions of each protocol the server can guide."""

CAPTURE_S_DEFAULT = 5.0
"""Seconds captured per position unless the session asks for another duration."""

CAPTURE_S_RANGE = (0.5, 30.0)
"""The seconds per position a session accepts (the API's and the wizard page's bounds)."""

CUBE_FACE_MAX_ANGLE_DEG = 45.0
"""The cube may stand on an inclined plane: its up face is the nearest axis within 45° (as Särkkä et al.'s
sequence check, app.calibration.cube.sequence)."""

PAGE_CUBE_FACE_MAX_ANGLE_DEG = 40.0
"""The wizard page captures a cube position only within 40° of a face, inside the server's 45°,
so that what it sends is not refused for the angle."""

MAX_ROTATION_DEG_S = 5.0
"""A still capture whose mean rotation rate exceeds this (°/s) was turning, whatever the
accelerometer says; a phone gyroscope's bias is well below it."""

PAGE_STILL_ENTER_DEG_S = 3.0
PAGE_STILL_LEAVE_DEG_S = MAX_ROTATION_DEG_S
"""The wizard page calls the device still when the mean rotation rate over its window falls below
3 °/s and moving again above the server's 5 °/s (hysteresis, static/js/motion.js)."""

PAGE_STILL_ENTER_STD = 0.1
PAGE_STILL_LEAVE_STD = 0.25
"""The same for the accelerometer, in m/s²: the largest per-axis standard deviation over the
window; the page leaves "still" below the server's limit (app.calibration.capture.STILL_MAX_STD_G,
0.03 g = 0.29 m/s²), so that a capture it completes is still for the server too."""


OS_CALIBRATION_WARNING = (
    "the phone's system may already calibrate what the browser reports (Android and iOS apply their "
    "own accelerometer corrections): this calibration corrects the browser's values, apply it to those"
)


def new_session(fields: dict) -> dict:
    """The stored body of a new session, from the request's fields (app.api.schemas.SessionIn)."""
    protocol = fields["protocol"]
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
        The samples are not a still pose of this protocol (or, in the cube flow, the turn that led
        to it was not the protocol's), or not in the session's unit.
    ConflictError
        The pose is captured already and ``redo`` is false (the message names what remains).
    """
    if capture.get("unit") not in (None, session["unit"]):
        raise CalibrationError(f"this session takes samples in {session['unit']}; got {capture['unit']}")
    if session["protocol"] == "cube24":
        summary = _cube_capture(store, session, capture)
    else:
        summary = _six_capture(session, capture)
    acc = np.asarray(capture["acc"], dtype=float)
    summary["quantization_step"] = workflow.quantization_step(acc) if session["unit"] == "m/s^2" else None
    summary["sign"] = capture.get("sign") or {"convention": "w3c", "detected_from": "default"}
    samples = {k: capture.get(k) for k in ("t_ms", "acc", "gyr", "gyr_unit", "motion")}
    try:
        summary = store.add_capture(session["id"], summary, samples, replace=bool(capture.get("redo")))
    except ConflictError:
        raise ConflictError(
            f"{summary['position']} is already captured; remaining: {_remaining_text(session)}. "
            "Turn the device to a remaining pose, or send redo=true to capture it again"
        ) from None
    return summary, view(store.get_session(session["id"]))


def _gyr_mean_deg_s(capture: dict) -> float:
    rate = np.linalg.norm(np.mean(np.asarray(capture["gyr"], dtype=float), axis=0))
    return float(np.degrees(rate * workflow.GYR_TO_RAD_S[capture.get("gyr_unit", "deg/s")]))


def _six_capture(session: dict, capture: dict) -> dict:
    """A pose of the six-position flow: any order, recognised from the data."""
    if capture.get("position") not in (None, *CANONICAL_SIX):
        raise CalibrationError(f"a six-position pose is one of {', '.join(CANONICAL_SIX)}; got {capture['position']!r}")
    checked = check_still_capture(capture["acc"], capture["t_ms"], gravity=session["gravity"],
                                  expected=capture.get("position"))
    if capture.get("gyr") is not None:
        rate = _gyr_mean_deg_s(capture)
        if rate > MAX_ROTATION_DEG_S:
            raise NotStillError(f"the device was turning during the capture ({rate:.3g} °/s): "
                                   "leave it resting until the capture ends")
    return checked.to_dict()


def _cube_capture(store, session: dict, capture: dict) -> dict:
    """A position of the cube flow: the next one in order, reached by the protocol's turn."""
    from app.calibration.cube.turns import check_turn

    protocol = cube24()
    done = [c["position"] for c in session["captures"]]
    position = str(len(done) + 1)
    if capture.get("redo") and done and capture.get("position") in (None, done[-1]):
        position = done[-1]  # the last position again, reached by the same turn
    elif capture.get("position") not in (None, position):
        raise CalibrationError(f"the cube sequence goes in order: this capture is position {position}"
                               + (", the last one captured can be redone with redo=true" if done else ""))
    if int(position) > len(session["positions"]):
        raise ConflictError(position)
    k = int(position)
    if capture.get("gyr") is None:
        raise CalibrationError("the cube flow needs the gyroscope: send gyr (rotationRate) with every capture")
    checked = check_still_capture(capture["acc"], capture["t_ms"], gravity=session["gravity"],
                                  max_angle_deg=CUBE_FACE_MAX_ANGLE_DEG)
    rate = _gyr_mean_deg_s(capture)
    if rate > MAX_ROTATION_DEG_S:
        raise NotStillError(f"the cube was turning during the capture ({rate:.3g} °/s): "
                               "leave it resting until the capture ends")
    summary = dict(checked.to_dict(), position=position, up=checked.position, expected_up=CUBE24_UPS[k - 1],
                   gyr_mean=np.mean(np.asarray(capture["gyr"], dtype=float), axis=0).tolist(),
                   gyr_unit=capture.get("gyr_unit", "deg/s"))
    declared = workflow.GYR_TO_RAD_S[summary["gyr_unit"]]
    summary["gyr_to_rad_s"] = declared
    if k > 1:
        motion = capture.get("motion")
        if not motion or not motion.get("gyr"):
            raise CalibrationError(f"position {k} needs the move from position {k - 1}: send motion "
                                   "{t_ms, gyr} with the rates recorded since the last capture ended")
        previous = next(c for c in session["captures"] if c["position"] == str(k - 1))
        turn = check_turn(motion["gyr"], motion["t_ms"], protocol, k - 2, bias=previous["gyr_mean"],
                          gyr_scale=declared)
        if not turn.ok:
            raise CalibrationError(turn.message, code="wrong_turn")
        summary["turn"] = turn.to_dict()
        summary["gyr_to_rad_s"] = turn.gyr_scale
    if checked.position != CUBE24_UPS[k - 1]:
        raise CalibrationError(
            f"position {k} should have {CUBE24_UPS[k - 1]} up on a level plane; the accelerometer sees "
            f"{checked.position} up: turn the cube as the picture shows"
        )
    return summary


def solve(store, session: dict) -> dict:
    """The calibration of a complete session, as a calibration body.

    ``six``: the six-position closed form (Georgieva et al. section 3.3.1) of the capture means; ``cube24``:
    Särkkä et al.'s method on the moves and positions joined into one recording.

    Raises
    ------
    InsufficientDataError
        Poses remain to be captured.
    """
    remaining = view(session)["remaining"]
    if remaining:
        raise InsufficientDataError(f"capture {', '.join(remaining)} first: the session has "
                                    f"{len(session['captures'])} of {len(session['positions'])} positions")
    if session["protocol"] == "cube24":
        return _solve_cube(store, session)
    captures = {c["position"]: c for c in session["captures"]}
    readings = [workflow.Reading(mean=tuple(captures[p]["mean"]), up=p, std=tuple(captures[p]["std"]),
                                 count=captures[p]["count"]) for p in session["positions"]]
    result, extra = workflow.calibrate_known("six_position", readings, unit=session["unit"],
                                             gravity=session["gravity"])
    notes = _browser_notes(session)
    rates = [c["sampling_rate_hz"] for c in captures.values()]
    extra = dict(extra, sampling_rate_hz_min=min(rates), sampling_rate_hz_max=max(rates))
    return workflow.calibration_body(
        result, extra, unit=session["unit"], notes=notes, device_id=session.get("device_id"),
        label=session.get("label"), session_id=session["id"],
        captures=[{k: captures[p][k] for k in ("position", "mean", "std", "count", "sampling_rate_hz")}
                  for p in session["positions"]],
    )


def _browser_notes(session: dict) -> list[str]:
    """The warnings a phone's browser calls for: rounding, the system's own calibration, the sign."""
    captures = session["captures"]
    notes = list(session.get("notes", ()))
    steps = {c.get("quantization_step") for c in captures} - {None}
    if steps:
        notes.append(f"the browser rounds its sensor values to {max(steps):g} m/s²: each position's mean "
                     "averages many samples, so it is still finer than the rounding")
    notes.append(OS_CALIBRATION_WARNING)
    ios = sorted({c["sign"]["detected_from"] for c in captures if c.get("sign", {}).get("convention") == "ios"})
    if ios:
        notes.append(f"the browser reported the iOS sign convention (detected from {', '.join(ios)}); "
                     "the samples were flipped to the W3C convention before fitting")
    return notes


def joined_recording(store, session: dict) -> tuple[np.ndarray, np.ndarray, float]:
    """The cube session as one recording: each move, then its still position, on a uniform grid.

    Returns accelerometer samples (session unit), gyroscope samples in rad/s and the rate in Hz
    (the median event interval's).
    """
    t, acc, gyr = [], [], []
    for c in session["captures"]:
        samples = store.get_capture_samples(session["id"], c["position"])
        parts = [samples["motion"]] if samples.get("motion") else []
        for part in parts + [samples]:
            if not part.get("acc") or len(part["acc"]) != len(part["t_ms"]):
                continue  # a move sent without accelerometer samples: the still parts bound it
            t.append(np.asarray(part["t_ms"], dtype=float))
            acc.append(np.asarray(part["acc"], dtype=float))
            gyr.append(np.asarray(part["gyr"], dtype=float) * c["gyr_to_rad_s"])
    t_all = np.concatenate(t)
    order = np.argsort(t_all, kind="stable")
    (acc_grid, gyr_grid), h_ms = on_uniform_grid(t_all[order], np.vstack(acc)[order], np.vstack(gyr)[order])
    return acc_grid, gyr_grid, 1000.0 / h_ms


def _solve_cube(store, session: dict) -> dict:
    """Särkkä et al.'s method on the joined cube session."""
    from app.calibration.cube import calibrate_cube  # scipy.stats: imported when needed

    acc, gyr, rate = joined_recording(store, session)
    result = calibrate_cube(acc, gyr, None, sampling_rate_hz=rate, protocol="cube24", gravity=session["gravity"])
    return workflow.calibration_body(
        result, {}, unit=session["unit"], notes=_browser_notes(session), device_id=session.get("device_id"),
        label=session.get("label"), session_id=session["id"], units={"acc": session["unit"], "gyr": "rad/s"},
        captures=[{k: c[k] for k in ("position", "up", "mean", "std", "count", "sampling_rate_hz")}
                  for c in session["captures"]],
    )
