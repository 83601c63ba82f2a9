"""The compass calibration: ``h = M (m − b)`` from a device turned in all directions.

Stages: the readings are checked (:func:`_validated`), the algebraic ellipsoid starts the fit
(:mod:`.ellipsoid`), Levenberg–Marquardt refines it on the field's magnitude (:mod:`.refine`; a
refinement that runs away from the readings is dropped for a closed form, :func:`_kept`), and the
result is judged by what a person gets: whether the readings leave one plane, the spread of |h|, the
directions covered (:mod:`.coverage`), the error on directions left out of the fit
(:func:`cross_validated_field_error`), the dip angle against the geomagnetic model when the
accelerometer rested (:func:`measured_inclination`), and the parameters' intervals (:func:`_gates`).
"""

from __future__ import annotations

import numpy as np

from ..shared.errors import CalibrationError, InsufficientDataError
from ..shared.gates import Gates
from ..shared.uncertainty import CONFIDENCE, half_widths
from .coverage import coverage, face_of, thickness
from .ellipsoid import fit_ellipsoid, fit_sphere
from .refine import STRUCTURES, Refined, held, refine, runs_away, unpack
from .result import MagnetometerResult

MIN_READINGS = 50
"""Fewest readings a compass calibration takes: five seconds of a slow turn at 10 Hz."""

MIN_COVERAGE = 0.75
"""Share of the 20 directions (:mod:`.coverage`) a turn must reach: 15 faces. A turn that keeps the
device flat, or the screen up, reaches a hemisphere (12 faces), where the ellipsoid is free to bulge."""

MIN_THICKNESS = 0.1
"""The readings' :func:`.coverage.thickness` below 0.1 (they leave their best plane by less than a tenth
of their width, a ring tilted by about 7° at most): the device was turned round flat, and the ellipsoid
across that plane is not determined (a hemisphere reaches 0.4, a full turn 0.65 or more)."""

MAX_SPREAD = 0.10
"""A 5–95 % range of |h| above 10 % of the field: the field changed while the device turned (steel,
magnets, a laptop), or the model does not fit."""

MAX_OFFSET_HALF_WIDTH = 0.05
"""A 95 % half-width of b above 5 % of the field: the hard iron is not determined."""

MAX_MATRIX_HALF_WIDTH = 0.05
"""A 95 % half-width of an entry of M above 5 % of M's mean diagonal: the soft iron is not determined."""

MAX_INCLINATION_ERROR_DEG = 5.0
"""The dip of the calibrated field under the horizontal, measured from the accelerometer's rests,
more than 5° from the model's: a disturbed field (Särkkä et al.'s α plays this role in the cube)."""

MAX_SCALE_DEVIATION = 0.15
"""The readings' own field more than 15 % from the one asked for: said in a warning."""

CV_READINGS_MAX = 3000
"""The cross-validation refits on at most this many readings, evenly spaced in time."""

SAMPLES_SHOWN = 600
"""Readings kept with the result for drawing the sphere, evenly spaced in time."""

FIELD_SOURCES = ("given", "model", "estimated")

MAX_CENTRE_DISAGREEMENT = 0.5
"""Where the refinement runs away, the closed-form ellipsoid is kept only if its centre lies within half
the readings' half-extent of the sphere's: 0.09 and 0.13 on the flat and the disturbed real turns of
``tests/data/real/corpus``, 2.0 on an iPhone's 1.7 s arc, where the ellipsoid is another surface
through the arc rather than the sphere reshaped."""

NO_CROSS_VALIDATION = {
    "cv_error_ut": None,
    "cv_error_max_ut": None,
    "cv_scheme": "leave-one-direction-out",
    "cv_note": "no figure for new directions: no ellipsoid fits the readings, so none can be "
    "refitted without a direction",
}

FIT_STAGES = {
    "refined": "the refined fit's",
    "closed form": "the closed-form ellipsoid's",
    "sphere": "the sphere's (hard iron only)",
    "centre": "the readings' own centre's",
}
"""What ``h = M (m − b)`` of a result is: the refinement, or (when it ran away from the readings) the
closed-form ellipsoid, the sphere or the readings' own centre (:func:`_kept`), in the reason's words."""


