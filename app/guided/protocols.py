"""The capture protocols, one strategy each: what a protocol asks for next, how it checks a capture, when
it may be solved and how it solves — for the wizard's sessions (app.guided.sessions, the page's flows
static/js/flow_six.js, flow_free.js, flow_cube.js) and for ``trical capture`` (app.cli.board), which
captures the same poses from a board's lines.

- ``six``: the six poses in any order, each recognised from the data; solved by the six-position closed
  form (Georgieva et al., ESGI'95, section 3.3.1) on the capture means.
- ``free``: still poses in any direction, no jig (issue 11): each at least :data:`FREE_MIN_ANGLE_DEG` from
  every earlier one; from :data:`FREE_FIT_FROM` poses on, the triangular model of Farago, Maczak and Gingl,
  IEEE Access is fitted to the capture means after each capture, and the session reports its cross-validated
  error (app.calibration.still.cross_validation) and the D-optimal next poses (app.calibration.still.advice); the target
  is reached when that error is below the session's ``target_mg`` with at least :data:`FREE_TARGET_MIN_POSES`
  poses.
- ``cube24``: positions 1–24 in order (docs/methods.md); each capture after the first brings the rates of
  the move that led to it, and the turn is checked at once against the protocol (Särkkä et al., IEEE
  Sensors Journal 17(11) 2017, section VII-A-1, app.calibration.cube.turns); solving joins the moves and
  the still positions into one recording and runs Särkkä et al.'s method on it.
- ``compass`` and ``noise``: the terminal only (the page has their own pages, without a session): the
  board turned through every direction, or left resting, for a given time.

The six and free flows keep each capture's gyroscope mean, std and count when it was sent; their
calibration carries the gyroscope's bias over the still captures (``gyroscope_bias``,
app.calibration.still.gyro_bias).

A new protocol is one class here, its entry in :data:`BOARD_PROTOCOLS` (``trical capture``) and, for the
page's wizard, its name and page in app.guided.capture_rules.WIZARD_PROTOCOLS (a session's: ``session=True``,
and its strategy in :data:`SESSION_PROTOCOLS`'s).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from app.calibration import CANONICAL_SIX, CalibrationError, InsufficientDataError
from app.calibration.cube.protocols import CUBE24_UPS, cube24
from app.calibration.shared.capture import PoseTooCloseError, check_new_direction, check_still_capture, on_uniform_grid
from app.calibration.shared.errors import NotStillError
from app.calibration.shared.orientations import nearest_orientation
from app.calibration.still.advice import farthest_directions
from app.calibration.still.gyro_bias import gyroscope_bias
from app.guided.capture_rules import (
    CAPTURE_PROTOCOLS,
    CUBE_FACE_MAX_ANGLE_DEG,
    FREE_FIT_FROM,
    FREE_MAX_ANGLE_DEG,
    FREE_MIN_ANGLE_DEG,
    FREE_TARGET_MIN_POSES,
    MAX_ROTATION_DEG_S,
    SESSION_PROTOCOL_NAMES,
    SIX_ASKED_ORDER,
)
from app.io.log import GYR_TO_RAD_S
from app.store import ConflictError
from app.workflows.calibration import Calibration
from app.workflows.results import pose_advice
from app.workflows.still import SIX_POSITION, Reading, calibrate_known, calibrate_unknown

if TYPE_CHECKING:
    from app.guided.sessions import Session

OS_CALIBRATION_WARNING = (
    "the phone's system may already calibrate what the browser reports (Android and iOS apply their "
    "own accelerometer corrections): this calibration corrects the browser's values, apply it to those"
)

CAPTURE_FIELDS = ("position", "up", "mean", "std", "count", "sampling_rate_hz")
"""What a solved session's calibration lists of each capture."""


class Protocol:
    """What every protocol tells ``trical capture`` (app.cli.board): the still captures it asks for
    (``poses``; None records for ``minutes`` instead), which capture a still pose would be (:meth:`label`),
    the words that ask for them, and the command and method that calibrate the log at the end."""

    name: str = ""
    words: str = ""
    """What the terminal asks the person to do."""
    poses: int | None = None
    """Still captures the terminal asks for; None: it records for ``minutes``."""
    minutes: float = 1.0
    """A posed protocol stops (refused) after this long; the others record this long."""
    command: str = "calibrate"
    """The ``trical`` command that finishes the log."""
    method: str = "auto"
    """The method the log is calibrated with at the end."""
    from_captures: bool = False
    """The log is calibrated from the captures' own rows (app.cli.board.capture_segments), as a wizard
    session is, rather than from still segments found again in the log."""

    def label(self, mean: np.ndarray, done: list, max_angle_deg: float) -> str | None:
        """The capture a still mean reading would be, given those ``done`` (label, unit direction); None when
        it is none the protocol asks for."""
        return None


