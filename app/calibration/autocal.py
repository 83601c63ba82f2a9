"""Auto-calibration of a long recording by the pipeline of Farago, Maczak and Gingl, IEEE Access
(section II.B, evaluation III.B).

Farago, Maczak and Gingl, IEEE Access:

1. **Rest segments** (section II.B.1): fixed 5 s segments whose max − min on one axis stays below
   0.12 g; NaN gaps and idle-sleep runs are refused (:mod:`app.calibration.segments.stationary_002`).
2. **Selection** (eq. (10)): each axis is split into [−1.25, −0.75], [−0.25, 0.25] and
   [0.75, 1.25] g, giving nine subsets C_xn … C_zp; each must hold between ``min_per_bin`` and
   ``max_per_bin`` points (2 and 2 → 18 points in the paper).  Figure 6, the paper's exact rule for
   accepting a point, is not in the text; trical's reading (the same as
   :func:`simulations.triangular.select_points`, plus the distance test the text describes):
   the rest segments are taken in time order, as a device would see them; a segment's mean joins
   the first subset, in the order x, y, z, that it falls in and that holds fewer than
   ``max_per_bin`` points — provided it lies at least ``min_distance`` (0.1 g) from every point
   already chosen ("if the deviation is sufficient", section II.B.1).  Scanning stops when every
   subset is full.
3. **Control set** (section III.B): a second, distinct set selected by the same rule from the rest
   segments not chosen for calibration.
4. **Fit** of the 9-parameter model ``a = K (v + o)`` (eqs. (6)–(9)) with
   :func:`app.calibration.still.triangular.fit_triangular` and any of its solvers.
5. **Held-out evaluation** (section III.B, Table 3): the mean of | |r| − 1 g | over the control
   points before and after, in mg, and the improvement R of eq. (21) in per cent.
6. **Comparison** on the same points and control set, like Table 3: the non-iterative ellipsoid fit
   (Farago, Maczak and Gingl, IEEE Access, ref. [34]) and the van Hees / GGIR sphere fit, the latter
   also on its own 10 s windows
   (:mod:`app.calibration.still.comparison`).

A recording that cannot be calibrated (no rest, rest in only one orientation, subsets left empty)
returns an :class:`AutoCalibration` with ``ok = False``, the identity model when no fit was possible,
and reasons that name what was missing — never a silent bad calibration.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .segments.stationary_002 import RestSegments, detect_rest_segments
from .shared.errors import CalibrationError
from .shared.gates import Gates
from .shared.norm_metrics import norm_errors
from .shared.result import (
    CalibrationResult,
    Figure,
    cv_figure,
    first_figure,
    gate_fields,
    holdout_figure,
    in_sample_figure,
)
from .still.comparison import fit_ellipsoid_axes, fit_sphere_van_hees
from .still.cross_validation import cross_validated_error
from .still.triangular import SOLVERS, TriangularCalibration, fit_triangular
from .still.trust import worse_than_raw

MODEL_TYPE = "triangular"
METHOD = "autocal"

BIN_EDGES_G = ((-1.25, -0.75), (-0.25, 0.25), (0.75, 1.25))
"""The three intervals of each axis, in g (Farago, Maczak and Gingl, IEEE Access, eq. (10))."""
BIN_NAMES = tuple(f"C_{a}{j}" for a in "xyz" for j in "n0p")
"""C_xn, C_x0, C_xp, C_yn, ... (Farago, Maczak and Gingl, IEEE Access, eq. (10)); bin b = 3·axis + interval."""

MIN_PER_BIN = 2
MAX_PER_BIN = 2
MIN_DISTANCE_G = 0.1
ONE_ORIENTATION_DEG = 20.0
"""Rest whose directions all lie within this angle of their mean is rest in one orientation."""


@dataclass(frozen=True)
class Selection:
    """Points chosen into the nine subsets of Farago, Maczak and Gingl, IEEE Access, eq. (10).

    Attributes
    ----------
    indices : numpy.ndarray of int
        Indices of the chosen candidates, in the order they were accepted.
    bins : numpy.ndarray of int
        Subset of each chosen point, ``3·axis + interval`` (names in :data:`BIN_NAMES`).
    counts : numpy.ndarray, shape (3, 3)
        Points per subset [axis, interval].
    min_per_bin, max_per_bin : int
    """

    indices: np.ndarray
    bins: np.ndarray
    counts: np.ndarray
    min_per_bin: int
    max_per_bin: int

    @property
    def short_bins(self) -> list[str]:
        """Names of the subsets holding fewer than ``min_per_bin`` points."""
        return [BIN_NAMES[b] for b in range(9) if self.counts.flat[b] < self.min_per_bin]

    @property
    def complete(self) -> bool:
        return not self.short_bins

    def to_dict(self) -> dict:
        return {BIN_NAMES[b]: int(self.counts.flat[b]) for b in range(9)}


def bin_of(points_g: np.ndarray) -> np.ndarray:
    """Interval of each coordinate (0 n, 1 zero, 2 p, −1 none), shape (N, 3), points in g (eq. (10))."""
    out = np.full(points_g.shape, -1, dtype=np.int8)
    for j, (lo, hi) in enumerate(BIN_EDGES_G):
        out[(points_g >= lo) & (points_g <= hi)] = j
    return out


def select_points(
    means,
    *,
    gravity: float = 1.0,
    min_per_bin: int = MIN_PER_BIN,
    max_per_bin: int = MAX_PER_BIN,
    min_distance_g: float = MIN_DISTANCE_G,
    exclude=None,
) -> Selection:
    """Choose calibration points into the nine subsets of Farago, Maczak and Gingl, IEEE Access, eq.
    (10) (module docstring, step 2).

    Parameters
    ----------
    means : array_like, shape (N, 3)
        Candidate points (rest-segment means) in time order, in the unit of ``gravity``.
    gravity : float
        Reference magnitude; the subsets and the distance are in g.
    min_per_bin, max_per_bin : int
        Bounds per subset (2 and 2 in Farago, Maczak and Gingl, IEEE Access).
    min_distance_g : float
        Smallest distance of a new point from those already chosen, in g (Figure 6 is not in the
        text; 0.1 g by default).
    exclude : array_like of int, optional
        Candidates not to choose (e.g. the calibration set, when choosing the control set).

    Returns
    -------
    Selection
    """
    if not (
        isinstance(min_per_bin, (int, np.integer))
        and isinstance(max_per_bin, (int, np.integer))
        and 1 <= min_per_bin <= max_per_bin
    ):
        raise CalibrationError(
            f"min_per_bin and max_per_bin must be integers with 1 ≤ min ≤ max; got {min_per_bin}, {max_per_bin}"
        )
    if not (math.isfinite(min_distance_g) and min_distance_g >= 0):
        raise CalibrationError(f"min_distance_g must be a non-negative number; got {min_distance_g!r}")
    v = np.asarray(means, dtype=float).reshape(-1, 3) / float(gravity)
    bins = bin_of(v)
    usable = np.asarray((bins >= 0).any(axis=1))
    if exclude is not None and len(exclude):
        usable[np.asarray(exclude, dtype=int)] = False
    counts = np.zeros((3, 3), dtype=int)
    chosen: list[int] = []
    chosen_bins: list[int] = []
    pts: list[tuple] = []
    d2min = float(min_distance_g) ** 2
    for i in np.flatnonzero(usable).tolist():  # time order, as a device sees them
        row = bins[i]
        target = -1
        for axis in range(3):
            j = row[axis]
            if j >= 0 and counts[axis, j] < max_per_bin:
                target = 3 * axis + int(j)
                break
        if target < 0:
            continue
        x, y, z = v[i]
        # "checked to determine if it differs from the previously collected calibration points"
        if any((x - a) ** 2 + (y - b) ** 2 + (z - c) ** 2 < d2min for a, b, c in pts):
            continue
        counts[target // 3, target % 3] += 1
        chosen.append(i)
        chosen_bins.append(target)
        pts.append((x, y, z))
        if counts.min() >= max_per_bin:
            break
    return Selection(
        indices=np.array(chosen, dtype=int),
        bins=np.array(chosen_bins, dtype=int),
        counts=counts,
        min_per_bin=int(min_per_bin),
        max_per_bin=int(max_per_bin),
    )


def control_figure(m: dict) -> Figure | None:
    """The error on the control points, held out of the fit (Farago, Maczak and Gingl, IEEE Access, Table 3)."""
    if "count_control" not in m or m.get("error_after_mg") is None:
        return None
    return Figure(m.get("error_before_mg"), m["error_after_mg"], "mg", "error on control points held out of the fit")


@dataclass(frozen=True)
class AutoCalibration(CalibrationResult):
    """Result of the Farago et al. auto-calibration of a recording.

    Attributes
    ----------
    calibration : TriangularCalibration or None
        The 9-parameter fit on the selected points; None when no fit was possible.
    gravity : float
    points, control : numpy.ndarray, shape (N, 3), (M, 3)
        Selected calibration and control points, in the recording's unit.
    point_starts, control_starts : numpy.ndarray of int
        First sample of the segment behind each point.
    selection, control_selection : dict
        Points per subset C_ij.
    detection : dict
        :meth:`RestSegments.summary`.
    comparison : dict
        Method → ``{error_before_mg, error_after_mg, improvement_pct, K, o, ok, count}`` (Farago et al. Table 3).
    metrics : dict
        ``error_before_mg``, ``error_after_mg``, ``improvement_pct`` on the control set, and the fit's.
    warnings, reasons : tuple of str
    solver : str
    unit : str
        ``g`` or ``m/s^2``.
    """

    calibration: TriangularCalibration | None
    gravity: float
    points: np.ndarray
    control: np.ndarray
    point_starts: np.ndarray
    control_starts: np.ndarray
    selection: dict
    control_selection: dict
    detection: dict
    comparison: dict
    solver: str
    metrics: dict = field(default_factory=dict)
    warnings: tuple = ()
    reasons: tuple = ()
    method: str = METHOD
    unit: str = "g"

    RESULT_TYPE = METHOD
    MODEL_TYPE = MODEL_TYPE
    CORRECTION_SOURCE = TriangularCalibration.CORRECTION_SOURCE
    AS_FITTED = TriangularCalibration.AS_FITTED

    @property
    def ok(self) -> bool:
        """True when a calibration was fitted and no gate failed."""
        return self.calibration is not None and not self.reasons

    @property
    def K(self) -> np.ndarray:
        return np.eye(3) if self.calibration is None else self.calibration.K

    @property
    def o(self) -> np.ndarray:
        return np.zeros(3) if self.calibration is None else self.calibration.o

    @property
    def p(self) -> np.ndarray:
        """[k_xx, k_yy, k_zz, k_xy, k_xz, k_yz, o_x, o_y, o_z] (Farago et al. eq. (6))."""
        K = self.K
        return np.array([K[0, 0], K[1, 1], K[2, 2], K[1, 0], K[2, 0], K[2, 1], *self.o])

    def _calibrate(self, rows: np.ndarray) -> np.ndarray:
        return (rows + self.o) @ self.K.T  # Farago et al. eqs. (7)–(9): a = K (v + o); the identity without a fit

    def still_readings(self) -> np.ndarray:
        """Its calibration points (the control points are held out of the fit)."""
        return np.asarray(self.points, dtype=float).reshape(-1, 3)

    @classmethod
    def figures_from(cls, metrics: dict, output_unit: str | None) -> tuple[Figure, ...]:
        """Readings the request held out, else its control points (held out of its fit, Farago et al.
        Table 3), else its cross-validated error, else the in-sample error."""
        return (first_figure(metrics, (holdout_figure, control_figure, cv_figure, in_sample_figure)),)

    def uncertainty(self) -> dict:
        if self.calibration is None:
            return {"K": None, "o": None, "note": "no calibration was fitted"}
        return self.calibration.uncertainty()

    def evaluate(self, means) -> dict:
        """Held-out norm errors of further still readings (Farago et al. Table 3, eq. (21))."""
        return norm_errors(means, self.apply, self.gravity)

    def model_dict(self) -> dict:
        return {"K": self.K.tolist(), "o": self.o.tolist()}

    def body_dict(self) -> dict:
        """The fit's covariance and readings, the comparison table (Farago et al. Table 3), the points
        selected per subset and the rest detection."""
        fit = self.calibration.body_dict() if self.calibration is not None else {"covariance": None, "readings": []}
        return dict(
            fit,
            solver=self.solver,
            comparison=self.comparison,
            selection=self.selection,
            control_selection=self.control_selection,
            detection=self.detection,
            points=self.points.tolist(),
            control=self.control.tolist(),
            point_starts=self.point_starts.tolist(),
            control_starts=self.control_starts.tolist(),
        )

    @classmethod
    def _from_body(cls, data: dict) -> AutoCalibration:
        """Rebuild from :meth:`to_dict` output."""
        cal = None
        if data.get("readings"):
            cal = TriangularCalibration._from_body({**data, "method": "triangular", "reasons": []})
        return cls(
            calibration=cal,
            gravity=float(data["gravity"]),
            points=np.asarray(data.get("points", []), dtype=float).reshape(-1, 3),
            control=np.asarray(data.get("control", []), dtype=float).reshape(-1, 3),
            point_starts=np.asarray(data.get("point_starts", []), dtype=np.int64),
            control_starts=np.asarray(data.get("control_starts", []), dtype=np.int64),
            selection=dict(data.get("selection", {})),
            control_selection=dict(data.get("control_selection", {})),
            detection=dict(data.get("detection", {})),
            comparison=dict(data.get("comparison", {})),
            solver=data.get("solver", "lm"),
            **gate_fields(data),
            unit=data.get("unit", "g"),
        )


def _comparison_entry(result, control, count: int) -> dict:
    """One row of the comparison table (Farago, Maczak and Gingl, IEEE Access, Table 3): errors on the
    control points and the model."""
    entry = {
        "K": result.K.tolist(),
        "o": np.asarray(result.o).tolist(),
        "ok": bool(result.ok),
        "count": int(count),
        "reasons": list(result.reasons),
        "error_before_mg": None,
        "error_after_mg": None,
        "improvement_pct": None,
        "count_control": int(len(control)),
    }
    if len(control):
        ev = norm_errors(control, result.apply, result.gravity)
        entry.update(
            error_before_mg=ev["error_before_mg"],
            error_after_mg=ev["error_after_mg"],
            improvement_pct=ev["improvement_pct"],
        )
    return entry


def _one_orientation(means: np.ndarray) -> np.ndarray | None:
    """The mean direction when every rest direction lies within ONE_ORIENTATION_DEG of it."""
    n = np.linalg.norm(means, axis=1, keepdims=True)
    d = means[n[:, 0] > 0] / n[n[:, 0] > 0]
    if len(d) == 0:
        return None
    c = d.mean(axis=0)
    nc = np.linalg.norm(c)
    if nc == 0:
        return None
    c = c / nc
    if np.all(d @ c >= math.cos(math.radians(ONE_ORIENTATION_DEG))):
        return c
    return None


FIT_METRICS = (
    "error_before_mg",
    "error_after_mg",
    "norm_error_max",
    "noise_estimate",
    "condition_number",
    "converged",
    "iterations",
    "distance_to_lm",
)
"""Metrics of the fit repeated in the auto-calibration's metrics, prefixed ``fit_``."""


