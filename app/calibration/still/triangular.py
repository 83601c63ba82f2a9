"""The 9-parameter lower-triangular model of Farago, Maczak and Gingl, IEEE Access fitted to still
readings of unknown orientation.

Farago, Maczak and Gingl, IEEE Access, section II: the actual acceleration is ``a = K (v + o)`` (eq. (2)) with
K = S·T lower triangular (eqs. (3)–(4)) and o the offsets (eq. (5)); the parameters are
p = [k_xx, k_yy, k_zz, k_xy, k_xz, k_yz, o_x, o_y, o_z] (eq. (6)) and the correction is written out
in eqs. (7)–(9).  At rest |a| = 1 g (eq. (11)); the objective is eq. (12).

Solvers (``solver=``):

- ``lm`` (default): Levenberg–Marquardt (``scipy.optimize.least_squares``) on the residuals
  ``(|K(vᵢ + o)| − g) / |∇ᵥ|K(vᵢ + o)||``: the terms of eq. (12) divided by the gradient of |a|
  with respect to the reading, i.e. to first order the distance of each reading from the fitted
  ellipsoid.  With independent Gaussian noise on the readings this is the (first-order) maximum
  likelihood estimate; the Cramér–Rao comparison is in ``bench/sim_002.py``.
- ``gradient``: the paper's finite-difference descent as published — p₀ = [1 1 1 0 0 0 0 0 0],
  forward differences with h (eqs. (13), (15)), ``p ← p − α∘g`` (eq. (14)) with the vectorised
  learning rates α_s = 0.3, α_m = 0.8, α_o = 0.2 (eq. (16)) on the cost without the square root
  ``f = mean (|a|² − 1)²``, at most 50 iterations (section III).  The readings are divided by g
  first (the paper works in g).  Eq. (12) writes a sum over the N points; with those learning
  rates the sum diverges for N = 18 (the offset curvature is about 8·Σvₓ² ≈ 48, and 0.2·48 > 2),
  so the cost is the mean over the points, for which the published rates converge.
- ``fixed16`` / ``fixed32``: the same descent in 16-bit (Q3.12, h = 0.01) and 32-bit (Q7.24,
  h = 10⁻⁵) fixed point, bit-exact to the scheme documented in :mod:`app.calibration.still.fixed_point`.

With h = 0.01 the forward difference moves the point where the descent stops by about
−(h/2)·H⁻¹·diag(H) (H the Hessian of the cost), several 95 % intervals at 1–5 mg noise; this is the
"formula error" the paper mentions, and ``fixed16`` reports it (``bench/sim_002.py``).  For every
descent, ``metrics["distance_to_lm"]`` is the largest distance of a parameter from the
Levenberg–Marquardt optimum in units of its 95 % half-width, with a warning above 1.

Every solver's result gets the same metrics, covariance and gates; the covariance
(Särkkä et al., IEEE Sensors Journal 17(11) 2017, Appendix A, eq. (22) with V(ε) = σ² I) is taken from
the Jacobian of the
``lm`` residuals at the returned parameters and the residual variance, so for the descents it
describes the noise around the least-squares optimum, not their own convergence error.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from ..shared.errors import CalibrationError
from ..shared.gates import (
    Gates,
    deviation_gate,
    hemisphere_gate,
    limit_gate,
    offset_gate,
    residual_gate,
    scale_gate,
    unknown_orientation_gates,
)
from ..shared.result import StillReadingsResult, parameter
from ..shared.uncertainty import covariance_from_jacobian, half_widths
from ..shared.validation import as_vectors, check_gravity, check_sphere_points, one_hemisphere_axis
from .fixed_point import fixed_point_descent
from .solvers import SOLVERS

MODEL_TYPE = "triangular"
N_PARAMS = 9
PARAM_NAMES = ("k_xx", "k_yy", "k_zz", "k_xy", "k_xz", "k_yz", "o_x", "o_y", "o_z")

P0 = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
"""Start of the descent: the ideal accelerometer (Farago, Maczak and Gingl, IEEE Access, section II.C)."""

LEARNING_RATES = (0.3, 0.8, 0.2)
"""α_s, α_m, α_o of Farago, Maczak and Gingl, IEEE Access, eq. (16), for the cost without the square root."""

H_FLOAT = 1e-5
H_FIXED16 = 0.01
H_FIXED32 = 1e-5
"""Finite-difference spacing h of Farago, Maczak and Gingl, IEEE Access, eq. (15) per number
representation (section II.C)."""

MAX_ITER = 50
"""Iteration cap of the descents (Farago, Maczak and Gingl, IEEE Access, section III)."""

PLAUSIBLE_SCALE = (0.8, 1.2)
MAX_MISALIGNMENT = 0.2
MAX_NORM_ERROR = 0.05
NEAR_DUPLICATE_FRACTION = 0.01
MAX_CONDITION_NUMBER = 30.0


def k_matrix(p) -> np.ndarray:
    """Lower-triangular K from p = [k_xx, k_yy, k_zz, k_xy, k_xz, k_yz, …] (Farago, Maczak and Gingl,
    IEEE Access, eqs. (6)–(9))."""
    p = np.asarray(p, dtype=float)
    return np.array([[p[0], 0.0, 0.0], [p[3], p[1], 0.0], [p[4], p[5], p[2]]])


def alpha_vector(alphas=LEARNING_RATES) -> np.ndarray:
    """The vectorised learning rate of Farago, Maczak and Gingl, IEEE Access, eq. (16) from (α_s, α_m, α_o)."""
    a_s, a_m, a_o = alphas
    return np.array([a_s] * 3 + [a_m] * 3 + [a_o] * 3, dtype=float)


def _calibrate(p: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Farago, Maczak and Gingl, IEEE Access, eqs. (7)–(9): a = K (v + o), rows of v."""
    return (v + p[6:9]) @ k_matrix(p).T


