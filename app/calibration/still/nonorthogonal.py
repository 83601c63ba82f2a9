"""Unknown-orientation calibration with non-orthogonal axes: Georgieva et al., ESGI'95, Approach 1.

Georgieva et al., ESGI'95, section 2.  Each accelerometer reading â is shifted and scaled,
``a = (â − s) / b`` component-wise (eq. (1)); a = (a_x, a_y, a_z) are the projections of the
acceleration onto the three sensing axes, which make the angles φ = ∠(Ox, Oy), ψ = ∠(Ox, Oz) and
θ = ∠(Oy, Oz) (eq. (3)).  The affine coordinates are ``ā = T̄ a`` (eq. (5), T̄ the inverse of the
Gram matrix of the axes, eq. (8)), and the coordinates in the orthonormal frame f₁ = e₁, f₂ in the
e₁e₂ plane (Proposition 3) are ``ā_orth = T̄_orth ā`` (eqs. (12), (15)), so that the calibrated
value is eq. (16): ``ā_orth = T̄_orth T̄ T â − T̄_orth T̄ s``.

The fit (section 2.2) first fits the orthogonal model (all angles π/2) to fix the signs of the
parameters, then minimises (17), ``Σ (|ā_orth⁽ⁱ⁾|² − g²)²``, over all nine parameters under those
sign restrictions.

Sign convention.  The norm in (17) is unchanged when all three scales b change sign (the angles
then stay the same), so the sign of b is not determined by the data.  trical fixes b > 0, which keeps
the calibrated values in the device frame of the readings (the axis that points up reads +g).  The
paper prints negative scales (Georgieva et al., ESGI'95, section 2.4); their magnitudes, the shifts and
the angles are the
same as ours.  The signs of the shifts s come from the rough orthogonal fit, as in the paper.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import OptimizeResult, least_squares

from ..shared.errors import CalibrationError
from ..shared.gates import (
    Gates,
    deviation_gate,
    hemisphere_gate,
    offset_gate,
    residual_gate,
    scale_gate,
    unknown_orientation_gates,
)
from ..shared.result import StillReadingsResult, parameter
from ..shared.uncertainty import covariance_from_jacobian
from ..shared.validation import as_vectors, check_gravity, check_sphere_points, one_hemisphere_axis

MODEL_TYPE = "nonorthogonal"

N_PARAMS = 9
"""s (3), b (3), φ, ψ, θ."""

PARAM_NAMES = ("s1", "s2", "s3", "b1", "b2", "b3", "phi", "psi", "theta")

PLAUSIBLE_SCALE = (0.8, 1.2)
"""|b| outside this range is implausible for a MEMS accelerometer read in its own unit (docs/methods.md)."""

MAX_ANGLE_DEVIATION = 0.05 * np.pi / 2
"""Angles further than 5 % from π/2 are flagged; Georgieva et al., ESGI'95, section 2 assumes 90° ± 2 %."""

MAX_NORM_ERROR = 0.05
"""A fitted position whose calibrated norm is further than 5 % from g fails the fit (ok = false)."""

NEAR_DUPLICATE_FRACTION = 0.01
"""Positions closer than 1 % of g to each other are named as near duplicates (docs/rest.md)."""

MAX_CONDITION_NUMBER = 30.0
"""Above this condition number of the column-scaled Jacobian the parameters are poorly determined."""


# ---------------------------------------------------------------------------------------------
# The model, eqs. (1)–(16)
# ---------------------------------------------------------------------------------------------


def gram_matrix(phi: float, psi: float, theta: float) -> np.ndarray:
    """Matrix of system (8): the Gram matrix of the unit vectors e₁, e₂, e₃ along the axes."""
    cf, cp, ct = np.cos(phi), np.cos(psi), np.cos(theta)
    # Georgieva et al., ESGI'95, eq. (8)
    return np.array([[1.0, cf, cp], [cf, 1.0, ct], [cp, ct, 1.0]])


def affine_matrix(phi: float, psi: float, theta: float) -> np.ndarray:
    """T̄ of Remark 2: affine coordinates ā from the projections a, ā = T̄ a (Georgieva et al.,
    ESGI'95, eq. (5))."""
    cf, cp, ct = np.cos(phi), np.cos(psi), np.cos(theta)
    # Georgieva et al., ESGI'95, eq. (5) / Remark 2: den = −1 + cos²φ + cos²ψ + cos²θ − 2 cosφ cosψ cosθ.
    den = -1.0 + cf**2 + cp**2 + ct**2 - 2.0 * cf * cp * ct
    return (
        np.array(
            [
                [-(np.sin(theta) ** 2), cf - ct * cp, cp - cf * ct],
                [cf - ct * cp, -(np.sin(psi) ** 2), ct - cf * cp],
                [cp - cf * ct, ct - cf * cp, -(np.sin(phi) ** 2)],
            ]
        )
        / den
    )