def _rest_gates(
    rest: RestSegments, sel: Selection, ctl: Selection, seg_s: float, min_per_bin: int, gates: Gates
) -> None:
    """Reasons when the recording has no rest, rest in one orientation, or subsets of Farago,
    Maczak and Gingl, IEEE Access, eq. (10) left short; a warning for an incomplete control set."""
    if rest.n_rest == 0:
        why = []
        if rest.n_moving:
            why.append(f"{rest.n_moving} moving (max − min above {rest.threshold:g})")
        if rest.n_nan:
            why.append(f"{rest.n_nan} with NaN gaps")
        if rest.n_idle:
            why.append(f"{rest.n_idle} idle-sleep (identical repeated samples)")
        if rest.n_moving and rest.n_moving == rest.n_segments:  # the cause: it never rested
            gates.fail(
                f"it never rested: all {rest.n_segments} segments of {seg_s:g} s moved (max − min above "
                f"{rest.threshold:g}): auto-calibration needs still stretches of at least one segment in many "
                "orientations — give a recording in which the device rests (taken off, or at night)"
            )
            return
        gates.fail(
            f"no rest segment found among the {rest.n_segments} segments of {seg_s:g} s"
            + (f" ({', '.join(why)})" if why else "")
            + ": auto-calibration needs still stretches of at least one segment in many orientations; "
            "give a longer recording, or check the unit and the sampling rate"
        )
    else:
        one = _one_orientation(rest.mean)
        if one is not None:
            gates.fail(
                f"rest in only one orientation: all {rest.n_rest} rest segments point within "
                f"{ONE_ORIENTATION_DEG:g}° of {np.array2string(one, precision=2)}; the 9 parameters need rest in "
                "many orientations (two per subset of Farago et al. eq. (10)): give a recording in which the device "
                "rests in different positions"
            )
        if sel.short_bins:
            gates.fail(
                f"subsets {', '.join(sel.short_bins)} of Farago et al. eq. (10) hold fewer than {min_per_bin} points "
                f"(counts {sel.to_dict()}): the recording has no rest in those orientations; give a "
                "longer recording or lower min_per_bin"
            )
        if (rest.n_idle or rest.n_nan) and sel.short_bins:
            gates.warn(f"{rest.n_idle} idle-sleep and {rest.n_nan} NaN segments were refused as rest")
    if ctl.short_bins and rest.n_rest:
        gates.warn(
            f"the control set is incomplete (subsets {', '.join(ctl.short_bins)} below {min_per_bin}): "
            "the held-out errors cover fewer orientations"
        )


