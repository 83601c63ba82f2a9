"""Check a device's calibration on a new recording: keep it, calibrate again, or move the compass.

The current calibration's correction ``f = M (m − o)`` (any result's :meth:`corrections`, whatever model made it)
is applied to the new readings, and the error it leaves is set against what a fresh calibration reaches on the
same readings (docs/methods.md, "Check: keep or recalibrate"):

- **accelerometer** (still poses): the norm error of each corrected pose, ``e_i = | |a_i| − g |`` in mg
  (:mod:`app.calibration.shared.norm_metrics`; Farago, Maczak and Gingl, IEEE Access, Table 3), its mean with a
  95 % bootstrap interval over the poses (Efron and Tibshirani, *An Introduction to the Bootstrap*, 1993,
  chapter 13, the percentile interval), told as the worst tilt ``asin(e / g)`` (:mod:`app.calibration.shared.angles`).
  The fresh calibration is the nine-parameter model ``a = K (v + o)`` (Farago et al., eqs. (6)–(9)) fitted on the
  *corrected* poses: it is the identity where nothing drifted, so its K and o are the drift itself, with their
  intervals. Its error on new poses is estimated by its in-sample errors scaled by √(N / (N − 9)) (the residual
  degrees of freedom), bootstrapped the same way.
- **compass** (a turn): the field-strength error of each corrected reading, ``| |h_i| − F |`` in µT, its RMS with a
  95 % bootstrap interval over the 20 directions of the icosahedron the readings fall in (a cluster bootstrap:
  readings close in time are not independent), told as the worst heading ``asin(e / H)``, H = F cos I. The fresh
  calibration is the compass's own fit (:func:`app.calibration.magnetometer.fit.fit_magnetometer`) on the corrected
  readings; its error is its error on directions it did not see (``cv_error_ut``).
- **gyroscope** at rest: the residual bias, the mean corrected rate in °/s, with a Student-t interval over ten
  blocks of the rest (their means are nearly independent where the samples are not).

The decision, per sensor:

- *cannot tell* when the readings do not constrain it (too few poses, a turn that misses directions), saying
  what to record;
- *move the compass* when no ellipsoid fits the turn (the fresh fit's spread of |h| beyond 10 % of F, or its
  refinement runs away: the field changed as the device turned), or the field the readings hold is more than
  15 % from the place's;
- *keep* when the current error's interval reaches the fresh one's (they overlap) or the current error is
  within the tolerance (:data:`KEEP_TOLERANCE_MG`, :data:`KEEP_TOLERANCE_UT`, :data:`KEEP_TOLERANCE_DPS`);
- else *calibrate again*, naming what drifted: the fresh fit's parameters whose 95 % interval excludes the
  identity (:mod:`app.calibration.compare`: offsets, scales, cross-axis terms; a compass's hard and soft iron),
  else the one furthest from it for its interval.

The device's verdict is its worst sensor's, in the order move the compass, calibrate again, keep, cannot tell.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .compare import (
    Difference,
    SensorComparison,
    acc_reference,
    calibrated_unit,
    compare_corrections,
    correction_half_widths,
)
from .magnetometer.coverage import coverage, face_of
from .magnetometer.fit import (
    MAX_INCLINATION_ERROR_DEG,
    MAX_SCALE_DEVIATION,
    MAX_SPREAD,
    MIN_COVERAGE,
    MIN_READINGS,
    fit_magnetometer,
    measured_inclination,
)
from .shared.angles import ASSUMED_INCLINATION_DEG, heading_error_deg, tilt_error_deg
from .shared.correction import AffineCorrection
from .shared.errors import CalibrationError
from .shared.result import CalibrationResult, StillReadingsResult
from .shared.uncertainty import t_quantile
from .shared.validation import as_vectors
from .still.affine import fit_orientations
from .still.triangular import fit_triangular

KEEP, AGAIN, MOVE, CANNOT = "keep", "calibrate_again", "move_the_compass", "cannot_tell"
VERDICTS = (KEEP, AGAIN, MOVE, CANNOT)
VERDICT_WORDS = {
    KEEP: "keep it",
    AGAIN: "calibrate again",
    MOVE: "move the compass",
    CANNOT: "cannot tell",
}
"""Each verdict in words, as the terminal and the page say it."""
SEVERITY = {MOVE: 3, AGAIN: 2, KEEP: 1, CANNOT: 0}
"""Which sensor's verdict is the device's: the worst that is told (a sensor that cannot tell decides nothing)."""

KEEP_TOLERANCE_MG = 1.0
"""An accelerometer error within 1 mg (a level off by 0.06° at most) is kept whatever a fresh fit reaches:
below a phone's repeatability between sessions. Decided here."""