STRUCTURE_WORDS = {
    "scale": "the readings do not determine the full ellipsoid, so the offsets and a scale per axis were fitted "
    "and the axes' cross terms held at 0: turn the device through all directions, tilted as well as level, for "
    "the soft iron's cross terms",
    "sphere": "the readings determine no ellipsoid, so the offsets and one scale were fitted (a sphere, as "
    "ArduPilot's compass calibration fits first), the soft iron held at none: turn the device through all "
    "directions, tilted as well as level, for the soft iron",
    "offsets": "the readings determine no ellipsoid nor sphere, so the offsets alone were fitted, the readings' "
    "scale taken as right and the soft iron held at none: turn the device through all directions, tilted as well "
    "as level, for the scale and the soft iron",
}
"""The warning of a result whose readings determined a simpler model than the full ellipsoid (:func:`_model`)."""


def _validated(mag) -> np.ndarray:
    m = np.asarray(mag, dtype=float)
    if m.ndim != 2 or m.shape[1] != 3:
        raise CalibrationError(f"magnetometer readings must be N×3 (x, y, z); got shape {m.shape}")
    if not np.all(np.isfinite(m)):
        raise CalibrationError("magnetometer readings contain NaN or infinite values: drop those rows")
    if len(m) < MIN_READINGS:
        raise InsufficientDataError(
            f"{len(m)} magnetometer readings: a compass calibration needs at least {MIN_READINGS}, spread over all "
            "directions — turn the device slowly through every direction for 30 s or more"
        )
    if np.ptp(m, axis=0).max() == 0.0:
        raise InsufficientDataError("the magnetometer readings do not change: turn the device through all directions")
    return m


def _start(m: np.ndarray, field: float, gates: Gates) -> tuple[np.ndarray, np.ndarray, str]:
    """The algebraic ellipsoid, or the sphere when the readings do not determine an ellipsoid."""
    try:
        return (*fit_ellipsoid(m, field), "closed form")
    except CalibrationError:
        gates.warn("the readings do not determine an ellipsoid on their own; the fit started from a sphere")
        return (*fit_sphere(m, field), "sphere")


def _kept(m: np.ndarray, M0: np.ndarray, b0: np.ndarray, stage: str, field: float) -> tuple[Refined, str]:
    """What stands when the refinement runs away (the readings determine no ellipsoid): the closed-form
    ellipsoid where it stays with the readings (:func:`.refine.runs_away`) and its centre agrees with
    the sphere's (:data:`MAX_CENTRE_DISAGREEMENT`: the soft iron then only reshapes the sphere), else
    the sphere (hard iron only: 4 numbers, ArduPilot's first step before its ellipsoid), else the
    readings' own centre with their RMS radius.  On an iPhone's short arc the closed-form ellipsoid
    bends round the arc, 35 µT from the sphere's centre, which is iOS's own hard iron within 3 µT
    (``tests/api/test_real_magnetometer.py``)."""
    M_s, b_s = fit_sphere(m, field)
    sphere_kept = not runs_away(M_s, b_s, m, field)
    if stage != "sphere" and not runs_away(M0, b0, m, field):
        half = 0.5 * float(np.ptp(m, axis=0).max())
        if not sphere_kept or np.linalg.norm(b0 - b_s) <= MAX_CENTRE_DISAGREEMENT * half:
            return held(m, M0, b0, field), stage
    if sphere_kept:
        return held(m, M_s, b_s, field), "sphere"
    centre = m.mean(axis=0)
    radius = float(np.sqrt(np.mean(np.sum((m - centre) ** 2, axis=1))))
    return held(m, (field / radius) * np.eye(3), centre, field), "centre"


def _determined(fitted: Refined, field: float) -> bool:
    """Whether a refined fit's 95 % intervals are within the gates' limits (:data:`MAX_OFFSET_HALF_WIDTH`,
    :data:`MAX_MATRIX_HALF_WIDTH`): the readings determine every number it fits."""
    if fitted.covariance is None or not fitted.converged:
        return False
    half_M, half_b = unpack(half_widths(fitted.covariance, fitted.dof, CONFIDENCE))
    scale = float(np.mean(np.diag(fitted.M)))
    return bool(np.max(half_b) <= MAX_OFFSET_HALF_WIDTH * field and np.max(half_M) <= MAX_MATRIX_HALF_WIDTH * scale)