def _residuals_batch(P: np.ndarray, v: np.ndarray) -> np.ndarray:
    """(|a| − 1) / |∇ᵥ|a|| for each parameter row of P (M, 9): shape (M, N), readings in g.

    a = K(v + o) (eqs. (7)–(9)); ∇ᵥ|a| = Kᵀ a / |a|, so the ratio is, to first order, the distance
    of the reading from the ellipsoid |K(v + o)| = 1 (module docstring).
    """
    K = np.zeros((len(P), 3, 3))
    K[:, 0, 0], K[:, 1, 1], K[:, 2, 2] = P[:, 0], P[:, 1], P[:, 2]
    K[:, 1, 0], K[:, 2, 0], K[:, 2, 1] = P[:, 3], P[:, 4], P[:, 5]
    w = v[None, :, :] + P[:, None, 6:9]
    a = np.einsum("mij,mnj->mni", K, w)
    na = np.linalg.norm(a, axis=2)
    grad = np.einsum("mni,mij->mnj", a / na[..., None], K)
    return (na - 1.0) / np.linalg.norm(grad, axis=2)


def _residuals_lm(p: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The ``lm`` residuals of one parameter vector (see :func:`_residuals_batch`)."""
    return _residuals_batch(np.asarray(p, dtype=float)[None, :], v)[0]


def _jacobian_lm(p: np.ndarray, v: np.ndarray, *, central: bool = False) -> np.ndarray:
    """Finite-difference Jacobian of the ``lm`` residuals, all nine columns in one batch."""
    p = np.asarray(p, dtype=float)
    if central:
        step = 1e-6 * np.maximum(1.0, np.abs(p))
        E = np.diag(step)
        R = _residuals_batch(np.vstack([p + E, p - E]), v)
        return ((R[:9] - R[9:]) / (2 * step)[:, None]).T
    step = 1.5e-8 * np.maximum(1.0, np.abs(p))
    R = _residuals_batch(np.vstack([p, p + np.diag(step)]), v)
    return ((R[1:] - R[0]) / step[:, None]).T


def gradient_descent(
    points_g,
    *,
    h: float = H_FLOAT,
    alphas=LEARNING_RATES,
    max_iter: int = MAX_ITER,
    p0=P0,
) -> tuple[np.ndarray, int]:
    """The finite-difference gradient descent of Farago, Maczak and Gingl, IEEE Access, eqs. (12)–(16)
    in floating point.

    Parameters
    ----------
    points_g : array_like, shape (N, 3)
        Calibration points in g.
    h : float
        Finite-difference spacing (eq. (15)).
    alphas : (float, float, float)
        α_s, α_m, α_o (eq. (16)).
    max_iter : int
        Iteration cap; the loop ends early only when a step changes nothing.
    p0 : array_like, shape (9,)

    Returns
    -------
    p : numpy.ndarray, shape (9,)
    iterations : int
    """
    v = np.asarray(points_g, dtype=float)
    alpha = alpha_vector(alphas)
    p = np.asarray(p0, dtype=float).copy()

    def cost(q):
        a = _calibrate(q, v)
        r = np.sum(a * a, axis=1) - 1.0  # eq. (12) without the square root
        return float(np.mean(r * r))

    it = 0
    for it in range(1, max_iter + 1):
        f0 = cost(p)
        # eqs. (13), (15): forward differences, one parameter at a time
        g = np.array([(cost(p + h * e) - f0) / h for e in np.eye(N_PARAMS)])
        new = p - alpha * g  # eq. (14)
        if not np.all(np.isfinite(new)):
            return new, it
        if np.array_equal(new, p):
            break
        p = new
    return p, it


@dataclass(frozen=True)
class TriangularCalibration(StillReadingsResult):
    """Result of the 9-parameter lower-triangular calibration of Farago et al..

    Attributes
    ----------
    K : numpy.ndarray, shape (3, 3)
        Lower-triangular, dimensionless (Farago et al. eq. (2)).
    o : numpy.ndarray, shape (3,)
        Offsets o of ``a = K (v + o)``, in the unit of the readings.
    gravity : float
        Reference magnitude, in the unit of the readings.
    means : numpy.ndarray, shape (N, 3)
        The fitted readings v⁽ⁱ⁾.
    solver : str
        ``lm``, ``gradient``, ``fixed16`` or ``fixed32``.
    covariance : numpy.ndarray or None
        Covariance (9, 9) of p in the order of eq. (6), offsets in the unit of the readings.
    dof : int
        N − 9.
    metrics, warnings, reasons
        As in :class:`~app.calibration.still.affine.AffineCalibration`.
    """

    K: np.ndarray = parameter()
    o: np.ndarray = parameter()
    solver: str  # type: ignore[misc]  # mypy takes parameter() (a field) for a default
    method: str = MODEL_TYPE

    RESULT_TYPE = MODEL_TYPE
    MODEL_TYPE = MODEL_TYPE
    N_PARAMS = N_PARAMS
    REPORTS_IMPROVEMENT = True  # Farago et al. report it for their model (Table 3, eq. (21))
    CORRECTION_SOURCE = "Farago, Maczak and Gingl, IEEE Access, eq. (6): M = K, o = -o_model"
    AS_FITTED = (
        "As fitted (Farago, Maczak and Gingl, IEEE Access, eq. (6)): a = K (v + o), so K = M and the "
        "paper's o is minus the o above: the paper adds its o to the reading, the correction takes its o off."
    )
    PARAMETERS = (
        ("k_xx", "scale", "x"),
        ("k_yy", "scale", "y"),
        ("k_zz", "scale", "z"),
        ("k_xy", "cross", "xy"),
        ("k_xz", "cross", "xz"),
        ("k_yz", "cross", "yz"),
        ("o_x", "offset", "x"),
        ("o_y", "offset", "y"),
        ("o_z", "offset", "z"),
    )
    """Name, kind and axes of each parameter in the covariance's order (p of eq. (6))."""

    @property
    def p(self) -> np.ndarray:
        """[k_xx, k_yy, k_zz, k_xy, k_xz, k_yz, o_x, o_y, o_z] (Farago et al. eq. (6)), o in the readings' unit."""
        K = self.K
        return np.array([K[0, 0], K[1, 1], K[2, 2], K[1, 0], K[2, 0], K[2, 1], *self.o])

    def _calibrate(self, rows: np.ndarray) -> np.ndarray:
        return (rows + self.o) @ self.K.T  # Farago et al. eqs. (7)–(9): a = K (v + o)

    def jacobian(self, means) -> np.ndarray:
        """Jacobian (N, 9) of the ``lm`` residuals (module docstring) of readings ``means`` (N, 3) with
        respect to p at the fitted parameters, offsets in g as the fit works: what each reading adds
        to the information JᵀJ behind :attr:`covariance` (app.calibration.still.advice)."""
        g = self.gravity
        p_g = np.r_[self.p[:6], self.o / g]  # Farago et al. eq. (6), offsets in g
        return _jacobian_lm(p_g, as_vectors(means, "means") / g, central=True)

    def interval_dict(self, hw: np.ndarray) -> dict:
        return {"K": k_matrix(hw).tolist(), "o": hw[6:9].tolist()}

    def body_dict(self) -> dict:
        return {"solver": self.solver, **super().body_dict()}

    @classmethod
    def _from_body(cls, data: dict) -> TriangularCalibration:
        model, _, common = cls.common_from_dict(data)
        return cls(
            **cls.parameters_from(model),
            solver=data.get("solver", "lm"),
            **common,
        )


def _validated(means, gravity, solver: str, max_iter) -> tuple[float, np.ndarray]:
    """Checked gravity and readings (Farago, Maczak and Gingl, IEEE Access, section II: N ≥ 9)."""
    if solver not in SOLVERS:
        raise CalibrationError(f"unknown solver {solver!r}: use one of {', '.join(SOLVERS)}")
    g = check_gravity(gravity)
    m = check_sphere_points(means, g, min_points=N_PARAMS, method="triangular", n_params=N_PARAMS)
    if not (isinstance(max_iter, (int, np.integer)) and max_iter >= 1):
        raise CalibrationError(f"max_iter must be a positive integer; got {max_iter!r}")
    return g, m


def _least_squares_lm(v: np.ndarray):
    """Levenberg–Marquardt on the residuals of :func:`_residuals_lm` from p₀ (module docstring)."""
    return least_squares(
        _residuals_lm, P0.copy(), jac=_jacobian_lm, args=(v,), method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15
    )


def _solve(
    v: np.ndarray, solver: str, *, max_iter, h, learning_rates, metrics: dict, gates: Gates
) -> tuple[np.ndarray, bool]:
    """Parameters p (in g) by the chosen solver: ``lm``, or the descent of Farago, Maczak and Gingl,
    IEEE Access, eqs. (12)–(16) in floating or fixed point; raise when it diverged."""
    if solver == "lm":
        sol = _least_squares_lm(v)
        p_g, converged = sol.x, bool(sol.success)
        metrics["iterations"] = int(sol.nfev)
        if not converged:
            gates.fail(f"the Levenberg–Marquardt fit did not converge ({sol.message}); add positions")
    elif solver == "gradient":
        hh = H_FLOAT if h is None else float(h)
        p_g, its = gradient_descent(v, h=hh, alphas=learning_rates, max_iter=int(max_iter))
        metrics.update(iterations=its, h=hh)
        converged = bool(np.all(np.isfinite(p_g)))
    else:
        bits = 16 if solver == "fixed16" else 32
        hh = (H_FIXED16 if bits == 16 else H_FIXED32) if h is None else float(h)
        run = fixed_point_descent(v, bits=bits, h=hh, alphas=alpha_vector(learning_rates), max_iter=int(max_iter))
        p_g, converged = run.p, True
        metrics.update(
            iterations=run.iterations, h=run.h, q_format=run.q_format, p_raw=run.p_raw.tolist(), saturated=run.saturated
        )
        if run.saturated:
            gates.warn(
                f"the {bits}-bit fixed-point descent saturated ({run.q_format}): the readings or the "
                "parameters left the number range; check the unit"
            )
    if not np.all(np.isfinite(p_g)):
        raise CalibrationError(
            f"the {solver} descent diverged to non-finite parameters: the readings are too far from "
            "a sphere of radius gravity for its fixed learning rates; check the unit and gravity, "
            "or use solver 'lm'"
        )
    return p_g, converged


def _distance_to_lm(v: np.ndarray, p_g: np.ndarray, solver: str, metrics: dict, gates: Gates) -> None:
    """How far a descent stopped from the least-squares optimum, in that optimum's 95 % intervals."""
    ref = _least_squares_lm(v)
    J_ref = _jacobian_lm(ref.x, v, central=True)
    cov_ref, dof_ref, _ = covariance_from_jacobian(J_ref, ref.fun)
    if cov_ref is None:
        return
    dist = float(np.max(np.abs(p_g - ref.x) / half_widths(cov_ref, dof_ref)))
    metrics["distance_to_lm"] = dist
    gates.warn(
        limit_gate(
            dist,
            1.0,
            "the {solver} solver stopped {value:.1f} times the 95 % interval from the "
            "least-squares optimum (iteration cap, finite-difference step or number format); "
            "use solver 'lm' for the best estimate",
            solver=solver,
        )
    )


def _covariance(p_g: np.ndarray, v: np.ndarray, g: float) -> tuple[np.ndarray | None, int, float, float]:
    """Covariance of p by Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (22) with
    V(ε) = σ² I, σ² from the residuals (in g); the offsets scaled back to the readings' unit.

    Returns the covariance, the residual dof, σ² and the condition number of the column-scaled
    Jacobian.
    """
    J = _jacobian_lm(p_g, v, central=True)
    r = _residuals_lm(p_g, v)
    cov, dof, sigma2 = covariance_from_jacobian(J, r)
    if cov is not None:
        scale = np.r_[np.ones(6), np.full(3, g)]  # offsets back to the readings' unit
        cov = cov * np.outer(scale, scale)
    col = np.linalg.norm(J, axis=0)
    cond = float(np.linalg.cond(J / np.where(col > 0, col, 1.0)))
    return cov, dof, sigma2, cond


def _metrics(m, K, o, g, sigma2, cond, converged, dof, metrics: dict) -> np.ndarray:
    """Norm errors of Farago, Maczak and Gingl, IEEE Access, Table 3 and the cost of eq. (12), added
    to ``metrics``; returns the relative calibrated norm error of each reading."""
    cal = (m + o) @ K.T
    norm_err = np.abs(np.linalg.norm(cal, axis=1) - g) / g
    norm_err_raw = np.abs(np.linalg.norm(m, axis=1) - g) / g
    metrics.update(
        {
            "norm_error_max": float(norm_err.max()),
            "norm_error_max_raw": float(norm_err_raw.max()),
            # Farago, Maczak and Gingl, IEEE Access, Table 3: mean | |r| − 1 g | in mg, fitted points.
            "error_before_mg": float(1000.0 * norm_err_raw.mean()),
            "error_after_mg": float(1000.0 * norm_err.mean()),
            "improvement": float(norm_err_raw.mean() / norm_err.mean()) if norm_err.mean() > 0 else None,
            # Eq. (12) with and without the square root, in g², mean over the points.
            "cost_12": float(np.mean((np.linalg.norm(cal, axis=1) / g - 1.0) ** 2)),
            "noise_estimate": float(np.sqrt(sigma2) * g) if np.isfinite(sigma2) else None,
            "condition_number": cond,
            "converged": converged,
            "dof": dof,
            "count": int(len(m)),
        }
    )
    return norm_err


def _gates(m, K, o, g, norm_err, cond, dof, hemisphere, solver, plausible_scale, max_offset, gates: Gates) -> None:
    """Quality gates: hemisphere, norm error, scales, offsets (reasons); misalignments,
    conditioning, coverage of Farago, Maczak and Gingl, IEEE Access, eq. (10), near duplicates,
    an exact fit (warnings)."""
    gates.fail(
        hemisphere_gate(
            hemisphere,
            "all positions lie in one hemisphere (around the direction {direction}): the offsets cannot be "
            "told from the scales; add positions with the device turned the other way up",
        )
    )
    gates.fail(
        residual_gate(
            norm_err,
            MAX_NORM_ERROR,
            "reading {index} has a calibrated norm {percent:.1f} % from g (gate {gate_percent:.0f} %): it may "
            "not have been still, or the {solver} solver did not reach the minimum",
            solver=solver,
        )
    )
    gates.fail(
        scale_gate(
            np.diag(K),
            plausible_scale,
            "scale k_{axis}{axis} is {value:.4f}, outside the plausible {lo}–{hi}: check the unit and the gravity "
            "value",
        )
    )
    gates.fail(
        offset_gate(
            o,
            g if max_offset is None else max_offset,
            "offset o_{axis} is {value:.4g}, above 1 g in magnitude: check the unit",
        )
    )
    gates.warn(
        deviation_gate(
            (("k_xy", K[1, 0]), ("k_xz", K[2, 0]), ("k_yz", K[2, 1])),
            0.0,
            MAX_MISALIGNMENT,
            "misalignment {name} = {value:.3f} is implausibly large (above {limit})",
        )
    )
    unknown_orientation_gates(
        gates,
        m,
        g,
        condition=cond,
        max_condition=MAX_CONDITION_NUMBER,
        dof=dof,
        hemisphere=hemisphere,
        near_fraction=NEAR_DUPLICATE_FRACTION,
        coverage_hint=" (Farago et al. eq. (10): two per bin)",
        positions_hint="use 18 positions (Farago et al.)",
    )


def fit_triangular(
    means,
    *,
    gravity: float,
    solver: str = "lm",
    max_iter: int = MAX_ITER,
    h: float | None = None,
    learning_rates=LEARNING_RATES,
    plausible_scale: tuple[float, float] | None = PLAUSIBLE_SCALE,
    max_offset: float | None = None,
) -> TriangularCalibration:
    """Fit the 9-parameter lower-triangular model ``a = K (v + o)`` of Farago, Maczak and Gingl, IEEE
    Access to still readings.

    Parameters
    ----------
    means : array_like, shape (N, 3)
        Averaged still readings in N ≥ 9 different orientations (Farago, Maczak and Gingl, IEEE Access
        recommends 18, two per bin of
        eq. (10)), in the unit of ``gravity``.
    gravity : float
        Reference magnitude (1 for readings in g, 9.80665 for m/s²…).
    solver : {"lm", "gradient", "fixed16", "fixed32"}
        See the module docstring; ``lm`` is the default and the most accurate.
    max_iter : int
        Iteration cap of the descents (50 in the paper); ignored by ``lm``.
    h : float, optional
        Finite-difference spacing of the descents; defaults to 1e-5 (``gradient``, ``fixed32``)
        and 0.01 (``fixed16``), as Farago, Maczak and Gingl, IEEE Access, section II.C recommends.
    learning_rates : (float, float, float)
        α_s, α_m, α_o of eq. (16) for the descents.
    plausible_scale : (float, float) or None
        Bounds of the diagonal of K that pass the gate; None to skip.
    max_offset : float or None
        Largest |o| that passes the gate; defaults to ``gravity`` (1 g).

    Returns
    -------
    TriangularCalibration

    Raises
    ------
    CalibrationError
        Wrong shapes, non-finite values, unknown solver.
    InsufficientDataError
        Fewer than 9 positions, or fewer than 9 distinct ones.
    """
    g, m = _validated(means, gravity, solver, max_iter)
    hemisphere = one_hemisphere_axis(m)
    v = m / g  # the paper works in g
    gates = Gates()
    metrics: dict = {"solver": solver}
    p_g, converged = _solve(
        v, solver, max_iter=max_iter, h=h, learning_rates=learning_rates, metrics=metrics, gates=gates
    )
    if solver != "lm":
        _distance_to_lm(v, p_g, solver, metrics, gates)
    K = k_matrix(p_g)
    o = p_g[6:9] * g
    cov, dof, sigma2, cond = _covariance(p_g, v, g)
    norm_err = _metrics(m, K, o, g, sigma2, cond, converged, dof, metrics)
    _gates(m, K, o, g, norm_err, cond, dof, hemisphere, solver, plausible_scale, max_offset, gates)
    return TriangularCalibration(
        K=K,
        o=o,
        gravity=g,
        means=m,
        solver=solver,
        covariance=cov,
        dof=dof,
        metrics=metrics,
        **gates.fields(),
    )
