"""Scale-and-offset calibrations that Farago et al. and the actigraphy field compare against (Farago et al. Table 3).

Both fit ``a = s ∘ (v + o)`` (a scale and an offset per axis, no cross-axis terms) to still
readings of unknown orientation:

- :func:`fit_ellipsoid_axes` — the non-iterative ellipsoid fit of Gietzelt et al. (Farago et al. ref. [34],
  the "Non-iterative method" row of Table 3): one linear least-squares solve of
  ``A x² + B y² + C z² + D x + E y + F z = 1`` for an axis-aligned ellipsoid, whose centre gives
  the offsets and whose semi-axes give the scales.
- :func:`fit_sphere_van_hees` — the sphere fit of van Hees et al. (2014) used by GGIR and
  actipy: iteratively reweighted per-axis linear regressions of the calibrated points onto their
  closest points on the unit sphere; the weights are ``min(1/distance, 100)``; it stops when the
  weighted mean squared distance changes by less than 1e-10 g², at most 1000 iterations.  GGIR
  feeds it the means of 10 s windows with a standard deviation below 0.013 g on every axis
  (:class:`~app.calibration.segments.stationary_002.RestSegments.ggir_mean`); here it also runs on the Farago et al.
  points so that all methods are compared on the same points, as Farago et al. section III does.

The results are :class:`AxisCalibration`; ``to_dict`` gives the model as the lower-triangular model
of Farago et al. with a diagonal K (``{"type": "triangular", "K": diag(s), "o": o}``), so any of them can be
applied and exported like the main result.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..shared.errors import InsufficientDataError
from ..shared.gates import Gates, limit_gate
from ..shared.norm_metrics import norm_errors
from ..shared.validation import as_samples, as_vectors, check_gravity

VAN_HEES_TOL = 1e-10
VAN_HEES_MAX_ITER = 1000
VAN_HEES_MAX_WEIGHT = 100.0  # 1 / 0.01 g
SPHERE_POPULATED_G = 0.3
"""GGIR's coverage check: each axis needs a point above +0.3 g and one below −0.3 g."""
MAX_ERROR_AFTER_G = 0.01
"""GGIR's acceptance: mean distance from the sphere below 0.01 g after calibration."""


@dataclass(frozen=True)
class AxisCalibration:
    """Scale and offset per axis: ``a = scale ∘ (v + offset)``.

    Attributes
    ----------
    scale : numpy.ndarray, shape (3,)
        Dimensionless.
    offset : numpy.ndarray, shape (3,)
        In the unit of the readings.
    gravity : float
    method : str
        ``ellipsoid_axes`` or ``sphere_van_hees``.
    count : int
        Points fitted.
    metrics, warnings, reasons
        As every result; ``ok`` is true without reasons.
    """

    scale: np.ndarray
    offset: np.ndarray
    gravity: float
    method: str
    count: int
    metrics: dict = field(default_factory=dict)
    warnings: tuple = ()
    reasons: tuple = ()

    @property
    def ok(self) -> bool:
        return not self.reasons

    @property
    def K(self) -> np.ndarray:
        return np.diag(self.scale)

    @property
    def o(self) -> np.ndarray:
        return self.offset

    def apply(self, raw) -> np.ndarray:
        """Calibrate readings, shape (3,) or (N, 3)."""
        return (as_samples(raw) + self.offset) * self.scale

    def evaluate(self, means) -> dict:
        """Mean | |r| − 1 g | in mg before and after on further still readings (Farago et al. Table 3, eq. (21))."""
        return norm_errors(means, self.apply, self.gravity)

    def uncertainty(self) -> dict:
        return {"K": None, "o": None, "note": "no intervals for the comparison methods"}

    def to_dict(self) -> dict:
        return {
            "method": self.method,
            "model": {"type": "triangular", "K": self.K.tolist(), "o": self.offset.tolist()},
            "scale": self.scale.tolist(),
            "offset": self.offset.tolist(),
            "gravity": self.gravity,
            "count": self.count,
            "metrics": dict(self.metrics),
            "ok": self.ok,
            "warnings": list(self.warnings),
            "reasons": list(self.reasons),
        }

    @classmethod
    def from_dict(cls, data: dict) -> AxisCalibration:
        return cls(
            scale=np.asarray(data["scale"], dtype=float),
            offset=np.asarray(data["offset"], dtype=float),
            gravity=float(data["gravity"]),
            method=data["method"],
            count=int(data.get("count", 0)),
            metrics=dict(data.get("metrics", {})),
            warnings=tuple(data.get("warnings", ())),
            reasons=tuple(data.get("reasons", ())),
        )


def _coverage_reasons(v: np.ndarray) -> list[str]:
    missing = [
        f"{s}{'xyz'[k]}"
        for k in range(3)
        for s, cond in (("+", (v[:, k] > SPHERE_POPULATED_G).any()), ("-", (v[:, k] < -SPHERE_POPULATED_G).any()))
        if not cond
    ]
    if missing:
        return [f"the sphere is not populated (GGIR check): no point beyond 0.3 g towards {', '.join(missing)}"]
    return []


def _still_readings(means, gravity: float, fit: str) -> tuple[float, np.ndarray, np.ndarray]:
    """Checked gravity, readings (N, 3) and the readings in g; at least 6 of them."""
    g = check_gravity(gravity)
    m = as_vectors(means, "means")
    if len(m) < 6:
        raise InsufficientDataError(f"{fit} needs at least 6 still readings; got {len(m)}")
    return g, m, m / g