class SessionProtocol(Protocol):
    """A protocol the wizard's sessions follow (app.guided.sessions): what it asks for next, how it checks a capture,
    when it may be solved and how."""

    positions: tuple[str, ...] = ()
    """The positions a session asks for, in order (free: none fixed, numbered as they come)."""

    def target_mg(self, fields: dict) -> float | None:
        """The error that ends a session of this protocol (None: it ends when no position remains)."""
        return None

    def remaining(self, session: Session) -> list[str]:
        """The positions still to capture, in protocol order."""
        done = set(session.done)
        return [p for p in self.positions if p not in done]

    def next_position(self, session: Session) -> str | None:
        """The position the next capture is asked for (None: none remains)."""
        remaining = self.remaining(session)
        return remaining[0] if remaining else None

    def progress(self, session: Session) -> dict:
        """What the session's view adds for this protocol."""
        return {}

    def check(self, session: Session, capture: dict) -> dict:
        """Check one capture's samples (the API's ``CaptureIn``) and return its summary as the store keeps it.

        Raises
        ------
        CalibrationError
            The samples are not a still pose this protocol asks for now.
        """
        raise NotImplementedError

    def solvable(self, session: Session) -> bool:
        """Whether the session has what solving it needs."""
        return not self.remaining(session)

    def unsolvable(self, session: Session) -> str:
        """What to capture before the session can be solved."""
        return (
            f"capture {', '.join(self.remaining(session))} first: the session has "
            f"{len(session.captures)} of {len(self.positions)} positions"
        )

    def solve(self, store, session: Session) -> Calibration:
        """The calibration body of the session.

        Raises
        ------
        InsufficientDataError
            The session is not :meth:`solvable` yet.
        """
        if not self.solvable(session):
            raise InsufficientDataError(self.unsolvable(session))
        return self._solve(store, session)

    def _solve(self, store, session: Session) -> Calibration:
        raise NotImplementedError


class SixProtocol(SessionProtocol):
    """The six poses, in any order, each recognised from the data."""

    name = "six"
    positions = CANONICAL_SIX
    poses = len(CANONICAL_SIX)
    minutes = 10.0
    from_captures = True
    words = (
        "rest the board on each of its six sides in turn (+x, -x, +y, -y, +z, -z up: the axis printed on "
        "the board pointing up; +z up is the component side up), still, until the bell"
    )
    asked_order = SIX_ASKED_ORDER

    def next_position(self, session):
        remaining = self.remaining(session)
        return next((p for p in self.asked_order if p in remaining), None)

    def label(self, mean, done, max_angle_deg):
        label = nearest_orientation(mean, max_angle_deg)
        return label if label and label not in [d[0] for d in done] else None

    def check(self, session, capture):
        if capture.get("position") not in (None, *self.positions):
            raise CalibrationError(
                f"a six-position pose is one of {', '.join(self.positions)}; got {capture['position']!r}"
            )
        checked = check_still_capture(
            capture["acc"], capture["t_ms"], gravity=session.gravity, expected=capture.get("position")
        )
        check_not_turning(capture)
        return dict(checked.to_dict(), **gyr_summary(capture))

    def _solve(self, store, session):
        captures = [session.capture(p) for p in self.positions]
        readings = [
            Reading(mean=tuple(c["mean"]), up=c["position"], std=tuple(c["std"]), count=c["count"]) for c in captures
        ]
        result, extra = calibrate_known(SIX_POSITION, readings, unit=session.unit, gravity=session.gravity)
        return session_body(
            session, result, extra, captures=[{k: c[k] for k in CAPTURE_FIELDS if k != "up"} for c in captures]
        )