def _fit(rest: RestSegments, points: np.ndarray, g: float, solver: str, gates: Gates) -> TriangularCalibration | None:
    """The 9-parameter fit of Farago, Maczak and Gingl, IEEE Access, eqs. (6)–(9) on the selected
    points, or None with a reason."""
    if len(points) >= 9:
        try:
            return fit_triangular(points, gravity=g, solver=solver)
        except CalibrationError as exc:  # InsufficientDataError: too few distinct orientations
            gates.fail(f"the 9-parameter fit was not possible: {exc}")
    elif rest.n_rest:
        gates.fail(
            f"only {len(points)} calibration points could be selected; the 9-parameter model needs "
            "at least 9 (Farago et al. recommends 18)"
        )
    return None


def _held_out(cal: TriangularCalibration, control: np.ndarray, g: float, metrics: dict, gates: Gates) -> None:
    """Held-out evaluation of Farago, Maczak and Gingl, IEEE Access, section III.B (Table 3,
    eq. (21)) on the control points; a reason when the calibration makes them worse."""
    if not len(control):
        metrics.update(error_before_mg=None, error_after_mg=None, improvement_pct=None)
        gates.warn(
            "no control points remain for the held-out evaluation (Farago et al. section III.B): "
            "a longer recording gives one"
        )
        return
    ev = norm_errors(control, cal.apply, g)
    metrics.update(
        error_before_mg=ev["error_before_mg"],
        error_after_mg=ev["error_after_mg"],
        improvement_pct=ev["improvement_pct"],
    )
    if ev["error_after_mg"] >= ev["error_before_mg"]:
        gates.fail(
            f"the calibration makes the control points worse ({ev['error_before_mg']:.2f} mg before, "
            f"{ev['error_after_mg']:.2f} mg after): the rest segments are probably not all still"
        )


