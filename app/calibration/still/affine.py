"""Known-orientation calibration: the 12-parameter affine model of Georgieva et al., ESGI'95, Approach 2.

Georgieva et al., ESGI'95, section 3: the measurement m of a true specific force a is modelled as
``m = X a + y`` (section 3.2); the calibrated value is ``a = X⁻¹ (m − y)`` (eq. (20)).  With N ≥ 4
readings in known orientations the parameters z (eq. (21)) solve ``K z = m̄`` in the least-squares
sense (section 3.3), provided condition (22) holds; for the six canonical orientations the solution
has a closed form (section 3.3.1).  The metrics are those of section 3.5.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..shared.correction import AffineCorrection
from ..shared.errors import CalibrationError, InsufficientDataError
from ..shared.gates import (
    Gates,
    exact_fit_gate,
    limit_gate,
    near_duplicate_gate,
    offset_gate,
    residual_gate,
    scale_gate,
)
from ..shared.orientations import CANONICAL_SIX, nearest_orientation, up_vector
from ..shared.result import StillReadingsResult, parameter
from ..shared.validation import as_vectors, check_gravity

MODEL_TYPE = "affine"

PLAUSIBLE_SCALE = (0.8, 1.2)
"""Diagonal of X outside this range is implausible for a MEMS accelerometer (docs/methods.md)."""

MAX_FIT_ERROR = 0.05
"""A calibrated reading further than 5 % of g from its orientation fails the fit (ok = false)."""

NEAR_DUPLICATE_FRACTION = 0.01
"""Readings closer than 1 % of g to each other are named as near duplicates (docs/rest.md)."""

MAX_CONDITION_NUMBER = 10.0
"""Above this condition number of the normalised design, the orientations are poorly spread."""


@dataclass(frozen=True)
class AffineCalibration(StillReadingsResult):
    """Result of an affine (12-parameter) calibration, Georgieva et al. Approach 2.

    Attributes
    ----------
    X, y : numpy.ndarray
        Model ``m = X a + y`` (Georgieva et al. section 3.2), X of shape (3, 3), y of shape (3,), in the unit of
        the readings (X maps the reference unit to it).
    gravity : float
        Reference magnitude g the expected readings were built with.
    means, expected : numpy.ndarray
        The fitted readings m⁽ⁱ⁾ and their known specific forces a⁽ⁱ⁾, shape (N, 3).
    labels : tuple
        Orientation label of each reading, or None where an explicit vector was given.
    covariance : numpy.ndarray or None
        Covariance (12, 12) of z in the order of Georgieva et al. eq. (21); None without degrees of freedom.
    dof : int
        Residual degrees of freedom per axis, N − 4.
    metrics : dict
        The figures of Georgieva et al. section 3.5 and the design's condition number.
    warnings : tuple of str
        Everything worth telling, gate failures first.
    reasons : tuple of str
        The gate failures; ``ok`` is true exactly when there are none.
    method : str
        ``six_position`` or ``orientations``.
    unit : str
        Unit of the readings: ``m/s^2``, ``g`` or ``raw``.
    """

    X: np.ndarray = parameter()
    y: np.ndarray = parameter()
    expected: np.ndarray  # type: ignore[misc]  # mypy takes parameter() (a field) for a default
    labels: tuple  # type: ignore[misc]  # mypy takes parameter() (a field) for a default
    method: str = "orientations"

    RESULT_TYPE = MODEL_TYPE
    MODEL_TYPE = MODEL_TYPE
    N_PARAMS = 12
    CORRECTION_SOURCE = "Georgieva et al., ESGI'95, eq. (20): M = X^-1, o = y"
    AS_FITTED = "As fitted (Georgieva et al., ESGI'95, section 3.2): m = X a + y, so X = M⁻¹ and y = o."
    PARAMETERS = tuple(
        (
            f"x{i + 1}{j + 1}",
            "scale" if i == j else "cross",
            "xyz"[i] if i == j else "xyz"[min(i, j)] + "xyz"[max(i, j)],
        )
        for i in range(3)
        for j in range(3)
    ) + (("y1", "offset", "x"), ("y2", "offset", "y"), ("y3", "offset", "z"))
    """Name, kind and axes of each parameter in the covariance's order (z of eq. (21))."""

    @property
    def correction_matrix(self) -> np.ndarray:
        """X⁻¹, the matrix firmware multiplies by after subtracting y (Georgieva et al. eq. (20))."""
        return np.linalg.inv(self.X)

    def _calibrate(self, rows: np.ndarray) -> np.ndarray:
        # Georgieva et al. eq. (20): a = X⁻¹ (m − y), solved rather than multiplied by the inverse.
        return np.linalg.solve(self.X, (rows - self.y).T).T

    @property
    def residuals(self) -> np.ndarray:
        """Calibrated readings minus their expected specific force, shape (N, 3)."""
        return self.apply(self.means) - self.expected

    NO_INTERVALS = (
        "no intervals: {n} readings fit 4 parameters per axis exactly (0 residual degrees of freedom); "
        "add orientations to estimate the uncertainty"
    )

    def interval_dict(self, hw: np.ndarray) -> dict:
        return {"X": hw[:9].reshape(3, 3).tolist(), "y": hw[9:].tolist()}

    def reading_detail(self, index: int, mean: np.ndarray, calibrated: np.ndarray) -> dict:
        """A known orientation's reading: its label, mean, expected vector, calibrated residual and the
        relative fit errors after and before (Georgieva et al., ESGI'95, section 3.5)."""
        a = self.expected[index]
        return {
            "up": self.labels[index],
            "mean": mean.tolist(),
            "expected": a.tolist(),
            "residual": (calibrated - a).tolist(),
            "fit_error": float(np.linalg.norm(calibrated - a) / np.linalg.norm(a)),
            "fit_error_raw": float(np.linalg.norm(mean - a) / np.linalg.norm(a)),
        }

    @property
    def correction(self) -> AffineCorrection:
        """``a = X⁻¹ (m − y)`` (Georgieva et al., ESGI'95, eq. (20)): M = X⁻¹, o = y."""
        return AffineCorrection(
            self.correction_matrix, np.asarray(self.y, dtype=float), self.unit, self.output_unit, self.CORRECTION_SOURCE
        )

    @classmethod
    def _from_body(cls, data: dict) -> AffineCalibration:
        model, readings, common = cls.common_from_dict(data)
        common["dof"] = int((data.get("uncertainty") or {}).get("dof", max(len(readings) - 4, 0)))
        return cls(
            **cls.parameters_from(model),
            expected=np.asarray([r["expected"] for r in readings], dtype=float).reshape(-1, 3),
            labels=tuple(r.get("up") for r in readings),
            **common,
        )