class FreeProtocol(SessionProtocol):
    """Still poses in any direction, each far enough from the others, until the target or the person stops."""

    name = "free"
    poses = FREE_TARGET_MIN_POSES
    minutes = 10.0
    from_captures = True
    words = f"rest the board still in {FREE_TARGET_MIN_POSES} different poses, at least {FREE_MIN_ANGLE_DEG:g}° apart"

    def label(self, mean, done, max_angle_deg):
        try:
            check_new_direction(mean, [d for _, d in done], min_angle_deg=FREE_MIN_ANGLE_DEG)
        except PoseTooCloseError:
            return None
        return f"pose {len(done) + 1}"

    def target_mg(self, fields):
        return fields["target_mg"]

    def next_position(self, session):
        return str(len(session.captures) + 1)

    def progress(self, session):
        return {"progress": self.progress_and_fit(session)[0]}

    def check(self, session, capture):
        position = self.next_position(session)
        if capture.get("position") not in (None, position):
            raise CalibrationError(
                f"free poses are numbered in order: this capture is pose {position}; leave `position` out"
            )
        checked = check_still_capture(
            capture["acc"], capture["t_ms"], gravity=session.gravity, max_angle_deg=FREE_MAX_ANGLE_DEG
        )
        check_not_turning(capture)
        check_new_direction(checked.mean, session.means, min_angle_deg=FREE_MIN_ANGLE_DEG)
        return dict(checked.to_dict(), position=position, up=checked.position, **gyr_summary(capture))

    def solvable(self, session):
        return len(session.captures) >= FREE_FIT_FROM

    def unsolvable(self, session):
        n = len(session.captures)
        return (
            f"capture {FREE_FIT_FROM - n} more poses first: a free session solves from {FREE_FIT_FROM} poses "
            f"(it has {n}); the target needs {FREE_TARGET_MIN_POSES}"
        )

    @staticmethod
    def fit(session: Session) -> tuple:
        """The triangular model of Farago et al. on the capture means, with its extra metrics."""
        return calibrate_unknown("triangular", session.means, unit=session.unit, gravity=session.gravity)

    def progress_and_fit(self, session: Session) -> tuple[dict, tuple | None]:
        """Where a free session stands: its cross-validated error, the advice and whether the target is
        reached; and the triangular fit with its extra metrics (None before FREE_FIT_FROM poses).

        Returns
        -------
        progress : dict
            ``count``, ``fit_from``, ``target_poses``, ``target_mg``, ``cv_error_mg``, ``cv_error_max_mg``,
            ``target_reached``, ``advice`` (app.calibration.still.advice: D-optimal once fitted, else the
            directions farthest from the poses taken) and ``message``.
        fit : (TriangularCalibration, dict) or None
        """
        n, target = len(session.captures), session.target_mg
        fit, cv, cv_max = None, None, None
        if self.solvable(session):
            try:
                fit = self.fit(session)
            except CalibrationError:
                fit = None  # poses that do not determine the model yet: the advice spreads them out
            else:
                cv, cv_max = fit[0].error_on_new_orientations, fit[0].largest_error_on_new_orientations
        # The target is an error on new orientations below target_mg from a fit that passes every gate.
        reached = cv is not None and n >= FREE_TARGET_MIN_POSES and cv < target and fit is not None and fit[0].ok
        if fit is not None:
            advice = pose_advice(fit[0])
        else:
            advice = [a.to_dict() for a in farthest_directions(np.asarray(session.means, dtype=float).reshape(-1, 3))]
        if reached:
            message = f"target reached: {cv:.1f} mg on new orientations with {n} poses"
        elif cv is None:
            more = FREE_FIT_FROM - n
            message = (
                f"{n} poses captured: {more} more before the first estimate"
                if more > 0
                else f"{n} poses captured: no estimate for new orientations yet; add poses in other directions"
            )
        else:
            need = f", at least {FREE_TARGET_MIN_POSES} poses" if n < FREE_TARGET_MIN_POSES else ""
            message = f"{n} poses: {cv:.1f} mg expected on new orientations (target {target:g} mg{need})"
        progress = {
            "count": n,
            "fit_from": FREE_FIT_FROM,
            "target_poses": FREE_TARGET_MIN_POSES,
            "target_mg": target,
            "cv_error_mg": cv,
            "cv_error_max_mg": cv_max,
            "target_reached": reached,
            "advice": advice,
            "message": message,
        }
        return progress, fit

    def _solve(self, store, session):
        """The triangular fit of the capture means, with how the session ended."""
        progress, fit = self.progress_and_fit(session)
        result, extra = fit if fit is not None else self.fit(session)  # the fit itself refuses: its error says why
        n, target = progress["count"], progress["target_mg"]
        cv = result.error_on_new_orientations if fit is not None else None  # the progress's figure
        if progress["target_reached"]:
            reason, text = "target", f"target reached: {cv:.1f} mg on new orientations"
        else:
            expected = "no figure for new orientations" if cv is None else f"{cv:.1f} mg expected on new orientations"
            reason, text = "stopped", f"stopped at {n} poses: {expected}, target {target:g} mg"
        finish = {"reason": reason, "text": text, "poses": n, "cv_error_mg": cv, "target_mg": target}
        return session_body(
            session,
            result,
            extra,
            advice=progress["advice"],
            finish=finish,
            captures=[{k: c[k] for k in CAPTURE_FIELDS} for c in session.captures],
        )


