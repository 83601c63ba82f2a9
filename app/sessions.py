"""Guided wizard sessions (issue 6): create, capture a pose, solve — between the API and the store.

A session belongs to whoever holds its token.  Each capture holds the raw samples of one pose
(kept in the store); the server checks them itself (app.calibration.capture) rather than trusting
the page.

- ``six``: poses in any order; solving runs the six-position closed form
  (Georgieva et al. (ESGI'95), section 3.3.1) on the capture means.

The six and free flows keep each capture's gyroscope mean, std and count when it was sent; their calibration
carries the gyroscope's bias over the still captures (``gyroscope_bias``, app.calibration.gyro_bias).
- ``free``: still poses in any direction, no jig (issue 11): each must point at least
  :data:`FREE_MIN_ANGLE_DEG` from every earlier one; from :data:`FREE_FIT_FROM` poses on, the
  triangular model of Farago, Maczak and Gingl, IEEE Access is fitted to the capture means after each
  capture, and the session reports its cross-validated error (app.calibration.cross_validation) and
  the D-optimal next poses (app.calibration.advice); the target is reached when that error is below
  the session's ``target_mg`` with at least :data:`FREE_TARGET_MIN_POSES` poses.
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
from app.calibration.advice import farthest_directions
from app.calibration.capture import check_new_direction, check_still_capture, on_uniform_grid
from app.calibration.cube.protocols import CUBE24_UPS, cube24
from app.calibration.gyro_bias import gyroscope_bias
from app.capture_rules import (CUBE_FACE_MAX_ANGLE_DEG, FREE_FIT_FROM, FREE_MAX_ANGLE_DEG, FREE_MIN_ANGLE_DEG, MAX_ROTATION_DEG_S,
                               FREE_TARGET_MIN_POSES)
from app.store import ConflictError

PROTOCOL_POSITIONS: dict[str, tuple[str, ...]] = {
    "six": CANONICAL_SIX,
    "free": (),  # any number of poses, numbered as they come
    "cube24": tuple(str(k) for k in range(1, len(CUBE24_UPS) + 1)),
}
"""The positions of each protocol the server can guide."""


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
        "source": fields.get("source", "phone"),
        # free: the cross-validated error that ends it (the API fills in TRICAL_FREE_TARGET_MG)
        **({"target_mg": fields["target_mg"]} if protocol == "free" else {}),
    }


def view(session: dict) -> dict:
    """A session as the API shows it: with the positions that remain, in protocol order, and for
    the free flow its ``progress``."""
    shown = dict(session, remaining=_remaining(session))
    if session["protocol"] == "free":
        shown["progress"] = free_progress(session)[0]
    return shown


def _remaining(session: dict) -> list[str]:
    done = {c["position"] for c in session["captures"]}
    return [p for p in session["positions"] if p not in done]


def _remaining_text(session: dict) -> str:
    remaining = _remaining(session)
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
    elif session["protocol"] == "free":
        summary = _free_capture(session, capture)
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


def _check_not_turning(capture: dict, what: str = "device") -> None:
    """Refuse a capture whose gyroscope, when sent, shows the device turning."""
    if capture.get("gyr") is None:
        return
    rate = _gyr_mean_deg_s(capture)
    if rate > MAX_ROTATION_DEG_S:
        raise NotStillError(f"the {what} was turning during the capture ({rate:.3g} °/s): "
                            "leave it resting until the capture ends")


def _gyr_summary(capture: dict) -> dict:
    """A still capture's gyroscope, as the session keeps it for the bias (app.calibration.gyro_bias): the mean,
    the standard deviation (ddof 1) and the count of its samples, in the unit they came in; empty without them."""
    if capture.get("gyr") is None:
        return {}
    gyr = np.asarray(capture["gyr"], dtype=float).reshape(-1, 3)
    return {"gyr_mean": gyr.mean(axis=0).tolist(), "gyr_std": gyr.std(axis=0, ddof=1).tolist(),
            "gyr_count": len(gyr), "gyr_unit": capture.get("gyr_unit", "deg/s")}


def session_gyroscope_bias(session: dict) -> dict | None:
    """The gyroscope bias over a session's still captures that carried gyroscope samples, in rad/s with its 95 %
    interval (app.calibration.gyro_bias); None when none did (or they were stored before captures kept it)."""
    captures = [c for c in session["captures"] if c.get("gyr_std") is not None]
    if not captures:
        return None
    scale = np.array([workflow.GYR_TO_RAD_S[c["gyr_unit"]] for c in captures])[:, None]
    return gyroscope_bias(np.array([c["gyr_mean"] for c in captures]) * scale,
                          np.array([c["gyr_std"] for c in captures]) * scale, [c["gyr_count"] for c in captures])


def _six_capture(session: dict, capture: dict) -> dict:
    """A pose of the six-position flow: any order, recognised from the data."""
    if capture.get("position") not in (None, *CANONICAL_SIX):
        raise CalibrationError(f"a six-position pose is one of {', '.join(CANONICAL_SIX)}; got {capture['position']!r}")
    checked = check_still_capture(capture["acc"], capture["t_ms"], gravity=session["gravity"],
                                  expected=capture.get("position"))
    _check_not_turning(capture)
    return dict(checked.to_dict(), **_gyr_summary(capture))


def _free_capture(session: dict, capture: dict) -> dict:
    """A pose of the free flow: any direction at least FREE_MIN_ANGLE_DEG from the earlier ones,
    numbered in order (``position`` "1", "2", …, ``up`` its nearest axis)."""
    position = str(len(session["captures"]) + 1)
    if capture.get("position") not in (None, position):
        raise CalibrationError(f"free poses are numbered in order: this capture is pose {position}; "
                               "leave `position` out")
    checked = check_still_capture(capture["acc"], capture["t_ms"], gravity=session["gravity"],
                                  max_angle_deg=FREE_MAX_ANGLE_DEG)
    _check_not_turning(capture)
    check_new_direction(checked.mean, [c["mean"] for c in session["captures"]], min_angle_deg=FREE_MIN_ANGLE_DEG)
    return dict(checked.to_dict(), position=position, up=checked.position, **_gyr_summary(capture))


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
    _check_not_turning(capture, "cube")
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


def free_progress(session: dict) -> tuple[dict, tuple | None]:
    """Where a free session stands: its cross-validated error, the advice and whether the target is
    reached; and the triangular fit with its extra metrics (None before FREE_FIT_FROM poses).

    Returns
    -------
    progress : dict
        ``count``, ``fit_from``, ``target_poses``, ``target_mg``, ``cv_error_mg``, ``cv_error_max_mg``,
        ``target_reached``, ``advice`` (app.calibration.advice: D-optimal once fitted, else the
        directions farthest from the poses taken) and ``message``.
    fit : (TriangularCalibration, dict) or None
    """
    means = [c["mean"] for c in session["captures"]]
    n, target = len(means), session["target_mg"]
    fit, cv, cv_max = None, None, None
    if n >= FREE_FIT_FROM:
        try:
            fit = workflow.calibrate_unknown("triangular", means, unit=session["unit"], gravity=session["gravity"])
        except CalibrationError:
            fit = None  # poses that do not determine the model yet: the advice spreads them out
        else:
            cv, cv_max = fit[0].metrics.get("cv_error_mg"), fit[0].metrics.get("cv_error_max_mg")
    # The target is an error on new orientations below target_mg from a fit that passes every gate.
    reached = cv is not None and n >= FREE_TARGET_MIN_POSES and cv < target and fit[0].ok
    if fit is not None:
        advice = workflow.pose_advice(fit[0])
    else:
        advice = [a.to_dict() for a in farthest_directions(np.asarray(means, dtype=float).reshape(-1, 3))]
    if reached:
        message = f"target reached: {cv:.1f} mg on new orientations with {n} poses"
    elif cv is None:
        more = FREE_FIT_FROM - n
        message = (f"{n} poses captured: {more} more before the first estimate" if more > 0
                   else f"{n} poses captured: no estimate for new orientations yet; add poses in other directions")
    else:
        need = f", at least {FREE_TARGET_MIN_POSES} poses" if n < FREE_TARGET_MIN_POSES else ""
        message = f"{n} poses: {cv:.1f} mg expected on new orientations (target {target:g} mg{need})"
    progress = {"count": n, "fit_from": FREE_FIT_FROM, "target_poses": FREE_TARGET_MIN_POSES, "target_mg": target,
                "cv_error_mg": cv, "cv_error_max_mg": cv_max, "target_reached": reached, "advice": advice,
                "message": message}
    return progress, fit


def _solve_free(session: dict) -> dict:
    """The triangular fit of a free session's capture means, with how the session ended."""
    progress, fit = free_progress(session)
    n = progress["count"]
    if fit is None and n >= FREE_FIT_FROM:  # the fit itself refuses: its error says why
        workflow.calibrate_unknown("triangular", [c["mean"] for c in session["captures"]], unit=session["unit"],
                                   gravity=session["gravity"])
    if fit is None:
        raise InsufficientDataError(f"capture {FREE_FIT_FROM - n} more poses first: a free session solves from "
                                    f"{FREE_FIT_FROM} poses (it has {n}); the target needs {FREE_TARGET_MIN_POSES}")
    result, extra = fit
    cv, target = progress["cv_error_mg"], progress["target_mg"]
    if progress["target_reached"]:
        reason, text = "target", f"target reached: {cv:.1f} mg on new orientations"
    else:
        expected = "no figure for new orientations" if cv is None else f"{cv:.1f} mg expected on new orientations"
        reason, text = "stopped", f"stopped at {n} poses: {expected}, target {target:g} mg"
    finish = {"reason": reason, "text": text, "poses": n, "cv_error_mg": cv, "target_mg": target}
    return _session_body(session, result, extra, advice=progress["advice"], finish=finish,
                         captures=[{k: c[k] for k in ("position", "up", "mean", "std", "count", "sampling_rate_hz")}
                                   for c in session["captures"]])