def _model(m: np.ndarray, full: Refined, M0: np.ndarray, b0: np.ndarray, stage: str, field: float, given: bool):
    """The richest model of :data:`.refine.STRUCTURES` the readings determine (:func:`_determined`): the full
    ellipsoid, else a scale per axis, else a sphere, else (with the field given) the offsets alone, each refined
    from the sphere and staying with the readings (:func:`.refine.runs_away`); where none is determined, the
    richest that stays with them (its gates then say what is not determined), else a closed form (:func:`_kept`).

    Returns ``(fitted, stage, structure)``."""
    stays = [] if runs_away(full.M, full.b, m, field) else [(full, STRUCTURES[0])]
    if stays and _determined(full, field):
        return full, "refined", STRUCTURES[0]
    M_s, b_s = fit_sphere(m, field)
    # the offsets alone take the readings' unit as the field's: not where the field is the readings' own
    for structure in STRUCTURES[1:] if given else STRUCTURES[1:-1]:
        fitted = refine(m, M_s, b_s, field, structure=structure)
        if fitted.converged and fitted.covariance is not None and not runs_away(fitted.M, fitted.b, m, field):
            if _determined(fitted, field):
                return fitted, "refined", structure
            stays.append((fitted, structure))
    if stays:
        return stays[0][0], "refined", stays[0][1]
    kept, stage = _kept(m, M0, b0, stage, field)
    return kept, stage, STRUCTURES[0]


def _fit(m: np.ndarray, field: float | None, gates: Gates) -> tuple[Refined, float, str, str]:
    """The refined fit, the field's magnitude (given, or estimated with ``det M = 1``), the stage kept
    (:data:`FIT_STAGES`) and the model's structure (:data:`.refine.STRUCTURES`).

    Without a field the scale of M is free (any F fits with M scaled by F); trical fixes it so that
    M changes no volume (``det M = 1``), and F is then the readings' own mean field.  A refinement
    that runs away from the readings (:func:`.refine.runs_away`: the criterion has no minimum there)
    is not a result, nor one whose intervals the readings do not bound: the richest simpler model they determine
    is refined instead (:func:`_model`: a scale per axis, then the offsets alone, as a flight's readings near
    level often allow), else a closed form is kept (:func:`_kept`), with no intervals.
    """
    unit_field = 1.0 if field is None else field
    M0, b0, stage = _start(m, unit_field, gates)
    fitted, stage, structure = _model(m, refine(m, M0, b0, unit_field), M0, b0, stage, unit_field, field is not None)
    if field is None:
        first = fitted
        scale = float(np.linalg.det(first.M)) ** (-1.0 / 3.0)
        field = scale
        again = refine(m, scale * first.M, first.b, field, structure=structure) if stage == "refined" else None
        if again is None or runs_away(again.M, again.b, m, field):
            again = held(m, scale * first.M, first.b, field)
        fitted = again
    return fitted, float(field), stage, structure


def _spread(values: np.ndarray) -> float:
    lo, hi = np.percentile(values, [5.0, 95.0])
    return float(hi - lo)


def cross_validated_field_error(mag, M: np.ndarray, b: np.ndarray, field: float, structure: str = "soft_iron") -> dict:
    """The error of |h| on directions the fit did not see: each covered face left out in turn.

    The readings are grouped by the face of the icosahedron their calibrated direction falls in
    (:mod:`.coverage`); each group is calibrated by the fit made without it (started from the full
    fit), and ``| |h| − F |`` there is what a person gets when the device points that way.

    Returns
    -------
    dict
        ``cv_error_ut`` (RMS over the readings), ``cv_error_max_ut`` (RMS of the worst face),
        ``cv_scheme``; None figures with ``cv_note`` when a fit without a face is undetermined.
    """
    m = np.asarray(mag, dtype=float)
    m = m[:: max(1, int(np.ceil(len(m) / CV_READINGS_MAX)))]
    faces = face_of((m - b) @ M.T)
    squared = np.empty(len(m))
    worst = 0.0
    for face in np.unique(faces):
        held = faces == face
        kept = m[~held]
        if len(kept) < MIN_READINGS:
            return {
                "cv_error_ut": None,
                "cv_error_max_ut": None,
                "cv_scheme": "leave-one-direction-out",
                "cv_note": "no figure for new directions: too few readings outside one direction",
            }
        refit = refine(kept, M, b, field, max_evaluations=50, structure=structure)
        e = np.linalg.norm((m[held] - refit.b) @ refit.M.T, axis=1) - field
        squared[held] = e * e
        worst = max(worst, float(np.sqrt(np.mean(e * e))))
    return {
        "cv_error_ut": float(np.sqrt(squared.mean())),
        "cv_error_max_ut": worst,
        "cv_scheme": "leave-one-direction-out (20 icosahedron faces)",
    }