KEEP_TOLERANCE_UT = 0.5
"""A compass error within 0.5 µT RMS (a heading off by about 1.2° at most where H = 24 µT) is kept. Decided
here: a phone's compass noise is about 0.3–0.5 µT."""

KEEP_TOLERANCE_DPS = 0.1
"""A gyroscope's residual bias within 0.1 °/s is kept (a consumer MEMS gyroscope's bias moves by more between
power-ups). Decided here."""

MIN_POSES = 12
"""Fewest still poses a check of the accelerometer takes: the fresh nine-parameter fit needs 9, and three more
leave its error and intervals degrees of freedom."""

MAX_FRESH_ERROR = 0.05
"""A fresh compass fit that errs by more than 5 % of F on directions it did not see (2.4 µT at 48 µT; a phone's
fit on a clean turn errs by 0.3–1 µT, the QMC5883L board's of tests/data/real/magnetometer by 2.9 %) fits no
ellipsoid: the field changed with the device's attitude."""

MIN_LABELLED_POSES = 6
"""Fewest still poses of known orientation (each labelled with the axis up) a check takes: the fresh fit is then
the affine model of known orientations (Georgieva et al., ESGI'95, section 3.3: 12 parameters, 3 equations a pose),
which the six axis orientations determine."""

AFFINE_PARAMETERS = 12

MIN_REST_SAMPLES = 50
"""Fewest samples of a rest a gyroscope's check takes (ten blocks of five)."""

BOOTSTRAP = 2000
"""Resamples of the bootstrap intervals (seeded: a check of the same readings says the same)."""

TRIANGULAR_PARAMETERS = 9


@dataclass(frozen=True)
class Interval:
    """An error figure with its 95 % interval, in ``unit``, and as an angle (``*_deg``; None where none is told)."""

    value: float
    low: float
    high: float
    unit: str
    value_deg: float | None = None
    high_deg: float | None = None

    def to_dict(self) -> dict:
        return {
            "value": self.value,
            "low": self.low,
            "high": self.high,
            "unit": self.unit,
            "value_deg": self.value_deg,
            "high_deg": self.high_deg,
        }


@dataclass(frozen=True)
class SensorCheck:
    """One sensor's check: its ``verdict``, the ``reasons`` in words, the error of the current calibration and of a
    fresh one on the same readings, what ``drifted`` (in words) and the fresh fit's drift, parameter by parameter."""

    sensor: str
    verdict: str
    reasons: tuple[str, ...]
    count: int
    current: Interval | None = None
    fresh: Interval | None = None
    drifted: tuple[str, ...] = ()
    drift: SensorComparison | None = None
    angle_kind: str | None = None

    def to_dict(self) -> dict:
        return {
            "sensor": self.sensor,
            "verdict": self.verdict,
            "reasons": list(self.reasons),
            "count": self.count,
            "angle_kind": self.angle_kind,
            "current": None if self.current is None else self.current.to_dict(),
            "fresh": None if self.fresh is None else self.fresh.to_dict(),
            "drifted": list(self.drifted),
            "drift": None if self.drift is None else self.drift.to_dict(),
        }


@dataclass(frozen=True)
class CheckResult:
    """A calibration checked on new readings: the device's ``verdict`` (its worst sensor's) and each sensor's."""

    verdict: str
    sensors: tuple[SensorCheck, ...]

    @property
    def reasons(self) -> tuple[str, ...]:
        return tuple(r for s in self.sensors for r in s.reasons)

    def to_dict(self) -> dict:
        return {
            "verdict": self.verdict,
            "reasons": list(self.reasons),
            "sensors": [s.to_dict() for s in self.sensors],
        }