def orthonormal_matrix(phi: float, psi: float, theta: float) -> np.ndarray:
    """T̄_orth of Proposition 3: coordinates in the orthonormal frame f from ā (Georgieva et al.,
    ESGI'95, eq. (12)).

    Its columns are e₁, e₂, e₃ in the frame f₁ = e₁, f₂ in the e₁e₂ plane (eq. (15) uses it as
    ``ā_orth = T̄_orth ā``).
    """
    cf, cp, ct = np.cos(phi), np.cos(psi), np.cos(theta)
    sf = np.sin(phi)
    det = 1.0 - cf**2 - cp**2 - ct**2 + 2.0 * cf * cp * ct
    if det <= 0.0:
        raise CalibrationError(f"angles φ={phi}, ψ={psi}, θ={theta} do not describe three independent axes")
    # Georgieva et al., ESGI'95, eq. (12)
    return np.array(
        [
            [1.0, cf, cp],
            [0.0, sf, (ct - cf * cp) / sf],
            [0.0, 0.0, np.sqrt(det) / sf],
        ]
    )


def calibration_matrix(b, phi: float, psi: float, theta: float) -> np.ndarray:
    """M = T̄_orth T̄ T of eq. (16), so that ā_orth = M (â − s)."""
    T = np.diag(1.0 / np.asarray(b, dtype=float))  # Georgieva et al., ESGI'95, eq. (1)–(2)
    return orthonormal_matrix(phi, psi, theta) @ affine_matrix(phi, psi, theta) @ T


def _squared_norms(p: np.ndarray, m: np.ndarray) -> np.ndarray:
    """|ā_orth|² = aᵀ G⁻¹ a with a = (â − s)/b (eqs. (1), (5), (9)); faster than building eq. (16)."""
    s, b = p[:3], p[3:6]
    a = (m - s) / b
    G = gram_matrix(*p[6:9])
    return np.einsum("ij,ij->i", a, np.linalg.solve(G, a.T).T)


def _residuals_17(p: np.ndarray, m: np.ndarray, g: float) -> np.ndarray:
    """Terms of the sum (17): |ā_orth⁽ⁱ⁾|² − g²."""
    return _squared_norms(p, m) - g * g


def _jacobian_17(p: np.ndarray, m: np.ndarray, g: float) -> np.ndarray:
    """Analytic Jacobian of the terms of (17) with respect to (s, b, φ, ψ, θ)."""
    s, b = p[:3], p[3:6]
    a = (m - s) / b
    G = gram_matrix(*p[6:9])
    Gi = np.linalg.inv(G)
    w = a @ Gi  # rows G⁻¹ a (G symmetric)
    J = np.empty((len(m), N_PARAMS))
    # ∂(aᵀG⁻¹a)/∂a = 2 G⁻¹ a; ∂a_k/∂s_k = −1/b_k; ∂a_k/∂b_k = −a_k/b_k.
    J[:, 0:3] = -2.0 * w / b
    J[:, 3:6] = -2.0 * w * a / b
    # ∂(aᵀG⁻¹a)/∂G_jk = −(G⁻¹a)_j (G⁻¹a)_k; G_12 = G_21 = cos φ, etc.
    for col, (j, k), ang in ((6, (0, 1), p[6]), (7, (0, 2), p[7]), (8, (1, 2), p[8])):
        J[:, col] = -2.0 * w[:, j] * w[:, k] * (-np.sin(ang))
    return J


