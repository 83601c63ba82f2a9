"""The geometric refinement of a compass calibration and the covariance of its nine parameters.

The calibrated field ``h_i = M (m_i − b)`` of a device turned in a uniform field has the magnitude
F of that field, so ``M`` (symmetric: six numbers) and ``b`` minimise the sum of squared
magnitude residuals

    r_i = |M (m_i − b)| − F,

the maximum-likelihood criterion for readings with isotropic noise on a sphere (Vasconcelos et al.,
IEEE Trans. Aerospace and Electronic Systems 47(2) 2011, section IV), by Levenberg–Marquardt from
the algebraic ellipsoid of :mod:`.ellipsoid`.  The covariance at the solution is
``σ² (Jᵀ J)⁻¹`` (Särkkä et al., IEEE Sensors Journal 17(11) 2017, Appendix A, eq. (22), with
V(ε) = σ² I), inflated for the correlation of the residuals in time (see
:func:`correlation_inflation`).

The criterion has no finite minimum when the readings do not lie on one ellipsoid (a field that
changed during the turn, readings in one plane, a small cap): an ellipsoid whose centre and one axis
grow without bound, M nearly singular along them, lowers the cost towards zero while every calibrated
direction falls in one face.  :func:`runs_away` tells such a fit from a refinement, and the caller
keeps a closed form instead (:func:`held`), as ArduPilot's CompassCalibrator refuses a fit whose offsets or scale
factors leave their bounds (``fit_acceptable``: offsets under ``offset_max``, diagonal 0.2–5) and
MotionCal keeps its previous calibration when a new one's field leaves 22–67 µT.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np

from ..shared.uncertainty import covariance_from_jacobian

SYMMETRIC_INDEX = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))
"""Where the six free numbers of the symmetric M sit: the diagonal, then xy, xz, yz."""

N_PARAMETERS = 9

MAX_REACH = 3.0
"""How far a fitted ellipsoid may reach beyond the readings, in their own half-extent (half the
largest range of an axis): its longest semi-axis, and its centre's distance outside their bounding
box.  Readings over a cap of half-angle α (up to 90°) of a sphere of radius R span R sin α about its
centre, which lies R cos α from them, so a true fit stays within the bound for any cap wider than
about 20° (1 / sin α ≤ 3 and cos α / sin α ≤ 3).  Fits on simulated turns (full, 120° cap,
hemisphere) reach 1.2; the runaways of real turns reach 10 to 100 and beyond."""


def _structure_map(structure: str) -> tuple[np.ndarray, np.ndarray]:
    """``(D, c)`` of a structure's free numbers z to the nine of :func:`pack`, ``x = D z + c`` (affine): ``soft_iron``
    all nine; ``scale`` M diagonal (three scales and b); ``sphere`` M = s I (one scale and b); ``offsets`` M = I
    (b alone: the readings' unit taken as the field's)."""
    c = np.zeros(N_PARAMETERS)
    if structure == "soft_iron":
        return np.eye(N_PARAMETERS), c
    if structure == "scale":
        return np.eye(N_PARAMETERS)[:, [0, 1, 2, 6, 7, 8]], c
    if structure == "sphere":
        D = np.zeros((N_PARAMETERS, 4))
        D[0:3, 0] = 1.0
        D[6:9, 1:4] = np.eye(3)
        return D, c
    if structure == "offsets":
        c[0:3] = 1.0
        return np.eye(N_PARAMETERS)[:, 6:9], c
    raise ValueError(f"unknown structure {structure!r}: one of {', '.join(STRUCTURES)}")


STRUCTURES = ("soft_iron", "scale", "sphere", "offsets")
"""The models of ``h = M (m − b)``, richest first: M symmetric (hard and soft iron), M diagonal (hard iron and
a scale per axis), M = s I (hard iron and one scale: a sphere, ArduPilot's CompassCalibrator's first step), M = I
(hard iron alone, the readings' unit taken as the field's: what a compass read in µT near level determines)."""


def pack(M: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The parameter vector ``(M_xx, M_yy, M_zz, M_xy, M_xz, M_yz, b_x, b_y, b_z)``."""
    return np.array([M[i, j] for i, j in SYMMETRIC_INDEX] + list(b), dtype=float)


