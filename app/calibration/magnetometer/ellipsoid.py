"""Closed-form starts of a compass calibration: the algebraic ellipsoid fit and the sphere fit.

A magnetometer turned in a uniform field ``h`` (|h| = F) reads ``m = M⁻¹ h + b``: the hard iron
``b`` shifts the sphere of radius F, the soft iron and the axes' gains and misalignments (the
symmetric ``M⁻¹``) stretch it into an ellipsoid,

    (m − b)ᵀ A (m − b) = 1,   A = Mᵀ M / F²

— the magnetometer model ỹ = S h + b of Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (6),
with ``S = M⁻¹`` and the attitude unknown; the ellipsoid is that of Vasconcelos, Elkaim, Silvestre,
Oliveira and Cardeira, "Geometric Approach to Strapdown Magnetometer Calibration in Sensor Frame",
IEEE Trans. Aerospace and Electronic Systems 47(2) 2011, section III.
Both fits here are linear least squares on that quadric; they minimise an algebraic, not the
geometric, distance, so they start the Levenberg–Marquardt refinement of :mod:`.refine` and serve
as the plain peers of ``bench/compass.py``.
"""

from __future__ import annotations

import numpy as np

from ..shared.errors import CalibrationError


def _normalised(m: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Readings centred on their mean and scaled to unit RMS radius: the quadric's design matrix of
    raw µT with a hard iron of hundreds of µT is badly conditioned (terms of 10⁵ beside 1)."""
    centre = m.mean(axis=0)
    scale = float(np.sqrt(np.mean(np.sum((m - centre) ** 2, axis=1)))) or 1.0
    return (m - centre) / scale, centre, scale


def _symmetric_sqrt(A: np.ndarray) -> np.ndarray:
    w, V = np.linalg.eigh(0.5 * (A + A.T))
    return (V * np.sqrt(w)) @ V.T


def fit_ellipsoid(mag, field: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """The algebraic least-squares ellipsoid through the readings, as ``h = M (m − b)``.

    Fits ``a x² + b y² + c z² + 2d xy + 2e xz + 2f yz + 2g x + 2h y + 2i z = 1`` (9 unknowns) to the
    normalised readings; then ``A = [[a, d, e], [d, b, f], [e, f, c]]``, the centre
    ``b = −A⁻¹ (g, h, i)``, ``k = 1 + bᵀ A b`` and the symmetric ``M = F (A / k)^½``: completing
    the square, ``(m − b)ᵀ (A / k) (m − b) = 1``.

    Parameters
    ----------
    mag : array_like, shape (N, 3)
        Raw readings, N ≥ 9.
    field : float
        The magnitude F the calibrated readings take.

    Returns
    -------
    M : numpy.ndarray, shape (3, 3)
        Symmetric, positive definite.
    b : numpy.ndarray, shape (3,)

    Raises
    ------
    CalibrationError
        The quadric is not an ellipsoid (the readings lie on a plane, a cylinder, too few directions).
    """
    m = np.asarray(mag, dtype=float).reshape(-1, 3)
    u, centre, scale = _normalised(m)
    x, y, z = u.T
    D = np.column_stack([x * x, y * y, z * z, 2 * x * y, 2 * x * z, 2 * y * z, 2 * x, 2 * y, 2 * z])
    theta, *_ = np.linalg.lstsq(D, np.ones(len(u)), rcond=None)
    a, bb, c, d, e, f, g, h, i = theta
    A = np.array([[a, d, e], [d, bb, f], [e, f, c]])
    if not np.all(np.linalg.eigvalsh(A) > 0):
        raise CalibrationError("the readings do not lie on an ellipsoid: turn the device through all directions")
    centre_u = -np.linalg.solve(A, np.array([g, h, i]))
    k = 1.0 + centre_u @ A @ centre_u
    if not k > 0:
        raise CalibrationError("the readings do not lie on an ellipsoid: turn the device through all directions")
    M_u = _symmetric_sqrt(A / k)
    # h = F M_u (u − b_u) with u = (m − c)/s  ⇒  M = F M_u / s, b = c + s b_u
    return field * M_u / scale, centre + scale * centre_u


def fit_sphere(mag, field: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The hard-iron-only calibration: the least-squares sphere ``|m − b|² = r²``.

    Linear in ``(b, r² − |b|²)``: ``|m|² = 2 bᵀ m + (r² − |b|²)`` (the fit of ArduPilot's and PX4's
    offsets-only step). ``M = (F / r) I``, or ``I`` when ``field`` is None.

    Returns
    -------
    M : numpy.ndarray, shape (3, 3)
    b : numpy.ndarray, shape (3,)
    """
    m = np.asarray(mag, dtype=float).reshape(-1, 3)
    u, centre, scale = _normalised(m)
    D = np.column_stack([2 * u, np.ones(len(u))])
    sol, *_ = np.linalg.lstsq(D, np.sum(u * u, axis=1), rcond=None)
    b_u, rest = sol[:3], sol[3]
    r = scale * float(np.sqrt(max(rest + b_u @ b_u, 1e-300)))
    M = np.eye(3) if field is None else (field / r) * np.eye(3)
    return M, centre + scale * b_u