# ---------------------------------------------------------------------------------------------
# Result
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class NonOrthogonalCalibration(StillReadingsResult):
    """Result of the non-orthogonal-axes (9-parameter) calibration, Georgieva et al. Approach 1.

    Attributes
    ----------
    s : numpy.ndarray, shape (3,)
        Shifts s₁, s₂, s₃ of eq. (1), in the unit of the readings.
    b : numpy.ndarray, shape (3,)
        Scaling coefficients b₁, b₂, b₃ of eq. (1), dimensionless, positive (module docstring).
    phi, psi, theta : float
        Angles ∠(Ox, Oy), ∠(Ox, Oz), ∠(Oy, Oz) between the sensing axes in radians (eq. (3)).
    gravity : float
        Reference magnitude g of (17), in the unit of the readings.
    means : numpy.ndarray, shape (N, 3)
        The fitted readings â⁽ⁱ⁾.
    covariance : numpy.ndarray or None
        Covariance (9, 9) of (s₁, s₂, s₃, b₁, b₂, b₃, φ, ψ, θ); None without degrees of freedom.
    dof : int
        Residual degrees of freedom, N − 9.
    metrics, warnings, reasons
        As in :class:`~app.calibration.still.affine.AffineCalibration`.
    """

    s: np.ndarray = parameter()
    b: np.ndarray = parameter()
    phi: float = parameter()
    psi: float = parameter()
    theta: float = parameter()
    method: str = MODEL_TYPE

    RESULT_TYPE = MODEL_TYPE
    MODEL_TYPE = MODEL_TYPE
    N_PARAMS = N_PARAMS
    CORRECTION_SOURCE = "Georgieva et al., ESGI'95, eq. (16): M = T_orth T_bar T, o = s / b"
    AS_FITTED = (
        "As fitted (Georgieva et al., ESGI'95, eq. (16)): shifts s, scales b and the angles φ, ψ, θ between "
        "the axes; M and o are what they come to."
    )
    PARAMETERS = (
        ("s1", "offset", "x"),
        ("s2", "offset", "y"),
        ("s3", "offset", "z"),
        ("b1", "scale", "x"),
        ("b2", "scale", "y"),
        ("b3", "scale", "z"),
        ("phi", "cross", "xy"),
        ("psi", "cross", "xz"),
        ("theta", "cross", "yz"),
    )
    """Name, kind and axes of each parameter in the covariance's order (eqs. (1), (3))."""

    @property
    def params(self) -> np.ndarray:
        """(s₁, s₂, s₃, b₁, b₂, b₃, φ, ψ, θ)."""
        return np.r_[self.s, self.b, self.phi, self.psi, self.theta]

    @property
    def matrix(self) -> np.ndarray:
        """T̄_orth T̄ T of eq. (16): calibrated = matrix @ (raw − s)."""
        return calibration_matrix(self.b, self.phi, self.psi, self.theta)

    def _calibrate(self, rows: np.ndarray) -> np.ndarray:
        # Georgieva et al. eq. (16): T̄_orth T̄ T â − T̄_orth T̄ s with the vector s = T (s₁, s₂, s₃) of eq. (2),
        # i.e. T̄_orth T̄ T (â − s), in the orthonormal frame of Proposition 3: f₁ along the sensor's x axis,
        # f₂ in the plane of its x and y axes.
        return (rows - self.s) @ self.matrix.T

    def jacobian(self, means) -> np.ndarray:
        """Jacobian (N, 9) of the terms of (17) for readings ``means`` (N, 3) with respect to
        (s, b, φ, ψ, θ) at the fitted parameters: what each reading adds to the information JᵀJ
        behind :attr:`covariance` (app.calibration.still.advice)."""
        return _jacobian_17(self.params, as_vectors(means, "means"), self.gravity)

    def interval_dict(self, hw: np.ndarray) -> dict:
        return {
            "s": hw[0:3].tolist(),
            "b": hw[3:6].tolist(),
            "phi": float(hw[6]),
            "psi": float(hw[7]),
            "theta": float(hw[8]),
        }

    @classmethod
    def _from_body(cls, data: dict) -> NonOrthogonalCalibration:
        model, _, common = cls.common_from_dict(data)
        return cls(**cls.parameters_from(model), **common)


# ---------------------------------------------------------------------------------------------
# Fit, section 2.2
# ---------------------------------------------------------------------------------------------


def _ellipsoid_start(m: np.ndarray, g: float) -> tuple[np.ndarray, np.ndarray]:
    """Centre and semi-axes of the axis-aligned ellipsoid through the readings (linear LS).

    ``Σ_k A_k x_k² + B_k x_k = 1`` is linear in (A, B); it starts the rough fit of step 2 so that
    no starting guess has to be made.
    """
    design = np.hstack([m**2, m])
    coef, *_ = np.linalg.lstsq(design, np.ones(len(m)), rcond=None)
    A, B = coef[:3], coef[3:]
    if np.all(A > 0):
        centre = -B / (2.0 * A)
        rhs = 1.0 + np.sum(B**2 / (4.0 * A))
        radii = np.sqrt(rhs / A)
        if np.all(np.isfinite(radii)):
            return centre, radii / g
    return m.mean(axis=0), np.ones(3)