def _cross_validated(points: np.ndarray, g: float, solver: str, metrics: dict, gates: Gates) -> None:
    """The cross-validated error of the calibration points (app.calibration.still.cross_validation: each
    point calibrated by the fit made without it) beside the control points' held-out one; a reason
    when it is not below the points' raw error."""
    cv = cross_validated_error(lambda idx: fit_triangular(points[idx], gravity=g, solver=solver), points, g)
    metrics.update(cv)
    gates.fail(worse_than_raw(cv["cv_error_mg"], metrics["fit_error_before_mg"], len(points), cv["cv_scheme"]))


def _comparison(
    rest: RestSegments, cal: TriangularCalibration, points: np.ndarray, control: np.ndarray, g: float
) -> dict:
    """The comparison table of Farago, Maczak and Gingl, IEEE Access, Table 3: the triangular fit,
    the axis-aligned ellipsoid fit and the van Hees sphere fit (also on its own 10 s windows)."""
    comparison = {"triangular_002": _comparison_entry(cal, control, len(points))}
    for name, fn, pts in (
        ("ellipsoid_axes", fit_ellipsoid_axes, points),
        ("sphere_van_hees", fit_sphere_van_hees, points),
        ("sphere_van_hees_10s", fit_sphere_van_hees, rest.ggir_mean),
    ):
        try:
            comparison[name] = _comparison_entry(fn(pts, gravity=g), control, len(pts))
        except CalibrationError as exc:
            comparison[name] = {
                "ok": False,
                "reasons": [str(exc)],
                "error_before_mg": None,
                "error_after_mg": None,
                "improvement_pct": None,
                "count": int(len(pts)),
            }
    return comparison