def measured_inclination(rests, M: np.ndarray, b: np.ndarray) -> float | None:
    """The dip of the calibrated field under the horizontal, from still moments of the accelerometer.

    At rest the accelerometer reads the specific force, which points up; the field dips by the
    inclination I below the horizontal, so the angle between them is 90° + I.

    Parameters
    ----------
    rests : sequence of (acc_mean, mag_mean), or None
        Mean accelerometer (any unit) and raw magnetometer reading of each still moment.

    Returns
    -------
    float or None
        The median over the rests, in degrees; None without rests.
    """
    if not rests:
        return None
    angles = []
    for acc, mag in rests:
        up = np.asarray(acc, dtype=float)
        h = M @ (np.asarray(mag, dtype=float) - b)
        cos = float(up @ h / (np.linalg.norm(up) * np.linalg.norm(h)))
        angles.append(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))) - 90.0)
    return float(np.median(angles))


def _gates(
    metrics: dict,
    fitted: Refined,
    half_M: np.ndarray | None,
    half_b: np.ndarray | None,
    raw_comparable: bool,
    gates: Gates,
    label: str = "µT",
) -> None:
    field = metrics["field_ut"]
    if metrics["thickness"] < MIN_THICKNESS:
        gates.fail(
            f"the readings lie in one plane (they leave it by {100 * metrics['thickness']:.0f} % of their "
            "width): the device was turned round flat, which leaves the hard and soft iron across that plane "
            "undetermined — turn it over too, through all directions, not only round on a table"
        )
    if metrics["fit_stage"] != "refined":
        gates.fail(
            f"no ellipsoid fits these readings: the least-squares fit runs away from them (its centre and "
            f"one axis grow without bound), so the hard and soft iron are not determined and the b and M "
            f"shown are {FIT_STAGES[metrics['fit_stage']]}, to draw the readings only — turn the device "
            "slowly through all directions, away from steel and magnets, and try again"
        )
    if metrics["coverage"] < MIN_COVERAGE:
        gates.fail(
            f"the turn covered {100 * metrics['coverage']:.0f} % of the directions (at least "
            f"{100 * MIN_COVERAGE:.0f} % needed): still missing {', '.join(metrics['missing_directions'])} — "
            "turn the device so that each of these points at the ground in turn"
        )
    if metrics["norm_spread_ut"] > MAX_SPREAD * field:
        gates.fail(
            f"the calibrated field's magnitude spreads over {metrics['norm_spread_ut']:.1f} {label} (5–95 %), more "
            f"than {100 * MAX_SPREAD:.0f} % of {field:.1f} {label}: the field changed while the device turned (steel, "
            "magnets, a laptop or a phone case nearby) — move away from them and turn it again"
        )
    if metrics["fit_stage"] != "refined":
        pass  # the runaway above says it: no intervals without a minimum
    elif half_b is None or half_M is None:
        gates.fail("the fit is not determined (no intervals): turn the device through all directions")
    else:
        if np.max(half_b) > MAX_OFFSET_HALF_WIDTH * field:
            gates.fail(
                f"the hard iron b is not determined: its 95 % interval is ±{np.max(half_b):.1f} {label} (limit "
                f"{MAX_OFFSET_HALF_WIDTH * field:.1f} {label}) — turn the device through more directions"
            )
        scale = float(np.mean(np.diag(fitted.M)))
        if np.max(half_M) > MAX_MATRIX_HALF_WIDTH * scale:
            gates.fail(
                f"the soft iron M is not determined: an entry's 95 % interval is ±{np.max(half_M):.3f} "
                f"(limit {MAX_MATRIX_HALF_WIDTH * scale:.3f}) — turn the device through more directions"
            )
    cv, raw = metrics["cv_error_ut"], metrics["raw_error_ut"]
    if raw_comparable and cv is not None and raw is not None and cv >= raw:
        gates.fail(
            f"the calibration would not help: on directions left out of the fit its error is {cv:.2f} {label}, "
            f"the readings as they are err by {raw:.2f} {label} — the sensor is already calibrated (use its readings "
            "as they are)"
        )
    measured, model = metrics["measured_inclination_deg"], metrics["inclination_deg"]
    if measured is not None and model is not None and abs(measured - model) > MAX_INCLINATION_ERROR_DEG:
        gates.fail(
            f"the field dips {measured:.1f}° under the horizontal where the device rested, the Earth's field "
            f"{model:.1f}° here: a disturbed field (steel, magnets, electronics nearby) — calibrate away from "
            "them"
        )


