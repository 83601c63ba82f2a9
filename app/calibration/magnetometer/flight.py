"""The compass calibrated from a flight: ``h_body = M (Q m − b − k p)`` against the field the attitude expects.

A flight log holds what no turn on a table has: the attitude ``C_nb`` (body → NED) at every compass
sample, so the field the compass should read in the body frame is known, ``e = C_nbᵀ B_ned`` (B_ned the
geomagnetic model's field at the log's place and date). The readings ``m`` (in the frame L the log gives
them in) are fitted to it:

1. **The orientation** (:func:`.flight_model.orientation`): the rotation Q (L → body) the data show, the
   nearest of the firmwares' rotations (:func:`app.calibration.shared.rotations.nearest_rotation`) and the angle
   left. The fit below uses the firmware's rotation, the only one a flight controller can apply.
2. **The fit** (:func:`.flight_model.design`): least squares of ``Q m − (M⁻¹ e + b + k p)``, linear in
   ``(M⁻¹, b, k)``; every sample weighted by one over the number of samples whose expected field points
   into the same face of an icosahedron (:mod:`.coverage`), so a long straight leg weighs no more than a
   short turn; 95 % intervals from the jackknife over blocks of time
   (:func:`.flight_model.block_jackknife`) — the residuals of a flight (the attitude's error, a wire's
   field) are correlated over seconds, and ``σ² (JᵀJ)⁻¹`` would count every sample as news.
3. **The model** chosen on flight segments left out: ``folds`` contiguous blocks of time; each candidate
   (offsets / + diagonal scale / + full symmetric soft iron, each with and without the motor term) is
   fitted on the other blocks and scored by the heading error on the block left out; the simplest
   candidate within :data:`MODEL_MARGIN` of the best is kept.
4. **The figure**: the heading error on the segments left out, before (the firmware's field) and after.
"""

from __future__ import annotations

import numpy as np

from ..shared.errors import CalibrationError, InsufficientDataError
from ..shared.gates import Gates
from ..shared.rotations import angle_between, nearest_rotation, rotation_matrix
from ..shared.uncertainty import CONFIDENCE, half_widths
from .coverage import coverage, face_of
from .flight_health import check_measuring
from .flight_model import (
    MATRIX_PARAMETERS,
    MODELS,
    block_jackknife,
    candidate_name,
    correlation_time,
    design,
    error_summary,
    headings_deg,
    n_parameters,
    normal_equations,
    orientation,
    parse_candidate,
    solve_normal,
    wrap_deg,
)
from .flight_partial import fixed_entries, held_words, improvement, undetermined, with_motor_axes
from .flight_result import FlightCompassResult

MIN_FIT_SAMPLES = 60
"""Fewer samples than this cannot be split into folds and fitted at all: refused (insufficient_data)."""

MIN_SAMPLES = 600
"""Fewer samples fit, but ``ok`` is false: a minute at 10 Hz, the shortest flight with turns through
every heading and enough blocks of time for the intervals."""

MIN_HEADING_SECTORS = 6
"""Of the eight 45° sectors of the expected field's azimuth in the body frame, a flight must reach six:
without turns the hard iron along the field and the field itself cannot be told apart."""

MAX_ONE_HEADING = 0.5
"""More than half of the flight in one 45° sector of heading (a vehicle parked, a straight leg): the few turns
weigh too little against it, and the offsets trade off against a turn of the compass about the vertical —
log171.bin of the real corpus, 77 % of it in one sector (mostly parked), shows the same 15–16° turn on all three
compasses. A flight of turns and circles holds 12–25 % in its fullest sector."""

MIN_COVERAGE = 0.15
"""Share of the 20 faces (:mod:`.coverage`) the expected field must reach (3 faces): a level flight turning
through all headings reaches a ring of 4–6 faces, a flight without turns one or two."""

MAX_ANGLE_LEFT_DEG = 15.0
"""The found rotation further than this from every firmware rotation: the orientation is unresolved
(a disturbed field, a wrong attitude, or a compass mounted at an angle no enum names)."""

WARN_ANGLE_LEFT_DEG = 5.0
"""Between this and :data:`MAX_ANGLE_LEFT_DEG` left: a warning (the compass sits a few degrees off its enum)."""

MAX_OFFSET_UT = 300.0
"""An offset above 300 µT on an axis: not iron near a compass (ArduPilot's COMPASS_OFFS_MAX defaults to
1800 mG, 180 µT) but a wrong unit or a magnet."""