def autocalibrate(
    rest: RestSegments,
    *,
    solver: str = "lm",
    min_per_bin: int = MIN_PER_BIN,
    max_per_bin: int = MAX_PER_BIN,
    min_distance_g: float = MIN_DISTANCE_G,
    compare: bool = True,
) -> AutoCalibration:
    """Select, fit and evaluate the Farago, Maczak and Gingl, IEEE Access auto-calibration from
    detected rest segments.

    Parameters
    ----------
    rest : RestSegments
        From :func:`~app.calibration.segments.stationary_002.detect_rest_segments` or a
        :class:`~app.calibration.segments.stationary_002.RestAccumulator`.
    solver : {"lm", "gradient", "fixed16", "fixed32"}
        Solver of :func:`~app.calibration.still.triangular.fit_triangular`.
    min_per_bin, max_per_bin : int
        Points per subset of eq. (10) (2 and 2: 18 points).
    min_distance_g : float
        Smallest distance between chosen points, in g.
    compare : bool
        Also run the comparison methods (Table 3).

    Returns
    -------
    AutoCalibration
        ``ok = False`` with reasons when the recording cannot be calibrated.

    Raises
    ------
    CalibrationError
        Unknown solver or invalid selection settings.
    """
    if solver not in SOLVERS:
        raise CalibrationError(f"unknown solver {solver!r}: use one of {', '.join(SOLVERS)}")
    g = rest.gravity
    det = rest.summary()
    gates = Gates()
    sel = select_points(
        rest.mean, gravity=g, min_per_bin=min_per_bin, max_per_bin=max_per_bin, min_distance_g=min_distance_g
    )
    ctl = select_points(
        rest.mean,
        gravity=g,
        min_per_bin=min_per_bin,
        max_per_bin=max_per_bin,
        min_distance_g=min_distance_g,
        exclude=sel.indices,
    )
    points = rest.mean[sel.indices]
    control = rest.mean[ctl.indices]
    _rest_gates(rest, sel, ctl, det["segment_s"], min_per_bin, gates)
    metrics: dict = {"count": int(len(points)), "count_control": int(len(control))}
    cal = _fit(rest, points, g, solver, gates)
    if cal is not None:
        gates.merge(cal)
        metrics.update({f"fit_{k}": v for k, v in cal.metrics.items() if k in FIT_METRICS})
        _cross_validated(points, g, solver, metrics, gates)
        _held_out(cal, control, g, metrics, gates)
    else:
        metrics.update(error_before_mg=None, error_after_mg=None, improvement_pct=None)
    comparison = _comparison(rest, cal, points, control, g) if compare and cal is not None else {}
    return AutoCalibration(
        calibration=cal,
        gravity=g,
        points=points,
        control=control,
        point_starts=rest.start[sel.indices],
        control_starts=rest.start[ctl.indices],
        selection=sel.to_dict(),
        control_selection=ctl.to_dict(),
        detection=det,
        comparison=comparison,
        solver=solver,
        metrics=metrics,
        **gates.fields(),
    )