def _bootstrap_mean(values: np.ndarray, groups: np.ndarray | None = None, *, rms: bool = False) -> tuple[float, float]:
    """The 95 % percentile interval of the mean (or RMS) of ``values``, resampling them (or their ``groups``)."""
    rng = np.random.default_rng(0)
    v = values * values if rms else values
    if groups is None:
        picks = rng.integers(0, len(v), (BOOTSTRAP, len(v)))
        stats = v[picks].mean(axis=1)
    else:
        labels = np.unique(groups)
        sums = np.array([v[groups == g].sum() for g in labels])
        counts = np.array([np.sum(groups == g) for g in labels], dtype=float)
        picks = rng.integers(0, len(labels), (BOOTSTRAP, len(labels)))
        stats = sums[picks].sum(axis=1) / counts[picks].sum(axis=1)
    lo, hi = np.percentile(stats, [2.5, 97.5])
    return (float(math.sqrt(lo)), float(math.sqrt(hi))) if rms else (float(lo), float(hi))


def _size(d: Difference, reference: float) -> float:
    """What a difference does to a vector of the reference's size, in the calibrated unit: an offset itself, a
    scale's ppm × r, a cross term's or a rotation's angle (rad) × r."""
    if d.group == "offsets":
        return abs(d.value)
    if d.group == "scales":
        return abs(d.value) * 1e-6 * reference
    return math.radians(abs(d.value)) * reference


def _drifted(drift: SensorComparison, without: tuple[str, ...], tolerance: float) -> tuple[str, ...]:
    """The groups of the fresh fit's drift that are real (their interval excludes none) and matter (they move a
    vector of the reference's size by half the tolerance, and half the largest drift's move, or more), the largest
    first; else the group that moves it most. A drift smaller than half the largest is the current calibration's
    own error, not what changed."""
    reference = 1000.0 if drift.effect_unit == "mg" else drift.reference  # g in mg, or F
    considered = [d for d in drift.differences if d.group not in without]
    if not considered:
        return ()
    largest: dict[str, float] = {}
    for d in considered:
        largest[d.words] = max(largest.get(d.words, 0.0), _size(d, reference))
    floor = max(tolerance / 2, max(largest.values()) / 2)
    real = {d.words for d in considered if d.real and _size(d, reference) >= floor}
    named = sorted(real, key=lambda w: -largest[w])
    return tuple(named) if named else (max(largest, key=largest.__getitem__),)


def _identity(c: AffineCorrection) -> AffineCorrection:
    return AffineCorrection(np.eye(3), np.zeros(3), c.output_unit, c.output_unit, sensor=c.sensor)


Halves = tuple[np.ndarray | None, np.ndarray | None]


def _drift(correction: AffineCorrection, half: Halves, fit, **place) -> SensorComparison:
    """What drifted: the fresh fit made on the corrected readings against the identity (the current correction in
    that frame), with both calibrations' intervals, the current one's carried into it; ``place`` is the vector's
    size it is told at (``gravity``, or ``field_ut`` and ``inclination_deg``)."""
    fc = fit.correction
    fresh = AffineCorrection(fc.M, fc.o, correction.output_unit, correction.output_unit, sensor=correction.sensor)
    return compare_corrections(
        _identity(correction),
        fresh,
        half_a=_in_calibrated_frame(correction, half),
        half_b=correction_half_widths(fit).get(correction.sensor, (None, None)),
        **place,
    )


def _in_calibrated_frame(c: AffineCorrection, half: Halves) -> Halves:
    """The current correction's half-widths carried into the frame of its corrected readings, where the fresh fit
    is made (and the current correction is the identity): o's through M, ``|M| h_o``, and M's relative to M,
    ``|h_M| |M⁻¹|`` (first order, each entry bounded by the triangle inequality)."""
    hw_M, hw_o = half
    return (
        None if hw_M is None else np.abs(hw_M) @ np.abs(np.linalg.inv(c.M)),
        None if hw_o is None else np.abs(c.M) @ np.abs(hw_o),
    )


def _fresh_fit(a: np.ndarray, labels, g: float) -> tuple[StillReadingsResult, float]:
    """The fresh calibration of the corrected poses ``a`` and the factor its in-sample errors are scaled by to
    estimate its error on new poses, √(3N / (3N − p)) for the affine model of known orientations (p = 12) and
    √(N / (N − p)) for the nine-parameter model (p = 9): one equation a pose of unknown orientation, three of a
    known one."""
    n = len(a)
    if labels is not None and all(label is not None for label in labels):
        known = fit_orientations(a, list(labels), gravity=g, plausible_scale=None)
        return known, math.sqrt(3 * n / (3 * n - AFFINE_PARAMETERS))
    fit = fit_triangular(a, gravity=g, plausible_scale=None, max_offset=None)
    return fit, math.sqrt(n / (n - TRIANGULAR_PARAMETERS))