def _design(expected: np.ndarray, gravity: float) -> np.ndarray:
    """Rows (a⁽ⁱ⁾/g, 1) of Georgieva et al., ESGI'95, condition (22), normalised so that the design is
    unit-free."""
    return np.hstack([expected / gravity, np.ones((len(expected), 1))])


def _check_condition_22(expected: np.ndarray, gravity: float, labels: tuple) -> None:
    """Raise unless the rows (a⁽ⁱ⁾, 1) have rank 4 (Georgieva et al., ESGI'95, condition (22), read as
    in docs/rest.md)."""
    design = _design(expected, gravity)
    sv = np.linalg.svd(design, compute_uv=False)
    rank = int(np.sum(sv > 1e-9 * sv[0]))
    if rank >= 4:
        return
    names = ", ".join(lab if lab else np.array2string(a / gravity, precision=2) for lab, a in zip(labels, expected))
    hint = ""
    if rank == 3:
        # The expected vectors lie on one plane; its normal names the direction that is missing.
        centred = expected - expected.mean(axis=0)
        normal = np.linalg.svd(centred)[2][-1]
        axis = nearest_orientation(normal, max_angle_deg=45.0)
        if axis:
            hint = f"; add a reading with the {axis[1]} axis up or down"
    raise InsufficientDataError(
        f"the orientations {names} do not satisfy condition (22) of Georgieva et al. section 3.3: the rows "
        f"(a, 1) have rank {rank}, not 4, so X and y are not determined. At least four "
        f"orientations that do not lie on one plane are needed{hint}"
    )