def fit_ellipsoid_axes(means, *, gravity: float) -> AxisCalibration:
    """Non-iterative axis-aligned ellipsoid fit for scale and offset (Gietzelt et al., Farago et al. ref. [34]).

    Parameters
    ----------
    means : array_like, shape (N, 3)
        Still readings, N ≥ 6, in the unit of ``gravity``.
    gravity : float

    Returns
    -------
    AxisCalibration
        ``method = "ellipsoid_axes"``.

    Raises
    ------
    InsufficientDataError
        Fewer than 6 readings.
    """
    g, m, v = _still_readings(means, gravity, "the ellipsoid fit")
    D = np.column_stack([v * v, v])
    beta, *_ = np.linalg.lstsq(D, np.ones(len(v)), rcond=None)
    A, L = beta[:3], beta[3:]
    gates = Gates()
    if np.any(A <= 0):
        gates.fail(
            "the fitted quadric is not an ellipsoid (a non-positive square term): the points do not cover the sphere"
        )
        A = np.where(A > 0, A, np.nan)
    centre = -L / (2 * A)
    G = 1.0 + np.sum(L * L / (4 * A))
    radii = np.sqrt(G / A)
    scale = 1.0 / radii
    offset = -centre * g
    if not np.all(np.isfinite(scale)):
        scale, offset = np.ones(3), np.zeros(3)
    gates.fail(_coverage_reasons(v))
    fit = norm_errors(m, lambda x: (x + offset) * scale, g)
    return AxisCalibration(
        scale=scale,
        offset=offset,
        gravity=g,
        method="ellipsoid_axes",
        count=len(m),
        metrics={"fit": fit},
        **gates.fields(),
    )


def fit_sphere_van_hees(
    means, *, gravity: float, tol: float = VAN_HEES_TOL, max_iter: int = VAN_HEES_MAX_ITER
) -> AxisCalibration:
    """Iteratively reweighted sphere fit of van Hees et al. (2014), as in GGIR and actipy.

    Parameters
    ----------
    means : array_like, shape (N, 3)
        Still readings (GGIR: 10 s window means with sd < 0.013 g), in the unit of ``gravity``.
    gravity : float
    tol : float
        Stop when the weighted mean squared distance changes by less than this (g²).
    max_iter : int

    Returns
    -------
    AxisCalibration
        ``method = "sphere_van_hees"``; ``metrics`` holds ``iterations`` and the fit's
        ``error_before_mg``/``error_after_mg`` over the fitted points.

    Raises
    ------
    InsufficientDataError
        Fewer than 6 readings.
    """
    g, m, v = _still_readings(means, gravity, "the sphere fit")
    vt = np.ascontiguousarray(v.T)  # (3, N): the reductions below run along contiguous rows
    offset = np.zeros(3)
    scale = np.ones(3)
    weights = np.ones(len(v))
    res_prev = np.inf
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 - the count of iterations is read after the loop
        curr = (vt + offset[:, None]) * scale[:, None]
        closest = curr / np.sqrt((curr * curr).sum(axis=0))
        # Weighted least squares closest_k ≈ b0 + b1·curr_k for the three axes at once.  Plain
        # sums, no BLAS: on a shared machine OpenBLAS threads make these small products 20× slower.
        sw = weights.sum()
        xm = (weights * curr).sum(axis=1) / sw
        ym = (weights * closest).sum(axis=1) / sw
        dx = curr - xm[:, None]
        sxx = (weights * dx * dx).sum(axis=1)
        sxy = (weights * dx * (closest - ym[:, None])).sum(axis=1)
        sc_ch = np.where(sxx > 0, sxy / np.where(sxx > 0, sxx, 1.0), 1.0)
        off_ch = ym - sc_ch * xm
        curr = off_ch[:, None] + sc_ch[:, None] * curr
        offset = offset + off_ch / (scale * sc_ch)
        scale = scale * sc_ch
        diff = curr - closest
        d2 = (diff * diff).sum(axis=0)
        res = 3.0 * np.mean(weights * d2 / sw)
        weights = np.minimum(1.0 / np.sqrt(np.maximum(d2, 1e-300)), VAN_HEES_MAX_WEIGHT)
        if abs(res - res_prev) < tol:
            break
        res_prev = res
    gates = Gates().fail(_coverage_reasons(v))
    if not (np.all(np.isfinite(scale)) and np.all(np.isfinite(offset))):
        gates.fail("the sphere fit diverged")
        scale, offset = np.ones(3), np.zeros(3)
    out = AxisCalibration(scale=scale, offset=offset * g, gravity=g, method="sphere_van_hees", count=len(m))
    fit = norm_errors(m, out.apply, g)
    gates.fail(
        limit_gate(
            fit["error_after_mg"],
            1000 * MAX_ERROR_AFTER_G,
            "mean distance from the sphere after calibration is {value:.1f} mg, above GGIR's 10 mg acceptance",
        )
    )
    return AxisCalibration(
        scale=scale,
        offset=offset * g,
        gravity=g,
        method="sphere_van_hees",
        count=len(m),
        metrics={"iterations": it, "fit": fit},
        **gates.fields(),
    )