def check_still(
    correction: AffineCorrection,
    means,
    *,
    gravity: float | None = None,
    labels=None,
    half: Halves = (None, None),
) -> SensorCheck:
    """Check an accelerometer's correction on new still poses (module docstring).

    Parameters
    ----------
    correction : AffineCorrection
        The current calibration's accelerometer correction.
    means : array_like, shape (N, 3)
        The mean reading of each still pose, in the correction's input unit.
    gravity : float, optional
        Gravity in the calibrated unit (1 g, 9.80665 m/s² by the unit without it).
    labels : sequence of str, optional
        The axis up in each pose (``+x`` … ``-z``) where every pose has one: the fresh fit is then the affine
        model of known orientations (its orientation is then seen too), from :data:`MIN_LABELLED_POSES` poses.
    half : (M's half-widths or None, o's half-widths or None)
        The current correction's 95 % half-widths (:func:`app.calibration.compare.correction_half_widths`): a
        drift is real when it exceeds both calibrations' intervals, combined.

    Returns
    -------
    SensorCheck
    """
    m = as_vectors(means, "still poses")
    g = acc_reference(correction, gravity)
    unit, factor = calibrated_unit(correction, g)
    known = labels is not None and len(labels) == len(m) and all(label is not None for label in labels)
    least = MIN_LABELLED_POSES if known else MIN_POSES
    if len(m) < least:
        return SensorCheck(
            "acc",
            CANNOT,
            (
                f"{len(m)} still poses were found, and the check needs at least {least}: record the device "
                f"resting still for 2–3 s in each of {MIN_POSES} or more different orientations (tilted as well as "
                "on its faces), or on each of its six faces",
            ),
            len(m),
        )
    a = correction.apply(m)
    errors = factor * np.abs(np.linalg.norm(a, axis=1) - g)
    low, high = _bootstrap_mean(errors)
    value = float(errors.mean())
    current = Interval(value, low, high, unit, tilt_error_deg(value), tilt_error_deg(high))
    try:
        fit, inflation = _fresh_fit(a, labels if known else None, g)
    except CalibrationError as exc:
        return SensorCheck(
            "acc",
            CANNOT,
            (f"no fresh calibration fits these poses ({exc}): record still poses in more different orientations",),
            len(m),
            current,
            angle_kind="tilt",
        )
    fresh_errors = inflation * factor * np.abs(np.linalg.norm(fit.apply(a), axis=1) - g)
    f_low, f_high = _bootstrap_mean(fresh_errors)
    f_value = float(fresh_errors.mean())
    fresh = Interval(f_value, f_low, f_high, unit, tilt_error_deg(f_value), tilt_error_deg(f_high))
    drift = _drift(correction, half, fit, gravity=g)
    unseen = () if known else ("orientation",)
    return _finish("acc", current, fresh, drift, KEEP_TOLERANCE_MG, len(m), "tilt", unseen)


def _finish(
    sensor: str,
    current: Interval,
    fresh: Interval,
    drift: SensorComparison,
    tolerance: float,
    count: int,
    kind: str,
    without: tuple[str, ...],
) -> SensorCheck:
    angle = "a level" if kind == "tilt" else "a heading"
    told = (
        f"on these readings the current calibration leaves {angle} off by up to {current.value_deg:.2f}° (an error "
        f"of {current.value:.2f} {current.unit}, 95 % {current.low:.2f}–{current.high:.2f}), a fresh one "
        f"{fresh.value_deg:.2f}° ({fresh.value:.2f} {fresh.unit}, {fresh.low:.2f}–{fresh.high:.2f})"
    )
    if current.value <= tolerance or current.low <= fresh.high:
        why = "within the tolerance" if current.value <= tolerance else "within reach of a fresh calibration"
        return SensorCheck(
            sensor, KEEP, (f"{told}: {why}, keep it",), count, current, fresh, (), drift, angle_kind=kind
        )
    named = _drifted(drift, without, tolerance)
    what = ", ".join(named) if named else "the calibration"
    return SensorCheck(
        sensor,
        AGAIN,
        (f"{told}: the {what} drifted, calibrate again",),
        count,
        current,
        fresh,
        named,
        drift,
        angle_kind=kind,
    )