def _rough_orthogonal_fit(m: np.ndarray, g: float) -> OptimizeResult:
    """Step 2 of section 2.2: minimise Σ [(Tâ − s)ᵀ(Tâ − s) − g²]² with all angles π/2."""
    centre, scale = _ellipsoid_start(m, g)

    def res(q):
        # Georgieva et al., ESGI'95, section 2.2, step 2 (eq. (2) with orthogonal axes), parametrised
        # by the shifts s_i
        # and scales b_i of eq. (1).
        a = (m - q[:3]) / q[3:]
        return np.sum(a * a, axis=1) - g * g

    return least_squares(res, np.r_[centre, scale], method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)


def _sign_bounds(rough, s0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sign restrictions of step 3 of Georgieva et al., ESGI'95, section 2.2.

    Each shift keeps the sign of the rough fit unless the rough fit cannot tell it from zero
    (|s| below 3 standard errors); b > 0 (module docstring); the angles in (0, π).
    """
    cov0, _, _ = covariance_from_jacobian(rough.jac, rough.fun)
    se0 = np.full(3, np.inf) if cov0 is None else np.sqrt(np.clip(np.diag(cov0)[:3], 0, None))
    lower = np.r_[np.full(3, -np.inf), np.full(3, 1e-9), np.full(3, 1e-6)]
    upper = np.r_[np.full(3, np.inf), np.full(3, np.inf), np.full(3, np.pi - 1e-6)]
    for k in range(3):
        if abs(s0[k]) > 3.0 * se0[k]:
            if s0[k] > 0:
                lower[k] = 0.0
            else:
                upper[k] = 0.0
    return lower, upper


def _fit_17(m: np.ndarray, g: float, rough, s0: np.ndarray, b0: np.ndarray):
    """Minimise Georgieva et al., ESGI'95, eq. (17) over the nine parameters, from the rough fit,
    under the sign restrictions of :func:`_sign_bounds`."""
    lower, upper = _sign_bounds(rough, s0)
    p0 = np.r_[s0, b0, np.full(3, np.pi / 2)]
    p0 = np.clip(p0, lower + 1e-12, upper - 1e-12)
    return least_squares(
        _residuals_17,
        p0,
        jac=_jacobian_17,
        args=(m, g),
        bounds=(lower, upper),
        method="trf",
        x_scale="jac",
        xtol=1e-15,
        ftol=1e-15,
        gtol=1e-15,
        max_nfev=2000,
    )


def _covariance(p: np.ndarray, m: np.ndarray, g: float):
    """Covariance and dof of the parameters from the Jacobian of the terms of (17), the terms
    themselves, and the condition number of the column-scaled Jacobian."""
    J = _jacobian_17(p, m, g)
    r = _residuals_17(p, m, g)
    cov, dof, _ = covariance_from_jacobian(J, r)
    col = np.linalg.norm(J, axis=0)
    cond = float(np.linalg.cond(J / np.where(col > 0, col, 1.0)))
    return cov, dof, r, cond


def _metrics(m, g, p, s, b, r, cond, s0, b0, sol, dof) -> tuple[dict, np.ndarray]:
    """Relative norm errors of Georgieva et al., ESGI'95, section 2.4, after eq. (16)."""
    norms = np.linalg.norm((m - s) @ calibration_matrix(b, *(float(v) for v in p[6:9])).T, axis=1)
    norm_err = np.abs(norms - g) / g
    norm_err_raw = np.abs(np.linalg.norm(m, axis=1) - g) / g
    metrics = {
        # Georgieva et al., ESGI'95, section 2.4: relative error |(a − g)/g|, fitted positions.
        "norm_error_max": float(norm_err.max()),
        "norm_error_max_raw": float(norm_err_raw.max()),
        "error_before_mg": float(1000.0 * norm_err_raw.mean()),
        "error_after_mg": float(1000.0 * norm_err.mean()),
        "norm_improvement": float(norm_err_raw.max() / norm_err.max()) if norm_err.max() > 0 else None,
        "rms_norm_residual": float(np.sqrt(np.mean((norms - g) ** 2))),
        "cost_17": float(np.sum(r**2)),
        "condition_number": cond,
        "angle_deviation_max_deg": float(np.degrees(np.max(np.abs(p[6:9] - np.pi / 2)))),
        "rough_s": s0.tolist(),
        "rough_b": b0.tolist(),
        "converged": bool(sol.success),
        "dof": dof,
        "count": int(len(m)),
    }
    return metrics, norm_err


def _gates(m, g, s, b, angles, norm_err, cond, dof, hemisphere, sol, plausible_scale, max_offset) -> Gates:
    """Quality gates: hemisphere, convergence, norm error, scales, shifts (reasons); angles,
    conditioning, coverage, near duplicates, an exact fit (warnings)."""
    gates = Gates()
    gates.fail(
        hemisphere_gate(
            hemisphere,
            "all positions lie in one hemisphere (around the direction {direction}): the shifts cannot be "
            "told from the scales; add positions with the device turned the other way up",
        )
    )
    if not sol.success:
        gates.fail(f"the least-squares fit of (17) did not converge ({sol.message}); add positions")
    gates.fail(
        residual_gate(
            norm_err,
            MAX_NORM_ERROR,
            "reading {index} has a calibrated norm {percent:.1f} % from g after "
            "calibration (gate {gate_percent:.0f} %): it may not have been still",
        )
    )
    gates.fail(
        scale_gate(
            b,
            plausible_scale,
            "scale b{n} of the {axis} axis is {value:.4f}, outside the plausible {lo}–{hi}: "
            "check the unit and the gravity value",
        )
    )
    gates.fail(
        offset_gate(
            s,
            g if max_offset is None else max_offset,
            "shift s{n} of the {axis} axis is {value:.4g}, above 1 g in magnitude: check the unit",
        )
    )
    gates.warn(
        deviation_gate(
            zip(("phi", "psi", "theta"), angles),
            np.pi / 2,
            MAX_ANGLE_DEVIATION,
            lambda name, value, **_: (
                f"the angle {name} between the axes is {np.degrees(value):.2f}°, more than 5 % from 90° "
                "(Georgieva et al. section 2 assumes 90° ± 2 %): check the positions"
            ),
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
        positions_hint="use about 20 positions",
    )
    return gates


def fit_nonorthogonal(
    means,
    *,
    gravity: float,
    plausible_scale: tuple[float, float] | None = PLAUSIBLE_SCALE,
    max_offset: float | None = None,
) -> NonOrthogonalCalibration:
    """Fit the non-orthogonal-axes model of Georgieva et al., ESGI'95, Approach 1 to still readings of
    unknown orientation.

    Two steps (Georgieva et al., ESGI'95, section 2.2): a rough fit of the orthogonal model (angles
    π/2) fixes the signs
    of the shifts; the nine parameters then minimise (17), ``Σ (|ā_orth⁽ⁱ⁾|² − g²)²``, under those
    sign restrictions, with b > 0 (module docstring) and the angles in (0, π).

    Parameters
    ----------
    means : array_like, shape (N, 3)
        Averaged still readings â⁽ⁱ⁾ in N ≥ 9 different positions (the paper uses 20).
    gravity : float
        Reference magnitude g, in the unit of the readings (1 for readings in g).
    plausible_scale : (float, float) or None
        Bounds of the scales b that pass the gate; None for raw units.
    max_offset : float or None
        Largest |s| that passes the gate; defaults to ``gravity`` (1 g).

    Returns
    -------
    NonOrthogonalCalibration

    Raises
    ------
    CalibrationError
        Wrong shapes, non-finite values.
    InsufficientDataError
        Fewer than 9 positions, or fewer than 9 distinct ones (e.g. all identical).
    """
    g = check_gravity(gravity)
    m = check_sphere_points(means, g, min_points=N_PARAMS, method="nonorthogonal", n_params=N_PARAMS)
    hemisphere = one_hemisphere_axis(m)
    rough = _rough_orthogonal_fit(m, g)
    s0, b0 = rough.x[:3], np.abs(rough.x[3:])
    sol = _fit_17(m, g, rough, s0, b0)
    p = sol.x
    s, b = p[:3].copy(), p[3:6].copy()
    phi, psi, theta = (float(v) for v in p[6:9])
    cov, dof, r, cond = _covariance(p, m, g)
    metrics, norm_err = _metrics(m, g, p, s, b, r, cond, s0, b0, sol, dof)
    gates = _gates(m, g, s, b, (phi, psi, theta), norm_err, cond, dof, hemisphere, sol, plausible_scale, max_offset)
    return NonOrthogonalCalibration(
        s=s,
        b=b,
        phi=phi,
        psi=psi,
        theta=theta,
        gravity=g,
        means=m,
        covariance=cov,
        dof=dof,
        metrics=metrics,
        **gates.fields(),
    )