def _covariance(design: np.ndarray, residuals: np.ndarray, gravity: float) -> tuple[np.ndarray | None, int]:
    """Least-squares covariance of z (Georgieva et al., ESGI'95, eq. (21) order) from the residual
    variance per axis.

    Each output axis j is its own linear model ``m_j = [a, 1] · [X_j, y_j]``; its parameters
    have covariance σ_j² (AᵀA)⁻¹ with σ_j² = RSS_j / (N − 4).  Axes are taken as independent.
    """
    n = len(design)
    dof = n - 4
    if dof <= 0:
        return None, 0
    # Undo the 1/g normalisation of the first three columns: parameters of X multiply a, not a/g.
    scale = np.array([1.0 / gravity] * 3 + [1.0])
    inv = np.linalg.inv(design.T @ design) * np.outer(scale, scale)
    sigma2 = (residuals**2).sum(axis=0) / dof
    cov = np.zeros((12, 12))
    for j in range(3):
        idx = [3 * j, 3 * j + 1, 3 * j + 2, 9 + j]
        cov[np.ix_(idx, idx)] = sigma2[j] * inv
    return cov, dof


def _calibrated(X: np.ndarray, y: np.ndarray, means: np.ndarray) -> np.ndarray:
    """``a = X⁻¹ (m − y)`` of every reading (Georgieva et al., ESGI'95, eq. (20)), or raise when X is
    singular."""
    det = float(np.linalg.det(X))
    if not np.isfinite(det) or abs(det) < 1e-12:
        raise CalibrationError(
            "the fitted matrix X is singular: the readings do not change with orientation; "
            "check that the readings are from the accelerometer and that the device was turned"
        )
    return np.linalg.solve(X, (means - y).T).T


def _metrics(
    cal: np.ndarray, means: np.ndarray, expected: np.ndarray, gravity: float, cond: float, dof: int
) -> tuple[dict, np.ndarray]:
    """The figures of Georgieva et al., ESGI'95, section 3.5, and the relative fitting errors."""
    norm_a = np.linalg.norm(expected, axis=1)
    fit = np.linalg.norm(cal - expected, axis=1) / norm_a
    fit_raw = np.linalg.norm(means - expected, axis=1) / norm_a
    norm_err = np.abs(np.linalg.norm(cal, axis=1) - gravity) / gravity
    norm_err_raw = np.abs(np.linalg.norm(means, axis=1) - gravity) / gravity
    metrics = {
        # Georgieva et al., ESGI'95, section 3.5: relative fitting error, calibrated and raw.
        "fit_error_max": float(fit.max()),
        "fit_error_max_raw": float(fit_raw.max()),
        # Georgieva et al., ESGI'95, section 3.5: relative error of the norms.
        "norm_error_max": float(norm_err.max()),
        "norm_error_max_raw": float(norm_err_raw.max()),
        "fit_improvement": float(fit_raw.max() / fit.max()) if fit.max() > 0 else None,
        "norm_improvement": float(norm_err_raw.max() / norm_err.max()) if norm_err.max() > 0 else None,
        "rms_residual": float(np.sqrt(np.mean((cal - expected) ** 2))),
        "condition_number": cond,
        "dof": dof,
        "count": int(len(means)),
    }
    return metrics, fit


def _gates(X, y, means, labels, gravity, fit, cond, dof, *, stds, plausible_scale, max_offset) -> Gates:
    """Quality gates of the affine fit (docs/methods.md): fit error, scales, offsets, spread, duplicates."""
    gates = Gates()
    gates.fail(
        residual_gate(
            fit,
            MAX_FIT_ERROR,
            lambda index, percent, gate_percent, **_: (
                f"reading {index} ({labels[index] or f'reading {index}'}) is {percent:.1f} % of g from its "
                f"orientation after calibration (gate {gate_percent:.0f} %): it may be mislabelled or not still"
            ),
        )
    )
    gates.fail(
        scale_gate(
            np.diag(X),
            plausible_scale,
            "scale of the {axis} axis is {value:.4f}, outside the plausible {lo}–{hi}: "
            "check the unit and the orientation labels",
        )
    )
    gates.fail(
        offset_gate(
            y,
            max_offset,
            "offset of the {axis} axis is {value:.4g}, above 1 g in magnitude: check the unit and the orientation "
            "labels",
        )
    )
    gates.warn(
        limit_gate(
            cond,
            MAX_CONDITION_NUMBER,
            "the orientations are poorly spread (condition number {value:.1f}): the parameters "
            "are sensitive to noise; add opposite orientations",
        )
    )
    gates.warn(
        near_duplicate_gate(
            means,
            NEAR_DUPLICATE_FRACTION * gravity,
            "readings {i} and {j} are within 1 % of g of each other (near-duplicate positions, "
            "Georgieva et al. Dataset 3): they weigh one orientation twice",
        )
    )
    if stds is not None:
        for i, s in enumerate(stds):
            if s is not None and np.all(np.isfinite(s)) and np.linalg.norm(s) > 0.05 * gravity:
                gates.warn(
                    f"reading {i} has a spread of {np.linalg.norm(s):.3g} (above 5 % of g): "
                    "the device may have moved during the capture"
                )
    gates.fail(
        exact_fit_gate(
            dof,
            "4 readings fit the 12 parameters exactly: there are no residual degrees of freedom, "
            "so no intervals and no check of the fit; use six or more orientations",
        )
    )
    return gates