class Cube24Protocol(SessionProtocol):
    """Särkkä et al.'s 24 cube positions in order, each reached by the protocol's turn."""

    name = "cube24"
    positions = tuple(str(k) for k in range(1, len(CUBE24_UPS) + 1))
    poses = len(CUBE24_UPS)
    minutes = 15.0
    method = "cube"
    words = "turn the board (in its cube) through the 24 positions, resting each until the bell"

    def label(self, mean, done, max_angle_deg):
        return f"position {len(done) + 1}"  # a turn between positions (the gyroscope sees it)

    def check(self, session, capture):
        from app.calibration.cube.turns import check_turn

        done = session.done
        position = str(len(done) + 1)
        if capture.get("redo") and done and capture.get("position") in (None, done[-1]):
            position = done[-1]  # the last position again, reached by the same turn
        elif capture.get("position") not in (None, position):
            raise CalibrationError(
                f"the cube sequence goes in order: this capture is position {position}"
                + (", the last one captured can be redone with redo=true" if done else "")
            )
        if int(position) > len(self.positions):
            raise ConflictError(position)
        k = int(position)
        if capture.get("gyr") is None:
            raise CalibrationError("the cube flow needs the gyroscope: send gyr (rotationRate) with every capture")
        checked = check_still_capture(
            capture["acc"], capture["t_ms"], gravity=session.gravity, max_angle_deg=CUBE_FACE_MAX_ANGLE_DEG
        )
        check_not_turning(capture, "cube")
        summary = dict(
            checked.to_dict(),
            position=position,
            up=checked.position,
            expected_up=CUBE24_UPS[k - 1],
            gyr_mean=np.mean(np.asarray(capture["gyr"], dtype=float), axis=0).tolist(),
            gyr_unit=capture.get("gyr_unit", "deg/s"),
        )
        declared = GYR_TO_RAD_S[summary["gyr_unit"]]
        summary["gyr_to_rad_s"] = declared
        if k > 1:
            motion = capture.get("motion")
            if not motion or not motion.get("gyr"):
                raise CalibrationError(
                    f"position {k} needs the move from position {k - 1}: send motion "
                    "{t_ms, gyr} with the rates recorded since the last capture ended"
                )
            turn = check_turn(
                motion["gyr"],
                motion["t_ms"],
                cube24(),
                k - 2,
                bias=session.capture(str(k - 1))["gyr_mean"],
                gyr_scale=declared,
            )
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

    @staticmethod
    def recording(store, session: Session) -> tuple[np.ndarray, np.ndarray, float]:
        """The session as one recording: each move, then its still position, on a uniform grid.

        Returns accelerometer samples (session unit), gyroscope samples in rad/s and the rate in Hz
        (the median event interval's).
        """
        t, acc, gyr = [], [], []
        for c in session.captures:
            samples = store.get_capture_samples(session.id, c["position"])
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

    def _solve(self, store, session):
        """Särkkä et al.'s method on the joined session."""
        from app.calibration.cube import calibrate_cube  # scipy.stats: imported when needed

        acc, gyr, rate = self.recording(store, session)
        result = calibrate_cube(acc, gyr, None, sampling_rate_hz=rate, protocol=self.name, gravity=session.gravity)
        return Calibration.of(
            result,
            {},
            unit=session.unit,
            notes=browser_notes(session),
            device_id=session.device_id,
            label=session.label,
            session_id=session.id,
            source=session.source,
            units={"acc": session.unit, "gyr": "rad/s"},
            captures=[{k: c[k] for k in CAPTURE_FIELDS} for c in session.captures],
        )


class CompassProtocol(Protocol):
    """The board turned through every direction for a while; its magnetometer calibrated."""

    name = "compass"
    method = "magnetometer"
    words = "turn the board slowly through every direction, away from steel and magnets"


class NoiseProtocol(Protocol):
    """The board left resting for a while; its noise characterised (``trical noise``)."""

    name = "noise"
    command = method = "noise"
    words = "leave the board resting, untouched"


SIX, FREE, CUBE24 = SixProtocol(), FreeProtocol(), Cube24Protocol()
_SESSION_STRATEGIES: dict[str, SessionProtocol] = {s.name: s for s in (SIX, FREE, CUBE24)}
_STRATEGIES: dict[str, Protocol] = {**_SESSION_STRATEGIES, **{s.name: s for s in (CompassProtocol(), NoiseProtocol())}}