def check_turn(
    correction: AffineCorrection,
    mag,
    *,
    field_ut: float | None = None,
    inclination_deg: float | None = None,
    half: Halves = (None, None),
    rests=None,
    dip_deg: float | None = None,
) -> SensorCheck:
    """Check a compass's correction on the readings of a new turn (module docstring).

    Parameters
    ----------
    correction : AffineCorrection
        The current calibration's magnetometer correction (into µT).
    mag : array_like, shape (N, 3)
        The turn's raw readings, in the correction's input unit.
    field_ut : float, optional
        The place's field F (the geomagnetic model's, or the calibration's own); the median of the corrected
        readings' magnitude without it (said in the reasons).
    inclination_deg : float, optional
        The place's inclination, for the heading (60° assumed without it).
    half : (M's half-widths or None, o's half-widths or None)
        The current correction's 95 % half-widths, as :func:`check_still` takes them.
    rests : sequence of (acc_mean, mag_mean), optional
        Still moments of the device in the recording (the accelerometer's mean and the magnetometer's raw mean).
    dip_deg : float, optional
        The dip the field should show between them: the place's inclination, else the one the calibration measured.
        With ``rests``, the dip of the corrected field at each rest (:func:`_dips`) more than
        :data:`~app.calibration.magnetometer.fit.MAX_INCLINATION_ERROR_DEG` from it (RMS) names the compass's
        orientation against the accelerometer as drifted (a compass remounted, or a board bent).

    Returns
    -------
    SensorCheck
    """
    m = as_vectors(mag, "magnetometer readings")
    h = correction.apply(m)
    share, missing = coverage(h)
    if len(m) < MIN_READINGS or share < MIN_COVERAGE:
        return SensorCheck(
            "mag",
            CANNOT,
            (
                f"the turn reached {100 * share:.0f} % of the directions in {len(m)} readings (at least "
                f"{100 * MIN_COVERAGE:.0f} % in {MIN_READINGS} needed): turn the device slowly through all "
                f"directions for about 60 s{', still missing ' + ', '.join(missing) if missing else ''}",
            ),
            len(m),
        )
    norms = np.linalg.norm(h, axis=1)
    notes: tuple[str, ...] = ()
    F = field_ut
    if F is None:
        F = float(np.median(norms))
        notes = (f"no field for the place: the corrected readings' own median ({F:.1f}) was taken",)
    inc = ASSUMED_INCLINATION_DEG if inclination_deg is None else inclination_deg
    faces = face_of(h)
    errors = norms - F
    value = float(np.sqrt(np.mean(errors**2)))
    low, high = _bootstrap_mean(errors, faces, rms=True)
    unit, _ = calibrated_unit(correction)  # µT, or counts for a compass left in counts
    current = Interval(value, low, high, unit, heading_error_deg(value, F, inc), heading_error_deg(high, F, inc))
    fit = fit_magnetometer(h, field_ut=F if field_ut is not None else None, raw_comparable=True)
    metrics = fit.metrics
    own = float(np.linalg.det(fit.M)) ** (-1.0 / 3.0) * F if field_ut is not None else None
    fresh_norms = np.linalg.norm(fit.apply(h), axis=1) - metrics["field_ut"]
    fit_error = float(np.sqrt(np.mean(fresh_norms**2)))
    figure = fit.figure()  # its error on directions the fit did not see, where it has one
    cv = figure.after if figure.basis.endswith("on new directions") else None
    if (
        metrics["fit_stage"] != "refined"
        or metrics["norm_spread_ut"] > MAX_SPREAD * metrics["field_ut"]
        or (cv is not None and cv > MAX_FRESH_ERROR * metrics["field_ut"])
    ):
        fresh_words = "" if cv is None else f", and a fresh fit errs by {cv:.1f} {unit} on directions it did not see"
        return SensorCheck(
            "mag",
            MOVE,
            (
                *notes,
                f"no calibration fits this turn: the field's strength varies by {metrics['norm_spread_ut']:.1f} {unit} "
                f"(5–95 %) as the device turns{fresh_words} (at most {100 * MAX_SPREAD:.0f} % and "
                f"{100 * MAX_FRESH_ERROR:.0f} % of {metrics['field_ut']:.1f} {unit} where a calibration fits) — iron, "
                "magnets or current near the compass: move it away from them (or them from it) and check again",
            ),
            len(m),
            current,
            angle_kind="heading",
        )
    if own is not None and abs(own / F - 1.0) > MAX_SCALE_DEVIATION:
        return SensorCheck(
            "mag",
            MOVE,
            (
                f"the field here reads {own:.1f} µT where the place's is {F:.1f} µT (more than "
                f"{100 * MAX_SCALE_DEVIATION:.0f} % apart): a disturbed field — move away from steel and magnets, or "
                "check the place and date",
            ),
            len(m),
            current,
            angle_kind="heading",
        )
    fresh_errors = fresh_norms * (cv / fit_error) if cv is not None and fit_error > 0 else fresh_norms
    f_value = float(np.sqrt(np.mean(fresh_errors**2)))
    f_low, f_high = _bootstrap_mean(fresh_errors, faces, rms=True)
    fresh = Interval(
        f_value, f_low, f_high, unit, heading_error_deg(f_value, F, inc), heading_error_deg(f_high, F, inc)
    )
    drift = _drift(correction, half, fit, field_ut=F, inclination_deg=inc)
    out = _finish("mag", current, fresh, drift, KEEP_TOLERANCE_UT, len(m), "heading", ("orientation",))
    if not rests or dip_deg is None:
        return dataclasses.replace(out, reasons=notes + out.reasons)
    dips = _dips(rests, correction)
    off = float(np.sqrt(np.mean((dips - dip_deg) ** 2)))
    if off <= MAX_INCLINATION_ERROR_DEG:
        return dataclasses.replace(out, reasons=notes + out.reasons)
    turned = (
        f"where the device rested the field dips {np.min(dips):.1f}°–{np.max(dips):.1f}° under the horizontal, "
        f"{dip_deg:.1f}° expected ({off:.1f}° RMS apart, more than {MAX_INCLINATION_ERROR_DEG:.0f}°): the compass "
        "turned against the accelerometer (remounted, or the board bent) — calibrate again, the compass with the "
        "accelerometer at rest"
    )
    return dataclasses.replace(
        out,
        verdict=AGAIN,
        reasons=(*notes, *out.reasons, turned) if out.verdict == AGAIN else (*notes, turned),
        drifted=(*out.drifted, "orientation"),
    )