def _finish(
    X: np.ndarray,
    y: np.ndarray,
    means: np.ndarray,
    expected: np.ndarray,
    labels: tuple,
    gravity: float,
    method: str,
    *,
    stds: np.ndarray | None,
    plausible_scale: tuple[float, float] | None,
    max_offset: float | None,
) -> AffineCalibration:
    """Covariance, metrics and gates shared by both solvers (Georgieva et al., ESGI'95, sections 3.3–3.5);
    ``max_offset`` defaults to ``gravity`` (1 g)."""
    stds = None if stds is None else np.asarray(stds, dtype=float)
    max_offset = gravity if max_offset is None else max_offset
    design = _design(expected, gravity)
    fitted = expected @ X.T + y
    cov, dof = _covariance(design, means - fitted, gravity)
    cond = float(np.linalg.cond(design))
    cal = _calibrated(X, y, means)
    metrics, fit = _metrics(cal, means, expected, gravity, cond, dof)
    gates = _gates(
        X, y, means, labels, gravity, fit, cond, dof, stds=stds, plausible_scale=plausible_scale, max_offset=max_offset
    )
    return AffineCalibration(
        X=X,
        y=y,
        gravity=gravity,
        means=means,
        expected=expected,
        labels=tuple(labels),
        covariance=cov,
        dof=dof,
        metrics=metrics,
        method=method,
        **gates.fields(),
    )


def _expected_from(ups, expected, n: int, gravity: float) -> tuple[np.ndarray, tuple]:
    """Known specific forces from labels and/or explicit vectors (explicit ones in the data's unit)."""
    if ups is None and expected is None:
        raise CalibrationError("each reading needs its orientation: give `ups` labels or `expected` vectors")
    labels = list(ups) if ups is not None else [None] * n
    if len(labels) != n:
        raise CalibrationError(f"{n} readings but {len(labels)} orientation labels: give one per reading")
    explicit = None
    if expected is not None:
        explicit = list(expected)
        if len(explicit) != n:
            raise CalibrationError(f"{n} readings but {len(explicit)} expected vectors: give one per reading")
    rows = []
    for i in range(n):
        e = None if explicit is None else explicit[i]
        if e is not None:
            v = as_vectors(e, f"expected vector of reading {i}")[0]
            if np.linalg.norm(v) == 0:
                raise CalibrationError(f"expected vector of reading {i} is zero; it must be the specific force at rest")
            rows.append(v)
        elif (label := labels[i]) is not None:
            rows.append(up_vector(label) * gravity)
        else:
            raise CalibrationError(f"reading {i} has neither an `up` label nor an `expected` vector")
    return np.array(rows), tuple(labels)