MATRIX_EIGEN_RANGE = (0.67, 1.5)
"""M's eigenvalues outside this range: a gain off by half or more is a wrong unit or field, not soft iron."""

MAX_OFFSET_HALF_WIDTH = 0.05
"""A 95 % half-width of b above 5 % of the field: the hard iron is not determined."""

MAX_MATRIX_HALF_WIDTH = 0.05
"""A 95 % half-width of an entry of M above 0.05: the soft iron is not determined."""

MAX_MOTOR_HALF_WIDTH = 0.05
"""The motor term's 95 % half-width times the power's range above 5 % of the field: not determined."""

HALF_WIDTH_LIMITS = (MAX_OFFSET_HALF_WIDTH, MAX_MATRIX_HALF_WIDTH, MAX_MOTOR_HALF_WIDTH)
"""The three limits a number's interval must keep to be determined (:func:`.flight_partial.undetermined`)."""

MIN_POWER_RANGE = 0.2
"""Power whose 5–95 % range is below 20 % of its 95th percentile hardly varied: no motor term is tried."""

MODEL_MARGIN = 0.01
"""A candidate within 1 % (and :data:`MODEL_MARGIN_DEG`) of the best left-out heading error is as good."""

MODEL_MARGIN_DEG = 0.01

MAX_BLOCKS = 30
"""The jackknife's blocks of time: at most 30 …"""

BLOCK_CORRELATION_TIMES = 10.0
"""… each at least ten correlation times of the residuals long (so that neighbouring blocks hardly share
a disturbance), and of at least :data:`MIN_BLOCK_SAMPLES` samples."""

FEW_BLOCKS = 4
SHORT_BLOCK_CORRELATION_TIMES = 5.0
"""A flight too short for :data:`FEW_BLOCKS` blocks of ten correlation times gets up to that many, each at least
five long: with two to four blocks Student's quantile falls steeply with every block (12.7, 4.3, 3.2 at one, two
and three degrees of freedom), while the blocks' shared disturbance grows only as the correlation time over their
length. On 150 seeded flights of 1–5 min correlated over 1–16 s (bench/flight_compass_intervals.py), the 50 that
hold at most four blocks of ten correlation times: the truth inside 97.5 % of the intervals, the offsets' 0.62 of
the width that blocks of ten correlation times without overlap gave; over all 150, 95.4 % and 0.83."""

BLOCK_STEPS = 4
"""A block is left out at every quarter of its length (overlapping blocks, :func:`.flight_model.block_jackknife`):
on short flights of two to four blocks the intervals' quantile falls by a third to two thirds."""

MIN_BLOCK_SAMPLES = 20
MIN_BLOCKS = 8
"""With fewer blocks the intervals rest on too few independent pieces: a warning."""

SERIES_POINTS = 600

MAX_FIT_SAMPLES = 60_000
"""A log of more compass samples (40 min at 25 Hz) is thinned evenly to at most this many before the attitude is
interpolated and the compass fitted (:func:`thinning`): the residuals of a flight stay correlated for 1.4–16 s
(35–400 samples at 25 Hz, the real corpus's), so a sample every few tenths of a second carries nearly all that the
flight holds, and the fit's time is the read's, not the samples' (bench/flight_compass_speed.py)."""