def fit_magnetometer(
    mag,
    *,
    field_ut: float | None = None,
    field_source: str | None = None,
    inclination_deg: float | None = None,
    declination_deg: float | None = None,
    rests=None,
    raw_comparable: bool = True,
    label: str = "µT",
) -> MagnetometerResult:
    """Calibrate a magnetometer from readings taken while the device turned through all directions.

    Parameters
    ----------
    mag : array_like, shape (N, 3)
        Raw readings in recording order, N ≥ :data:`MIN_READINGS`; µT when ``field_ut`` is in µT.
    field_ut : float, optional
        The local field's magnitude F: given by the user, or the geomagnetic model's at the place and
        date. Without it F is estimated (``det M = 1``) and a warning says so.
    field_source : {"given", "model", "estimated"}, optional
        Where F comes from (``estimated`` when ``field_ut`` is None).
    inclination_deg, declination_deg : float, optional
        The model's dip and declination at the place, reported and checked against ``rests``.
    rests : sequence of (acc_mean, mag_mean), optional
        Still moments of the accelerometer during the turn (:func:`measured_inclination`).
    raw_comparable : bool
        Whether the raw readings are in the unit of F (µT): then the calibration must beat them on
        directions it did not see, else ``ok`` is false.
    label : str
        The unit the messages name: ``µT``, or ``counts`` for readings in counts whose field is
        estimated (the fit's figures are then in counts).

    Returns
    -------
    MagnetometerResult
        ``h = M (m − b)`` with M symmetric, 95 % half-widths of M and b, the metrics and gates.

    Raises
    ------
    InsufficientDataError
        Fewer than :data:`MIN_READINGS` readings, or readings that do not change.
    CalibrationError
        Readings that are not N×3 finite numbers.
    """
    m = _validated(mag)
    gates = Gates()
    source = "estimated" if field_ut is None else (field_source or "given")
    if source not in FIELD_SOURCES:
        raise CalibrationError(f"field_source must be one of {', '.join(FIELD_SOURCES)}; got {source!r}")
    fitted, field, stage, structure = _fit(m, field_ut, gates)
    if structure != STRUCTURES[0]:
        gates.warn(STRUCTURE_WORDS[structure])
    if field_ut is None:
        gates.warn(
            f"no place and date, so the field's magnitude is estimated from the readings ({field:.1f} {label}, M "
            "scaled to change no volume): give `date`, latitude_deg and longitude_deg (or field_ut) for the "
            "Earth's field there"
        )
    M, b = fitted.M, fitted.b
    h = (m - b) @ M.T
    norms = np.linalg.norm(h, axis=1)
    share, missing = coverage(h)
    half_M: np.ndarray | None
    half_b: np.ndarray | None
    if fitted.covariance is not None:
        half_M, half_b = unpack(half_widths(fitted.covariance, fitted.dof, CONFIDENCE))
    else:
        half_M = half_b = None
    raw_norms = np.linalg.norm(m, axis=1)
    metrics = {
        "field_ut": field,
        "field_source": source,
        "inclination_deg": inclination_deg,
        "declination_deg": declination_deg,
        "norm_spread_ut": _spread(norms),
        "norm_spread_raw_ut": _spread(raw_norms),
        "coverage": share,
        "missing_directions": missing,
        "thickness": thickness(m),
        "fit_stage": stage,
        "structure": structure,
        "count": int(len(m)),
        "fit_error_ut": float(np.sqrt(np.mean((norms - field) ** 2))),
        "raw_error_ut": float(np.sqrt(np.mean((raw_norms - field) ** 2))) if raw_comparable else None,
        "noise_ut": fitted.sigma_ut,
        "correlation_inflation": fitted.inflation,
        **(cross_validated_field_error(m, M, b, field, structure) if stage == "refined" else NO_CROSS_VALIDATION),
        "measured_inclination_deg": measured_inclination(rests, M, b),
        "rests": 0 if not rests else len(rests),
    }
    if field_ut is not None:
        own = float(np.linalg.det(M)) ** (-1.0 / 3.0) * field
        if abs(own / field - 1.0) > MAX_SCALE_DEVIATION:
            gates.warn(
                f"the readings' own field is about {own:.1f} {label} where {field:.1f} {label} was asked for: "
                "check the magnetometer's unit, or the place and date"
            )
    if stage == "refined" and not fitted.converged:
        gates.fail("the fit did not converge: turn the device slowly through all directions and try again")
    _gates(metrics, fitted, half_M, half_b, raw_comparable, gates, label)
    shown = m[:: max(1, int(np.ceil(len(m) / SAMPLES_SHOWN)))]
    return MagnetometerResult(
        M=M, b=b, covariance=fitted.covariance, dof=fitted.dof, metrics=metrics, samples=shown, **gates.fields()
    )


__all__ = ["cross_validated_field_error", "fit_magnetometer", "measured_inclination"]