def fit_orientations(
    means,
    ups=None,
    *,
    expected=None,
    gravity: float,
    stds=None,
    plausible_scale: tuple[float, float] | None = PLAUSIBLE_SCALE,
    max_offset: float | None = None,
) -> AffineCalibration:
    """Least-squares affine calibration from readings in known orientations (Georgieva et al., ESGI'95,
    section 3.3).

    Solves ``K z = m̄`` for z = (x11, …, x33, y1, y2, y3) (Georgieva et al., ESGI'95, eq. (21)) in the
    least-squares
    sense, after checking condition (22).

    Parameters
    ----------
    means : array_like, shape (N, 3)
        Averaged still readings m⁽ⁱ⁾, N ≥ 4.
    ups : sequence of str, optional
        Orientation label of each reading (``+x`` … ``-z``, the axis that points up).
    expected : sequence, optional
        Explicit specific force a⁽ⁱ⁾ for each reading (None entries fall back to ``ups``), in the
        unit of the readings.
    gravity : float
        Reference magnitude, in the unit of the readings (1 for readings in g).
    stds : array_like, optional
        Per-reading standard deviations, only used to warn about movement.
    plausible_scale : (float, float) or None
        Bounds of the diagonal of X that pass the gate; None for raw units.
    max_offset : float or None
        Largest |y| that passes the gate; defaults to ``gravity`` (1 g).

    Returns
    -------
    AffineCalibration

    Raises
    ------
    CalibrationError
        Wrong shapes, non-finite values, unknown labels.
    InsufficientDataError
        Fewer than 4 readings, or orientations that violate condition (22).
    """
    g = check_gravity(gravity)
    m = as_vectors(means, "means")
    a, labels = _expected_from(ups, expected, len(m), g)
    if len(m) < 4:
        raise InsufficientDataError(
            f"{len(m)} readings cannot determine the 12 parameters of X and y: at least 4 "
            "orientations that do not lie on one plane are needed (Georgieva et al. condition (22))"
        )
    _check_condition_22(a, g, labels)
    # Georgieva et al., ESGI'95, section 3.3: K z = m̄ decouples into A W = M with A = [a, 1] and W = [Xᵀ; yᵀ].
    design = np.hstack([a, np.ones((len(a), 1))])
    W, *_ = np.linalg.lstsq(design, m, rcond=None)
    X, y = W[:3].T.copy(), W[3].copy()
    return _finish(
        X, y, m, a, labels, g, "orientations", stds=stds, plausible_scale=plausible_scale, max_offset=max_offset
    )


def fit_six_position(
    means,
    ups=CANONICAL_SIX,
    *,
    gravity: float,
    stds=None,
    plausible_scale: tuple[float, float] | None = PLAUSIBLE_SCALE,
    max_offset: float | None = None,
) -> AffineCalibration:
    """Closed-form affine calibration from the six canonical orientations (Georgieva et al., ESGI'95,
    section 3.3.1).

    ``X = (1/2g) [m⁽⁺ˣ⁾ − m⁽⁻ˣ⁾, m⁽⁺ʸ⁾ − m⁽⁻ʸ⁾, m⁽⁺ᶻ⁾ − m⁽⁻ᶻ⁾]`` and ``y = (1/6) Σ m⁽ⁱ⁾``; it
    equals the least-squares solution of section 3.3 on the same readings.

    Parameters
    ----------
    means : array_like, shape (6, 3)
        Averaged still readings, one per canonical orientation, in any order.
    ups : sequence of str
        The label of each reading; each of ``-x, +x, -y, +y, -z, +z`` exactly once.
        Defaults to the canonical order of Georgieva et al., ESGI'95, section 3.3.1.
    gravity, stds, plausible_scale, max_offset
        As in :func:`fit_orientations`.

    Returns
    -------
    AffineCalibration

    Raises
    ------
    CalibrationError
        Not exactly six readings, unknown, missing or repeated orientations, non-finite values.
    """
    g = check_gravity(gravity)
    m = as_vectors(means, "means")
    labels = list(ups)
    if len(m) != 6 or len(labels) != 6:
        error = InsufficientDataError if min(len(m), len(labels)) < 6 else CalibrationError
        raise error(
            f"six_position needs exactly 6 readings, one per orientation {', '.join(CANONICAL_SIX)}; "
            f"got {len(m)} readings and {len(labels)} labels (use method `orientations` for other sets)"
        )
    for lab in labels:
        up_vector(lab)  # raises on an unknown label
    repeated = sorted({lab for lab in labels if labels.count(lab) > 1})
    if repeated:
        missing = [lab for lab in CANONICAL_SIX if lab not in labels]
        raise CalibrationError(
            f"orientation {', '.join(repeated)} is given more than once and {', '.join(missing)} "
            "is missing: six_position needs each of the six orientations exactly once"
        )
    by_label = {lab: m[i] for i, lab in enumerate(labels)}
    # Georgieva et al., ESGI'95, section 3.3.1: closed form of the least-squares solution for the
    # canonical orientations.
    X = np.column_stack([by_label["+" + ax] - by_label["-" + ax] for ax in "xyz"]) / (2.0 * g)
    y = m.mean(axis=0)
    a = np.array([up_vector(lab) * g for lab in labels])
    return _finish(
        X, y, m, a, tuple(labels), g, "six_position", stds=stds, plausible_scale=plausible_scale, max_offset=max_offset
    )