def _session_body(session: dict, result, extra: dict, **fields) -> dict:
    """The calibration body of a solved session: the browser's notes, the capture rates, its owner's fields."""
    rates = [c["sampling_rate_hz"] for c in session["captures"]]
    extra = dict(extra, sampling_rate_hz_min=min(rates), sampling_rate_hz_max=max(rates))
    bias = session_gyroscope_bias(session)
    if bias is not None:
        fields["gyroscope_bias"] = bias
    return workflow.calibration_body(
        result, extra, unit=session["unit"], notes=_browser_notes(session), device_id=session.get("device_id"),
        label=session.get("label"), session_id=session["id"], **fields)


def solve(store, session: dict) -> dict:
    """The calibration of a complete session, as a calibration body.

    ``six``: the six-position closed form (Georgieva et al. section 3.3.1) of the capture means; ``cube24``:
    Särkkä et al.'s method on the moves and positions joined into one recording; ``free``: the triangular
    model of Farago et al. on the capture means, with ``finish`` saying whether the target was reached.

    Raises
    ------
    InsufficientDataError
        Poses remain to be captured (free: fewer than FREE_FIT_FROM).
    """
    if session["protocol"] == "free":
        return _solve_free(session)
    remaining = _remaining(session)
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
    return _session_body(
        session, result, extra,
        captures=[{k: captures[p][k] for k in ("position", "mean", "std", "count", "sampling_rate_hz")}
                  for p in session["positions"]],
    )


def _browser_notes(session: dict) -> list[str]:
    """The warnings a phone's browser calls for: rounding, the system's own calibration, the sign; a
    board's printed lines (``source`` ``board``) call for none of them."""
    captures = session["captures"]
    notes = list(session.get("notes", ()))
    if session.get("source") == "board":
        return notes
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