def thinning(n: int) -> slice:
    """Every k-th of ``n`` compass samples, k the smallest that keeps at most :data:`MAX_FIT_SAMPLES`."""
    return slice(None, None, max(1, -(-n // MAX_FIT_SAMPLES)))


def _weights(e: np.ndarray) -> np.ndarray:
    """One over the count of samples whose expected field falls in the same face, scaled to mean 1."""
    faces = face_of(e)
    counts = np.bincount(faces, minlength=20)
    w = 1.0 / counts[faces]
    return w / w.mean()


def _blocks(n: int, count: int) -> np.ndarray:
    return (np.arange(n) * count) // n


def _candidates(models, power_usable: bool, power_given: bool) -> list[str]:
    if models == "auto":
        return [candidate_name(m, motor) for m in MODELS for motor in ((False, True) if power_usable else (False,))]
    names = [models] if isinstance(models, str) else list(models)
    out = []
    for name in names:
        try:
            _model, motor = parse_candidate(name)
        except ValueError:
            raise CalibrationError(
                f"unknown compass model {name!r}: use auto or one of "
                + ", ".join(candidate_name(m, x) for m in MODELS for x in (False, True))
            ) from None
        if motor and not power_given:
            raise CalibrationError(f"the model {name!r} has a motor term: give the power (current or throttle)")
        out.append(name)
    return out


def _simplest(scores: dict[str, float]) -> str:
    """The candidate with fewest parameters (no motor term first among equals) whose left-out heading
    error is within :data:`MODEL_MARGIN` of the best."""
    best = min(scores.values())
    limit = best * (1.0 + MODEL_MARGIN) + MODEL_MARGIN_DEG
    order = sorted(scores, key=lambda n: (n_parameters(*parse_candidate(n)), parse_candidate(n)[1]))
    return next(n for n in order if scores[n] <= limit)


def _thin(n: int) -> np.ndarray:
    return np.unique(np.linspace(0, n - 1, min(n, SERIES_POINTS)).round().astype(int))


def _array(x, name: str, shape_tail: tuple, n: int | None = None) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.shape[1:] != shape_tail or a.ndim != 1 + len(shape_tail) or (n is not None and len(a) != n):
        want = "N" + "".join(f"×{s}" for s in shape_tail)
        raise CalibrationError(
            f"{name} must be {want}" + (f" with N = {n}" if n is not None else "") + f"; got shape {a.shape}"
        )
    return a


def fit_flight_compass(
    mag,
    expected,
    *,
    time_s,
    power=None,
    power_kind=None,
    firmware_field=None,
    frame_to_body=None,
    attitude=None,
    earth_ned=None,
    folds: int = 5,
    models="auto",
    confidence: float = CONFIDENCE,
    not_measuring_remedy: str | None = None,
    firmware: str | None = None,
    stored=None,
) -> FlightCompassResult:
    """Calibrate a compass from a flight: ``h_body = M (Q m − b − k p)`` fitted to ``e = C_nbᵀ B_ned``.

    Parameters
    ----------
    mag : array_like, shape (N, 3)
        Raw readings in µT in the frame L the log gives them in.
    expected : array_like, shape (N, 3)
        The field expected in the body frame, µT (``C_nbᵀ B_ned``).
    time_s : array_like, shape (N,)
        Sample times, increasing; the folds and the covariance's blocks are contiguous in time.
    power : array_like of shape (N,), optional
        Current in A or throttle 0..1 (``power_kind`` says which); without it no motor term.
    power_kind : {"current", "throttle"}, optional
    firmware_field : array_like of shape (N, 3), optional
        The body field the firmware computed (its calibration), for the error "before".
    frame_to_body : array_like of shape (3, 3), optional
        The rotation L → body the firmware applies now (identity by default).
    attitude : array_like of shape (N, 3, 3), optional
        ``C_nb`` (body → NED) at each sample: needed for the heading errors (without it ``ok`` is false).
    earth_ned : array_like of shape (3,), optional
        B_ned in µT; without it the reference azimuth is that of ``C_nb e`` sample by sample.
    folds : int
        Contiguous blocks of time for choosing the model, ≥ 2.
    models : str or sequence of str
        ``"auto"`` (every candidate), or the candidates to try: ``offsets``, ``scale``, ``soft_iron``,
        each optionally ``+motor``.
    confidence : float
        Of the intervals.
    not_measuring_remedy : str, optional
        What to check when the readings do not measure the Earth's field (the firmware's own settings).
    firmware : {"ardupilot", "px4"}, optional
        The firmware that will apply the orientation: only its rotations are searched (by default either's).
    stored : dict, optional
        The firmware's stored calibration in the fit's terms (``M``, ``b``, ``k`` of ``h = M (Q m − b − k p)``,
        for the rotation the firmware applies now): where the flight leaves some numbers undetermined and the
        mounting agrees, those are held at these values and the rest updated (:mod:`.flight_partial`).

    Returns
    -------
    FlightCompassResult

    Raises
    ------
    CalibrationError
        Malformed input (shapes, non-finite times, an unknown model).
    CompassNotMeasuringError
        Readings that do not measure the Earth's field (:func:`.flight_health.check_measuring`): zero, not
        turning with the vehicle, or turning by a wrong scale.
    InsufficientDataError
        Fewer than :data:`MIN_FIT_SAMPLES` usable samples.
    """
    m, e, t, p, fw, C = _series_arrays(mag, expected, time_s, power, power_kind, firmware_field, attitude)
    F2B = np.eye(3) if frame_to_body is None else np.asarray(frame_to_body, dtype=float).reshape(3, 3)
    B = None if earth_ned is None else np.asarray(earth_ned, dtype=float).reshape(3)
    if int(folds) < 2:
        raise CalibrationError(f"folds must be 2 or more; got {folds}")
    folds = int(folds)

    m, e, t, p, fw, C = _usable(m, e, t, p, fw, C)
    check_measuring(m, e, remedy=not_measuring_remedy)  # before anything is fitted or judged "better"
    n = len(m)
    gates = Gates()
    if n < MIN_SAMPLES:
        gates.fail(f"only {n} samples: fly at least a minute ({MIN_SAMPLES} samples) with turns through every heading")
    F = float(np.median(np.linalg.norm(e, axis=1)))
    share, level = _direction_gates(gates, e, C)
    power_usable = _power_usable(gates, p, power_kind)
    candidates = _candidates(models, power_usable, p is not None)
    if models == "auto" and p is None:
        gates.warn("no current or throttle given: the motor term was not tried")
    w = _weights(e)

    # 1. The orientation.
    Q_found = orientation(m, e, p if power_usable else None, w)
    ap, px4, name, angle_left = nearest_rotation(Q_found, firmware)
    Q = rotation_matrix(ap, px4)
    agrees = angle_between(Q, F2B) < 0.01
    _orientation_gates(gates, ap, px4, name, angle_left, agrees)
    u = m @ Q.T

    # 3. The model chosen on segments left out.
    fold = _blocks(n, folds)
    ref = None if C is None else (np.degrees(np.arctan2(B[1], B[0])) if B is not None else headings_deg(e, C))
    scores, left_out = _left_out(candidates, u, e, p, w, fold, folds, C, ref)
    key = "rms" if C is not None else "rms_ut"
    chosen = _simplest({c: s[key] for c, s in scores.items()})
    model, motor = parse_candidate(chosen)

    # 2. The fit on all samples and its intervals.
    fit, h, half, blocks = _fit_with_intervals(gates, u, e, p if motor else None, w, t, model, motor, confidence)
    held = None
    if stored is not None and agrees and half is not None and C is not None and fw is not None:
        partial = _partial(
            gates, u, e, p if motor else None, w, t, fold, folds, model, motor, half, F, stored, confidence
        )
        if partial is not None:
            fit, h, half, blocks, left_out[chosen], held = partial
    if level is not None and (half is None or _any_open(half, F, p, motor, model)):
        gates.fail(level)  # a level flight: failed where it leaves a number open (not held, not bounded)
    _parameter_gates(gates, fit, half, F, p, power_kind, confidence)

    # 4. The figure: heading errors on segments left out, before and after.
    heading, err_before, err_after = _heading_errors(gates, left_out[chosen], fw, C, ref)
    if held is not None and err_before is not None and err_after is not None:
        drop, within = improvement(err_before, err_after, fold, folds, confidence)
        heading["improvement"] = {"mean_deg": drop, "half_width_deg": within}
        if 0 < drop <= within:  # a rise is said by the "does not lower" gate
            gates.fail(
                f"the update lowers the heading error by {drop:.2f}° ± {within:.2f}° on segments left out, within "
                "its interval: keep the calibration the firmware has, and fly turns through every heading"
            )

    idx = _thin(n)

    def thin(a):
        return None if a is None else a[idx]

    series = {
        "time_s": t[idx],
        "expected": e[idx],
        "corrected": h[idx],
        "firmware": thin(fw),
        "field_magnitude": np.linalg.norm(h[idx], axis=1),
        "power": thin(p),
        "heading_error_before": thin(err_before),
        "heading_error_after": thin(err_after),
    }
    fields = gates.fields()
    hw_M, hw_b, hw_k = half if half is not None else (None, None, None)
    return FlightCompassResult(
        ok=not fields["reasons"],
        reasons=fields["reasons"],
        warnings=fields["warnings"],
        model=model,
        motor=power_kind if motor else None,
        offsets_ut=fit.b,
        offsets_half_width_ut=hw_b,
        matrix=fit.M,
        matrix_half_width=hw_M,
        motor_coefficients=fit.k,
        motor_half_width=hw_k,
        rotation=Q,
        rotation_found=Q_found,
        rotation_nearest={"ardupilot": ap, "px4": px4, "name": name},
        angle_left_deg=float(angle_left),
        orientation_agrees=bool(agrees),
        heading_error_deg=heading,
        models=scores,
        coverage=float(share),
        n_samples=n,
        series=series,
        intervals=blocks,
        confidence=confidence,
        updated=None if held is None else _updated(held),
    )


def _series_arrays(mag, expected, time_s, power, power_kind, firmware_field, attitude):
    """The flight's series as arrays, each checked for its shape and one value per reading: the readings,
    the expected field, the times, the power (with its kind), the firmware's field and the attitude (the
    last three None when not given)."""
    m = _array(mag, "the compass readings", (3,))
    n0 = len(m)
    e = _array(expected, "the expected field", (3,), n0)
    t = np.asarray(time_s, dtype=float).reshape(-1)
    if len(t) != n0:
        raise CalibrationError(f"time_s must have one time per reading ({n0}); got {len(t)}")
    p = None if power is None else np.asarray(power, dtype=float).reshape(-1)
    if p is not None and len(p) != n0:
        raise CalibrationError(f"power must have one value per reading ({n0}); got {len(p)}")
    if p is not None and power_kind not in ("current", "throttle"):
        raise CalibrationError(f"power_kind must be current or throttle with a power; got {power_kind!r}")
    fw = None if firmware_field is None else _array(firmware_field, "the firmware's field", (3,), n0)
    C = None if attitude is None else _array(attitude, "the attitude", (3, 3), n0)
    return m, e, t, p, fw, C


def _heading_errors(gates: Gates, corrected_left_out, fw, C, ref) -> tuple[dict, np.ndarray | None, np.ndarray | None]:
    """The heading errors against the reference azimuth ``ref``: after (the fields of the chosen model on
    segments left out) and before (the firmware's field), each summarised, and both series; None without an
    attitude (and before without the firmware's field). A fit that does not lower the error fails."""
    heading: dict[str, dict | None] = {"before": None, "after": None}
    err_before = err_after = None
    if C is not None:
        err_after = wrap_deg(headings_deg(corrected_left_out, C) - ref)
        heading["after"] = after = error_summary(err_after)
        if fw is not None:
            err_before = wrap_deg(headings_deg(fw, C) - ref)
            heading["before"] = before = error_summary(err_before)
            if after["rms"] >= before["rms"]:
                gates.fail(
                    f"the fit does not lower the heading error (rms {after['rms']:.2f}° on "
                    f"segments left out against {before['rms']:.2f}° with the firmware's "
                    "calibration): keep the calibration the firmware has"
                )
    return heading, err_before, err_after


def _usable(m, e, t, p, fw, C):
    """The samples with every given quantity finite, in time order; refused below :data:`MIN_FIT_SAMPLES`."""
    n0 = len(m)
    good = np.all(np.isfinite(m), axis=1) & np.all(np.isfinite(e), axis=1) & np.isfinite(t)
    if p is not None:
        good &= np.isfinite(p)
    if fw is not None:
        good &= np.all(np.isfinite(fw), axis=1)
    if C is not None:
        good &= np.all(np.isfinite(C.reshape(n0, 9)), axis=1)
    order = np.argsort(t[good], kind="stable")
    out = tuple(None if a is None else a[good][order] for a in (m, e, t, p, fw, C))
    n = len(out[0])
    if n < MIN_FIT_SAMPLES:
        raise InsufficientDataError(
            f"{n} usable compass samples (with their expected field{', power' if p is not None else ''} and time): "
            f"a flight calibration needs at least {MIN_FIT_SAMPLES}, and a minute of flight with turns to be trusted"
        )
    return out


def _direction_gates(gates: Gates, e: np.ndarray, C) -> tuple[float, str | None]:
    """The directions the flight reached in the body frame (:data:`MIN_HEADING_SECTORS`,
    :data:`MIN_COVERAGE`) and the attitude; returns the share of the 20 faces covered, and the reason of a flight
    that turned through every heading but stayed level (too few directions alone), which the caller gives unless
    the numbers a level flight leaves open are held at the firmware's (:func:`_partial`)."""
    share, _ = coverage(e)
    azimuth = np.degrees(np.arctan2(e[:, 1], e[:, 0]))
    counts = np.bincount(((azimuth + 180.0) // 45.0).astype(int) % 8, minlength=8)
    sectors, one_way = int(np.count_nonzero(counts)), float(counts.max() / max(len(e), 1))
    level = None  # too few directions alone: a reason only where a number stays open (the caller's)
    if sectors < MIN_HEADING_SECTORS or share < MIN_COVERAGE or one_way > MAX_ONE_HEADING:
        # The cause that failed, said so that the figures never contradict it: 8 of 8 sectors is no "too few".
        if sectors < MIN_HEADING_SECTORS:
            said = f"the flight turned through too few headings ({sectors} of 8 sectors of 45° reached"
        elif one_way > MAX_ONE_HEADING:
            said = (
                f"the flight held one heading for most of it ({sectors} of 8 sectors of 45° reached, but "
                f"{one_way:.0%} of the flight in one"
            )
        else:
            said = f"the flight stayed level ({sectors} of 8 sectors of 45° reached, but tilted little"
        why = (
            f"{said}; {share:.0%} of the directions): fly turns through every heading (a slow full yaw turn, or "
            "circles), banked as well as level, so that the hard iron can be told from the field and from a turn of "
            "the compass"
        )
        if sectors < MIN_HEADING_SECTORS or one_way > MAX_ONE_HEADING:
            gates.fail(why)
        else:
            level = why
    if C is None:
        gates.fail(
            "no attitude in the log: the heading errors cannot be measured, so no fit can be judged; "
            "log the attitude (ArduPilot ATT, PX4 vehicle_attitude)"
        )
    return float(share), level


def _power_usable(gates: Gates, p, power_kind) -> bool:
    """Whether the power varied enough for a motor term (:data:`MIN_POWER_RANGE`), with a warning if not."""
    if p is None:
        return False
    lo, hi = np.percentile(p, [5, 95])
    usable = bool((hi - lo) > MIN_POWER_RANGE * max(abs(hi), 1e-12))
    if not usable:
        gates.warn(
            f"the {power_kind} hardly varied ({lo:.3g} to {hi:.3g}, 5–95 %): the motor term is not "
            "determined, so none is fitted; fly climbs and hovers to find it"
        )
    return usable


def _orientation_gates(gates: Gates, ap, px4, name: str, angle_left: float, agrees: bool) -> None:
    if angle_left > MAX_ANGLE_LEFT_DEG:
        gates.fail(
            f"the compass's orientation is unresolved: the rotation the data show is {angle_left:.0f}° from "
            f"every firmware rotation (the nearest is {name}); a disturbed field, a wrong attitude, or a "
            "compass mounted at an angle no orientation setting names"
        )
    elif angle_left > WARN_ANGLE_LEFT_DEG:
        gates.warn(
            f"the compass sits {angle_left:.1f}° off the nearest orientation setting ({name}): the "
            "firmware cannot apply the rest, which stays as a heading error"
        )
    if not agrees:
        settings = [
            f"ArduPilot COMPASS_ORIENTn {ap}" if ap is not None else "no ArduPilot COMPASS_ORIENTn value",
            f"PX4 CAL_MAGn_ROT {px4}" if px4 is not None else "no PX4 CAL_MAGn_ROT value",
        ]
        gates.warn(f"the compass is mounted as {name} ({', '.join(settings)}), not as the firmware applies it now")


def _left_out(candidates, u, e, p, w, fold, folds: int, C, ref) -> tuple[dict, dict]:
    """Each candidate fitted without each fold and evaluated on it: its scores (heading error, or the
    field's error without an attitude) and its left-out fields. A candidate the other folds do not
    determine is dropped."""
    scores, left_out = {}, {}
    for cand in candidates:
        model, motor = parse_candidate(cand)
        pred = _fold_fields(u, e, p if motor else None, w, fold, folds, model, motor)
        if pred is None:  # the other segments do not determine this candidate
            continue
        left_out[cand] = pred
        if C is not None:
            scores[cand] = error_summary(wrap_deg(headings_deg(pred, C) - ref))
        else:
            scores[cand] = {"rms_ut": float(np.sqrt(np.mean(np.sum((pred - e) ** 2, axis=1))))}
        scores[cand]["n_parameters"] = n_parameters(model, motor)
    if not scores:
        raise InsufficientDataError(
            "no model can be fitted on the flight with a segment left out: fly longer, "
            "with turns through every heading and some pitch and roll"
        )
    return scores, left_out


def _fold_fields(u, e, p, w, fold, folds: int, model: str, motor: bool, held=None) -> np.ndarray | None:
    """Each fold's field from the fit on the other folds (``held`` entries fixed, :func:`.flight_model.
    solve_normal`), or None where the other folds do not determine the model."""
    X, y = design(u, e, p, model, motor)
    A, g = normal_equations(X, y, w, fold, folds)
    pred = np.empty_like(e)
    for k in range(folds):
        out = fold == k
        try:
            f = solve_normal(A.sum(axis=0) - A[k], g.sum(axis=0) - g[k], model, motor, held)
        except np.linalg.LinAlgError:
            return None
        pred[out] = f.field(u[out], p[out] if motor else None)
    return pred


def _fit_with_intervals(gates: Gates, u, e, p, w, t, model: str, motor: bool, confidence: float, held=None):
    """The fit on every sample (``held`` entries fixed), its field, the half-widths ``(M, b, k)`` (None without
    intervals) and how the blocks of the jackknife were chosen (:data:`BLOCK_CORRELATION_TIMES`)."""
    n = len(u)
    X, y = design(u, e, p, model, motor)
    A, g = normal_equations(X, y, w, np.zeros(n, dtype=int), 1)
    try:
        fit = solve_normal(A[0], g[0], model, motor, held)
    except np.linalg.LinAlgError:
        raise InsufficientDataError(
            "the flight does not determine the compass's parameters (a singular fit): "
            "fly turns through every heading with some pitch and roll"
        ) from None
    h = fit.field(u, p)
    dt = float(np.median(np.diff(t)))
    corr = correlation_time(h - e)
    count = _block_count(n, corr)
    if count < MIN_BLOCKS:
        gates.warn(
            f"the residuals stay correlated over {corr * dt:.1f} s: the flight holds fewer than "
            f"{MIN_BLOCKS} independent stretches, so the intervals rest on few of them"
        )
    count = max(count, 2)
    A, g = normal_equations(X, y, w, _blocks(n, count * BLOCK_STEPS), count * BLOCK_STEPS)
    try:
        cov, dof = block_jackknife(A, g, model, motor, held, steps=BLOCK_STEPS)
    except np.linalg.LinAlgError:
        gates.fail(
            "a stretch of the flight holds all that determines a parameter (the fit without it is "
            "singular): no intervals; fly turns through every heading with some pitch and roll"
        )
        return fit, h, None, _blocks_used(count, corr * dt, None)
    blocks = _blocks_used(count, corr * dt, dof)
    return fit, h, _split_half(half_widths(cov, dof, confidence), model, motor), blocks


def _block_count(n: int, corr: float) -> int:
    """Blocks of :data:`BLOCK_CORRELATION_TIMES` correlation times; where that leaves fewer than
    :data:`FEW_BLOCKS`, as many as that of blocks down to :data:`SHORT_BLOCK_CORRELATION_TIMES` long."""
    count = int(min(MAX_BLOCKS, n // max(MIN_BLOCK_SAMPLES, BLOCK_CORRELATION_TIMES * corr)))
    if count < FEW_BLOCKS:
        count = max(count, int(min(FEW_BLOCKS, n // max(MIN_BLOCK_SAMPLES, SHORT_BLOCK_CORRELATION_TIMES * corr))))
    return count


def _blocks_used(count: int, correlation_s: float, dof: float | None) -> dict:
    return {
        "blocks": count,
        "correlation_s": correlation_s,
        "dof": None if dof is None else round(dof, 2),
        "method": "jackknife over overlapping blocks of time",
    }


def _split_half(hw: np.ndarray, model: str, motor: bool) -> tuple:
    """``(M's, b's, k's)`` half-widths from those of ``(M's entries, b, k)``."""
    nm = len(MATRIX_PARAMETERS[model])
    hw_M = np.zeros((3, 3))
    for value, (i, j) in zip(hw[:nm], MATRIX_PARAMETERS[model]):
        hw_M[i, j] = hw_M[j, i] = value
    return hw_M, hw[nm : nm + 3], hw[nm + 3 : nm + 6] if motor else np.zeros(3)


def _partial(
    gates: Gates, u, e, p, w, t, fold, folds: int, model: str, motor: bool, half, F: float, stored, confidence
):
    """Where the intervals leave some numbers undetermined and others not, the fit with those held at the
    firmware's ``stored`` values (:mod:`.flight_partial`): its fit, field, half-widths (0 where held), blocks,
    fields on segments left out, and what was held; None where nothing or everything is undetermined."""
    held = with_motor_axes(undetermined(half, F, p, motor, model, HALF_WIDTH_LIMITS))
    found = None
    for _ in range(2):  # numbers freed may still be open once the others are held: hold them too, once
        if motor and held["k"].any() and stored.get("k") is None:
            return found  # a motor term the firmware stores in other terms: not held
        one = _held_fit(u, e, p, w, t, fold, folds, model, motor, held, stored, confidence)
        if one is None:
            return found
        found = (*one, held)
        more = undetermined(one[2], F, p, motor, model, HALF_WIDTH_LIMITS)
        more = with_motor_axes({"b": more["b"] | held["b"], "M": more["M"] or held["M"], "k": more["k"] | held["k"]})
        if all(np.array_equal(more[key], held[key]) for key in held):
            break
        held = more
    if found is not None:
        gates.warn(
            "the flight does not determine "
            + ", ".join(held_words(found[-1]))
            + ": held at the firmware's stored values, the rest updated from the flight (their intervals assume "
            "the held values are right)"
        )
    return found


def _held_fit(u, e, p, w, t, fold, folds: int, model: str, motor: bool, held: dict, stored, confidence):
    """The fit with ``held`` at the ``stored`` values: fit, field, half-widths (0 where held), blocks and the fields
    on segments left out; None where nothing or everything is held, or the rest is not determined."""
    fixed = fixed_entries(model, motor, held, stored)
    if not fixed[0].any() or fixed[0].all():
        return None
    pred = _fold_fields(u, e, p, w, fold, folds, model, motor, fixed)
    if pred is None:
        return None
    try:  # its gates are the caller's: a singular fit, or no intervals, is no update
        fit, h, half, blocks = _fit_with_intervals(Gates(), u, e, p, w, t, model, motor, confidence, fixed)
    except InsufficientDataError:
        return None
    return None if half is None else (fit, h, half, blocks, pred)


def _any_open(half, F: float, p, motor: bool, model: str) -> bool:
    """Whether a half-width leaves its number undetermined (a held one has none: it is the firmware's)."""
    open_ = undetermined(half, F, p, motor, model, HALF_WIDTH_LIMITS)
    return bool(open_["b"].any() or open_["M"] or open_["k"].any())


def _updated(held: dict) -> dict:
    """What the flight updated (true) and what it held at the firmware's values (false)."""
    return {"b": [not h for h in held["b"]], "M": not held["M"], "k": [not h for h in held["k"]]}


def _parameter_gates(gates: Gates, fit, half, F: float, p, power_kind, confidence: float) -> None:
    """Plausible parameters (:data:`MAX_OFFSET_UT`, :data:`MATRIX_EIGEN_RANGE`) and determined ones (the
    half-widths against :data:`MAX_OFFSET_HALF_WIDTH`, :data:`MAX_MATRIX_HALF_WIDTH`,
    :data:`MAX_MOTOR_HALF_WIDTH`)."""
    for axis, value in zip("xyz", fit.b):
        if abs(value) > MAX_OFFSET_UT:
            gates.fail(
                f"the {axis} offset {value:.0f} µT is beyond {MAX_OFFSET_UT:.0f} µT: no iron near a compass "
                "does that; check the unit of the readings and for a magnet"
            )
    eig = np.linalg.eigvalsh(fit.M)
    lo, hi = MATRIX_EIGEN_RANGE
    if eig.min() < lo or eig.max() > hi:
        gates.fail(
            f"the soft-iron matrix scales the field by {eig.min():.2f} to {eig.max():.2f} (plausible "
            f"{lo}–{hi}): a wrong unit or a wrong expected field, not soft iron"
        )
    if half is None:
        return
    hw_M, hw_b, hw_k = half
    if np.max(hw_b) > MAX_OFFSET_HALF_WIDTH * F:
        gates.fail(
            f"the offsets are not determined (±{np.max(hw_b):.2f} µT at {confidence:.0%}, above "
            f"{MAX_OFFSET_HALF_WIDTH:.0%} of the field): fly turns through every heading"
        )
    if np.max(hw_M) > MAX_MATRIX_HALF_WIDTH:
        gates.fail(
            f"the soft iron is not determined (±{np.max(hw_M):.3f} on an entry at {confidence:.0%}): "
            "fly turns with more pitch and roll"
        )
    if fit.motor:
        spread = float(np.max(hw_k) * np.ptp(p))
        if spread > MAX_MOTOR_HALF_WIDTH * F:
            gates.fail(
                f"the motor term is not determined (±{spread:.2f} µT over the flight's {power_kind} "
                "range): fly climbs and hovers while turning"
            )