SESSION_PROTOCOLS: dict[str, SessionProtocol] = {name: _SESSION_STRATEGIES[name] for name in SESSION_PROTOCOL_NAMES}
"""The protocols the wizard's sessions follow (the API's ``SessionIn.protocol``): those
app.guided.capture_rules.WIZARD_PROTOCOLS says a session runs, each its strategy (a name without one fails
at import)."""

BOARD_PROTOCOLS: dict[str, Protocol] = {name: _STRATEGIES[name] for name in CAPTURE_PROTOCOLS}
"""The protocols ``trical capture`` follows (app.guided.capture_rules.CAPTURE_PROTOCOLS, in that order), each its
strategy."""


# -- what the protocols share ------------------------------------------------------------------------------------


def _gyr_mean_deg_s(capture: dict) -> float:
    rate = np.linalg.norm(np.mean(np.asarray(capture["gyr"], dtype=float), axis=0))
    return float(np.degrees(rate * GYR_TO_RAD_S[capture.get("gyr_unit", "deg/s")]))


def check_not_turning(capture: dict, what: str = "device") -> None:
    """Refuse a capture whose gyroscope, when sent, shows the device turning."""
    if capture.get("gyr") is None:
        return
    rate = _gyr_mean_deg_s(capture)
    if rate > MAX_ROTATION_DEG_S:
        raise NotStillError(
            f"the {what} was turning during the capture ({rate:.3g} °/s): leave it resting until the capture ends"
        )


def gyr_summary(capture: dict) -> dict:
    """A still capture's gyroscope, as the session keeps it for the bias (app.calibration.still.gyro_bias): the mean,
    the standard deviation (ddof 1) and the count of its samples, in the unit they came in; empty without them."""
    if capture.get("gyr") is None:
        return {}
    gyr = np.asarray(capture["gyr"], dtype=float).reshape(-1, 3)
    return {
        "gyr_mean": gyr.mean(axis=0).tolist(),
        "gyr_std": gyr.std(axis=0, ddof=1).tolist(),
        "gyr_count": len(gyr),
        "gyr_unit": capture.get("gyr_unit", "deg/s"),
    }


def session_gyroscope_bias(session: Session) -> dict | None:
    """The gyroscope bias over a session's still captures that carried gyroscope samples, in rad/s with its 95 %
    interval (app.calibration.still.gyro_bias); None when none did (or they were stored before captures kept it)."""
    captures = [c for c in session.captures if c.get("gyr_std") is not None]
    if not captures:
        return None
    scale = np.array([GYR_TO_RAD_S[c["gyr_unit"]] for c in captures])[:, None]
    return gyroscope_bias(
        np.array([c["gyr_mean"] for c in captures]) * scale,
        np.array([c["gyr_std"] for c in captures]) * scale,
        [c["gyr_count"] for c in captures],
    )


def session_body(session: Session, result, extra: dict, **fields) -> Calibration:
    """The calibration body of a solved session of still poses: the browser's notes, the capture rates, the
    gyroscope's bias, its owner's fields."""
    rates = [c["sampling_rate_hz"] for c in session.captures]
    extra = dict(extra, sampling_rate_hz_min=min(rates), sampling_rate_hz_max=max(rates))
    bias = session_gyroscope_bias(session)
    if bias is not None:
        fields["gyroscope_bias"] = bias
    return Calibration.of(
        result,
        extra,
        unit=session.unit,
        notes=browser_notes(session),
        device_id=session.device_id,
        label=session.label,
        session_id=session.id,
        source=session.source,
        **fields,
    )


def browser_notes(session: Session) -> list[str]:
    """The warnings a phone's browser calls for: rounding, the system's own calibration, the sign; a
    board's printed lines (``source`` ``board``) call for none of them."""
    notes = list(session.notes)
    if session.source == "board":
        return notes
    steps = {s for c in session.captures if (s := c.get("quantization_step")) is not None}
    if steps:
        notes.append(
            f"the browser rounds its sensor values to {max(steps):g} m/s²: each position's mean "
            "averages many samples, so it is still finer than the rounding"
        )
    notes.append(OS_CALIBRATION_WARNING)
    ios = sorted({c["sign"]["detected_from"] for c in session.captures if c.get("sign", {}).get("convention") == "ios"})
    if ios:
        notes.append(
            f"the browser reported the iOS sign convention (detected from {', '.join(ios)}); "
            "the samples were flipped to the W3C convention before fitting"
        )
    return notes