def autocalibrate_samples(
    samples,
    sampling_rate_hz: float,
    *,
    gravity: float = 1.0,
    solver: str = "lm",
    progress=None,
    detection: dict | None = None,
    **selection,
) -> AutoCalibration:
    """Detect, select, fit and evaluate in one call (Farago, Maczak and Gingl, IEEE Access, section II.B).

    Parameters
    ----------
    samples : array_like or numpy.memmap, shape (N, 3)
        The recording, in the unit of ``gravity``; read in chunks.
    sampling_rate_hz : float
    gravity : float
        1 for samples in g, 9.80665 (or local gravity) for m/s².
    solver : str
    progress : callable, optional
        ``progress(done, total)`` in samples.
    detection : dict, optional
        Options of :class:`~app.calibration.segments.stationary_002.RestAccumulator`.
    **selection
        ``min_per_bin``, ``max_per_bin``, ``min_distance_g``, ``compare`` of :func:`autocalibrate`.

    Returns
    -------
    AutoCalibration
    """
    rest = detect_rest_segments(samples, sampling_rate_hz, gravity=gravity, progress=progress, **(detection or {}))
    return autocalibrate(rest, solver=solver, **selection)


__all__ = [
    "BIN_NAMES",
    "AutoCalibration",
    "Selection",
    "autocalibrate",
    "autocalibrate_samples",
    "bin_of",
    "select_points",
]