def unpack(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``M`` (symmetric) and ``b`` of a parameter vector (:func:`pack`)."""
    M = np.empty((3, 3))
    for value, (i, j) in zip(x[:6], SYMMETRIC_INDEX):
        M[i, j] = M[j, i] = value
    return M, np.asarray(x[6:9], dtype=float)


def residuals(x: np.ndarray, m: np.ndarray, field: float) -> np.ndarray:
    """``|M (m_i − b)| − F`` for every reading."""
    M, b = unpack(x)
    return np.linalg.norm((m - b) @ M.T, axis=1) - field


def jacobian(x: np.ndarray, m: np.ndarray, field: float) -> np.ndarray:
    """Derivatives of :func:`residuals` in the nine parameters.

    With ``u = m − b``, ``w = M u`` and ``n = w / |w|``: ``∂r/∂M_ij = n_i u_j`` (both entries of an
    off-diagonal pair: ``n_i u_j + n_j u_i``) and ``∂r/∂b = −Mᵀ n``.
    """
    M, b = unpack(x)
    u = m - b
    w = u @ M.T
    n = w / np.linalg.norm(w, axis=1, keepdims=True)
    J = np.empty((len(m), N_PARAMETERS))
    for k, (i, j) in enumerate(SYMMETRIC_INDEX):
        J[:, k] = n[:, i] * u[:, j] if i == j else n[:, i] * u[:, j] + n[:, j] * u[:, i]
    J[:, 6:] = -n @ M
    return J


@dataclass(frozen=True)
class Refined:
    """A refined compass calibration: ``M``, ``b``, the residuals and the parameters' covariance.

    ``covariance`` is None when the fit is undetermined (no residual degrees of freedom, or a
    singular ``Jᵀ J``); ``inflation`` is the factor the white-noise covariance was multiplied by.
    """

    M: np.ndarray
    b: np.ndarray
    residuals: np.ndarray
    covariance: np.ndarray | None
    dof: int
    sigma_ut: float
    inflation: float
    converged: bool


def correlation_inflation(r: np.ndarray) -> float:
    """Variance factor for residuals correlated in time: ``(1 + ρ) / (1 − ρ)``, at least 1.

    A device turned slowly by hand sees the same disturbance (a nearby steel part, the misfit of
    the model in one direction) on many consecutive readings, so N readings carry the information
    of fewer independent ones.  For an AR(1) sequence with lag-one autocorrelation ρ the variance
    of a mean grows by ``(1 + ρ) / (1 − ρ)`` (Bayley and Hammersley, "The 'effective' number of
    independent observations in an autocorrelated time series", J. R. Stat. Soc. Suppl. 8(2)
    1946); the same factor scales the least-squares covariance.  White noise (ρ ≈ 0) keeps it.
    """
    r = np.asarray(r, dtype=float) - np.mean(r)
    denominator = float(r @ r)
    if len(r) < 3 or denominator == 0.0:
        return 1.0
    rho = float(r[1:] @ r[:-1]) / denominator
    rho = min(rho, 0.99)
    return max(1.0, (1.0 + rho) / (1.0 - rho))


def runs_away(M: np.ndarray, b: np.ndarray, mag, field: float) -> bool:
    """Whether ``h = M (m − b)`` has left the readings: M not positive definite, or its ellipsoid's
    longest semi-axis (F over M's smallest eigenvalue) or its centre's distance outside the readings'
    bounding box above :data:`MAX_REACH` half-extents of the readings."""
    m = np.asarray(mag, dtype=float).reshape(-1, 3)
    lo, hi = m.min(axis=0), m.max(axis=0)
    half = 0.5 * float(np.max(hi - lo))
    if not (np.all(np.isfinite(M)) and np.all(np.isfinite(b)) and half > 0.0):
        return True
    smallest = float(np.linalg.eigvalsh(0.5 * (M + M.T))[0])
    if not smallest > 0.0:
        return True
    outside = float(np.max(np.maximum(np.maximum(lo - b, b - hi), 0.0)))
    return field / smallest > MAX_REACH * half or outside > MAX_REACH * half


def held(mag, M: np.ndarray, b: np.ndarray, field: float) -> Refined:
    """``(M, b)`` kept as they are (a closed form kept where the refinement ran away): its
    residuals, no covariance (the criterion is not at a minimum there) and ``converged`` false."""
    m = np.asarray(mag, dtype=float).reshape(-1, 3)
    M = 0.5 * (M + M.T)
    r = residuals(pack(M, b), m, field)
    dof = max(len(m) - N_PARAMETERS, 0)
    sigma = float(np.sqrt(r @ r / dof)) if dof else float("nan")
    return Refined(
        M=M,
        b=np.asarray(b, dtype=float),
        residuals=r,
        covariance=None,
        dof=dof,
        sigma_ut=sigma,
        inflation=correlation_inflation(r),
        converged=False,
    )


def refine(
    mag, M0: np.ndarray, b0: np.ndarray, field: float, *, max_evaluations: int = 200, structure: str = "soft_iron"
) -> Refined:
    """Levenberg–Marquardt on ``|M (m − b)| − F`` from ``(M0, b0)``, and the covariance there.

    Parameters
    ----------
    mag : array_like, shape (N, 3)
        Raw readings in recording order (the order matters for the covariance's inflation).
    M0, b0 : numpy.ndarray
        The start (the algebraic ellipsoid or the sphere).
    field : float
        The field's magnitude F, in the unit the calibrated readings take.
    structure : {"soft_iron", "scale", "sphere", "offsets"}
        Which entries of M are free (:data:`STRUCTURES`); the start is projected onto it. The covariance is
        of the nine numbers of :func:`pack`, ``D C Dᵀ``, zero on the entries the structure holds.

    Returns
    -------
    Refined
    """
    m = np.asarray(mag, dtype=float).reshape(-1, 3)
    D, c = _structure_map(structure)
    z0 = np.linalg.lstsq(D, pack(0.5 * (M0 + M0.T), b0) - c, rcond=None)[0]  # the start's nearest of this structure

    def fun(z: np.ndarray) -> np.ndarray:
        return residuals(D @ z + c, m, field)

    def jac(z: np.ndarray) -> np.ndarray:  # x = D z + c is affine: the chain rule is one product
        return jacobian(D @ z + c, m, field) @ D

    from scipy.optimize import least_squares  # here: scipy.optimize takes ~0.4 s to import, which the server's

    sol = least_squares(  # start paid for the compass page's thresholds (app/web/tables.py)
        fun,
        z0,
        jac=jac,
        method="lm",
        x_scale="jac",
        max_nfev=max_evaluations,
    )
    M, b = unpack(D @ sol.x + c)
    if np.linalg.det(M) < 0:  # −M fits as well: keep the orientation of the readings
        M = -M
    r = sol.fun
    # a dense Jacobian: least_squares gives a sparse one or an operator only when asked to
    covariance, dof, sigma2 = covariance_from_jacobian(cast(np.ndarray, sol.jac), r)
    inflation = correlation_inflation(r)
    if covariance is not None:
        covariance = D @ (covariance * inflation) @ D.T
    return Refined(
        M=M,
        b=b,
        residuals=r,
        covariance=covariance,
        dof=dof,
        sigma_ut=float(np.sqrt(sigma2)) if dof else float("nan"),
        inflation=inflation,
        converged=bool(sol.status > 0),
    )