def check_rest(correction: AffineCorrection, gyr) -> SensorCheck:
    """Check a gyroscope's bias on a new rest: the mean corrected rate (°/s), with a Student-t interval over ten
    blocks of the rest; kept when the interval holds zero or the bias is within :data:`KEEP_TOLERANCE_DPS`.

    Parameters
    ----------
    correction : AffineCorrection
        The current calibration's gyroscope correction.
    gyr : array_like, shape (N, 3)
        The gyroscope's readings while the device rested, in the correction's input unit.
    """
    w = as_vectors(gyr, "gyroscope readings")
    if len(w) < MIN_REST_SAMPLES:
        return SensorCheck(
            "gyr",
            CANNOT,
            (
                f"{len(w)} gyroscope readings at rest, at least {MIN_REST_SAMPLES} needed: leave the device still "
                "for 10 s",
            ),
            len(w),
        )
    _, factor = calibrated_unit(correction)
    rates = factor * correction.apply(w)
    blocks = np.array([b.mean(axis=0) for b in np.array_split(rates, 10)])
    bias = blocks.mean(axis=0)
    hw = t_quantile(len(blocks) - 1) * blocks.std(axis=0, ddof=1) / math.sqrt(len(blocks))
    size = float(np.linalg.norm(bias))
    told = (
        f"the gyroscope's residual bias is {size:.3f} °/s (x {bias[0]:+.3f} ± {hw[0]:.3f}, y {bias[1]:+.3f} ± "
        f"{hw[1]:.3f}, z {bias[2]:+.3f} ± {hw[2]:.3f})"
    )
    current = Interval(size, max(0.0, size - float(np.linalg.norm(hw))), size + float(np.linalg.norm(hw)), "°/s")
    if bool(np.all(np.abs(bias) <= hw)) or size <= KEEP_TOLERANCE_DPS:
        return SensorCheck("gyr", KEEP, (f"{told}: keep it",), len(w), current)
    return SensorCheck(
        "gyr", AGAIN, (f"{told}: the biases drifted, calibrate again",), len(w), current, None, ("biases",)
    )


def check(
    result: CalibrationResult,
    *,
    still_means=None,
    labels=None,
    mag=None,
    rests=None,
    gyr_rest=None,
    field_ut: float | None = None,
    inclination_deg: float | None = None,
) -> CheckResult:
    """Check a calibration on new readings, sensor by sensor (module docstring).

    Parameters
    ----------
    result : CalibrationResult
        Any calibration with corrections (:meth:`~CalibrationResult.corrections`).
    still_means : array_like, shape (N, 3), optional
        The accelerometer's still poses (their means), in the result's unit.
    labels : sequence of str, optional
        The axis up in each still pose, where each is known (:func:`check_still`).
    mag : array_like, shape (N, 3), optional
        A turn's magnetometer readings.
    rests : sequence of (acc_mean, mag_mean), optional
        Still moments of the turn, for the compass's orientation against the accelerometer (:func:`check_turn`): its
        dip set against the place's inclination, else the one the calibration measured.
    gyr_rest : array_like, shape (N, 3), optional
        The gyroscope at rest.
    field_ut, inclination_deg : float, optional
        The place's field and inclination (a compass result's own ``field_ut`` without them).

    Returns
    -------
    CheckResult

    Raises
    ------
    CalibrationError
        When the result corrects none of the sensors the readings hold.
    """
    corrections = result.corrections()
    given = {"acc": still_means, "mag": mag, "gyr": gyr_rest}
    sensors = [s for s, v in given.items() if v is not None and s in corrections]
    if not sensors:
        held = [s for s, v in given.items() if v is not None]
        raise CalibrationError(
            f"the recording holds {', '.join(held) or 'no readings'} and the calibration corrects "
            f"{', '.join(corrections) or 'nothing'}: check it on a recording of a sensor it corrects"
        )
    checks: list[SensorCheck] = []
    halves = correction_half_widths(result)
    if "acc" in sensors:
        gravity = result.gravity if result.unit != "raw" and isinstance(result.gravity, (int, float)) else None
        checks.append(
            check_still(
                corrections["acc"], still_means, gravity=gravity, labels=labels, half=halves.get("acc", (None, None))
            )
        )
    if "mag" in sensors:
        field = field_ut
        if field is None:
            own = result.metrics.get("field_ut") if isinstance(result.metrics, dict) else None
            field = float(own) if isinstance(own, (int, float)) else None
        checks.append(
            check_turn(
                corrections["mag"],
                mag,
                field_ut=field,
                inclination_deg=inclination_deg,
                half=halves.get("mag", (None, None)),
                rests=rests,
                dip_deg=inclination_deg if inclination_deg is not None else _measured_dip(result),
            )
        )
    if "gyr" in sensors:
        checks.append(check_rest(corrections["gyr"], gyr_rest))
    return combined(checks)


def _dips(rests, correction: AffineCorrection) -> np.ndarray:
    """The dip of the corrected field under the horizontal at each rest: the angle between the accelerometer's up
    and the field is 90° + I (:func:`app.calibration.magnetometer.fit.measured_inclination`, rest by rest). A compass
    that turned against the accelerometer reads a dip that changes with the attitude; one that did not, the same."""
    return np.array([measured_inclination([rest], correction.M, correction.o) for rest in rests], dtype=float)


def _measured_dip(result: CalibrationResult) -> float | None:
    """The dip a compass calibration measured between its accelerometer's rests and its field, where it did."""
    dip = result.metrics.get("measured_inclination_deg") if isinstance(result.metrics, dict) else None
    return float(dip) if isinstance(dip, (int, float)) else None


def combined(checks) -> CheckResult:
    """The device's check from its sensors' (at least one): its verdict the worst that tells (:data:`SEVERITY`)."""
    checks = tuple(checks)
    return CheckResult(max((c.verdict for c in checks), key=SEVERITY.__getitem__), checks)


__all__ = [
    "AGAIN",
    "CANNOT",
    "KEEP",
    "MOVE",
    "VERDICTS",
    "VERDICT_WORDS",
    "CheckResult",
    "SensorCheck",
    "check",
    "check_rest",
    "check_still",
    "check_turn",
    "combined",
]
