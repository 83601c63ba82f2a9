"""The error of ignoring non-orthogonal axes: Georgieva et al. (ESGI'95), section 2.3.

With a = (a_x, a_y, a_z) the readings along three sensing axes that make the angles φ, ψ, θ
(Georgieva et al. eq. (3)), the true magnitude is ``a_nonorth`` of eq. (10) while an orthogonal model takes
``a_orth = sqrt(a_x² + a_y² + a_z²)`` (Proposition 1).  Section 2.3 defines
``err = |a_nonorth − a_orth|`` and solves two extremal problems numerically:

- Problem 1 (eq. (18)): max err subject to a_nonorth = g and the angles within 2 % of a right
  angle; the paper finds 0.3130299 m/s² at a_x = a_y = a_z ≈ 5.48114, φ = ψ = θ ≈ 1.60221.
- Problem 2 (eq. (19)): max |(a_nonorth − a_orth)/a_nonorth| over |a_i| ≤ 16 g (also 4 g, 8 g) and
  the same angles; the paper finds ≈ 3.192 %.

The paper writes the angle box as ``0.98π ≤ φ, ψ, θ ≤ 1.02π``; it means 0.98·π/2 … 1.02·π/2 (its
own maximiser 1.60221 = 1.02·π/2 and "90° ± 2 %" in section 2), which is what is solved here.

Both problems are solved by SLSQP from starts at every corner of the angle box combined with the
14 directions of a cube's corners and faces; the best local maximum is kept (the first one
found on ties, so the paper's symmetric maximiser is returned).  Because a_nonorth² = aᵀG⁻¹a
(G the Gram matrix of eq. (8)), the ratio a_orth/a_nonorth ranges over the square roots of the
eigenvalues of G, which gives closed forms to check the numbers against: Problem 2's value is
``1 − sqrt(1 + 2 cos(1.02·π/2))`` and Problem 1's is g times that.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from ..shared.errors import CalibrationError
from ..shared.gravity import STANDARD_GRAVITY
from ..shared.validation import check_gravity

NONORTHOGONALITY = 0.02
"""Up to 2 % non-orthogonality of the axes (Georgieva et al. section 2, [5])."""


def a_orth(a) -> np.ndarray:
    """Magnitude assuming orthogonal axes, Proposition 1: sqrt(a_x² + a_y² + a_z²).

    Parameters
    ----------
    a : array_like, shape (..., 3)

    Returns
    -------
    numpy.ndarray of shape (...)
    """
    a = np.asarray(a, dtype=float)
    return np.sqrt(np.sum(a * a, axis=-1))


def a_nonorth(a, phi, psi, theta) -> np.ndarray:
    """Magnitude of the acceleration with readings a along non-orthogonal axes, Georgieva et al. eq. (10).

    Parameters
    ----------
    a : array_like, shape (..., 3)
        Readings a_x, a_y, a_z along the three axes (projections, Georgieva et al. eq. (4)).
    phi, psi, theta : float or array_like broadcasting with a[..., 0]
        Angles ∠(Ox, Oy), ∠(Ox, Oz), ∠(Oy, Oz) in radians.

    Returns
    -------
    numpy.ndarray of shape (...)
    """
    a = np.asarray(a, dtype=float)
    ax, ay, az = a[..., 0], a[..., 1], a[..., 2]
    cf, cp, ct = np.cos(phi), np.cos(psi), np.cos(theta)
    # Georgieva et al. eq. (10)
    numerator = (
        2 * (-1 + np.cos(2 * theta)) * ax**2
        + 2 * (-1 + np.cos(2 * psi)) * ay**2
        + 2 * (-1 + np.cos(2 * phi)) * az**2
        + 8 * (cf - cp * ct) * ax * ay
        + 8 * (ct - cf * cp) * ay * az
        + 8 * (cp - cf * ct) * ax * az
    )
    denominator = 2 + 2 * np.cos(2 * phi) + 2 * np.cos(2 * psi) + 2 * np.cos(2 * theta) - 8 * cf * cp * ct
    return np.sqrt(numerator / denominator)


def nonorthogonality_error(a, phi, psi, theta) -> np.ndarray:
    """err(a_x, a_y, a_z, φ, ψ, θ) = |a_nonorth − a_orth| of Georgieva et al. section 2.3."""
    return np.abs(a_nonorth(a, phi, psi, theta) - a_orth(a))


def relative_nonorthogonality_error(a, phi, psi, theta) -> np.ndarray:
    """|(a_nonorth − a_orth) / a_nonorth|, the objective of Georgieva et al. Problem 2 (eq. (19))."""
    n = a_nonorth(a, phi, psi, theta)
    return np.abs((n - a_orth(a)) / n)


@dataclass(frozen=True)
class NonOrthogonalityErrorBound:
    """Solution of an extremal problem of Georgieva et al. section 2.3.

    Attributes
    ----------
    problem : int
        1 (eq. (18), absolute error at a_nonorth = g) or 2 (eq. (19), relative error).
    value : float
        The maximum: in the unit of ``gravity`` for Problem 1, a fraction for Problem 2.
    acceleration : numpy.ndarray, shape (3,)
        A maximising (a_x, a_y, a_z); for Problem 2 scaled onto the box |a_i| ≤ range_g·g.
    phi, psi, theta : float
        The maximising angles, radians.
    gravity : float
    angle_bounds : (float, float)
        The box of the angles, radians.
    """

    problem: int
    value: float
    acceleration: np.ndarray
    phi: float
    psi: float
    theta: float
    gravity: float
    angle_bounds: tuple

    @property
    def angles(self) -> np.ndarray:
        return np.array([self.phi, self.psi, self.theta])

    def to_dict(self) -> dict:
        """Plain-JSON form."""
        return {
            "problem": self.problem,
            "value": self.value,
            "acceleration": self.acceleration.tolist(),
            "phi": self.phi,
            "psi": self.psi,
            "theta": self.theta,
            "gravity": self.gravity,
            "angle_bounds": list(self.angle_bounds),
        }


def _angle_bounds(nonorthogonality: float) -> tuple[float, float]:
    if not (np.isfinite(nonorthogonality) and 0.0 < nonorthogonality < 0.5):
        raise CalibrationError(f"nonorthogonality must be a fraction in (0, 0.5); got {nonorthogonality!r}")
    return ((1.0 - nonorthogonality) * np.pi / 2, (1.0 + nonorthogonality) * np.pi / 2)


def _directions() -> list[np.ndarray]:
    """The 14 directions of a cube's corners and faces, corners first."""
    dirs = [np.array(v, dtype=float) for v in itertools.product((1, -1, 0), repeat=3) if np.count_nonzero(v) in (1, 3)]
    dirs.sort(key=lambda v: -np.count_nonzero(v))
    return [v / np.linalg.norm(v) for v in dirs]


def _corners(lo: float, hi: float) -> list[np.ndarray]:
    """Corners of the angle box, the all-upper corner first."""
    return [np.array(c) for c in itertools.product((hi, lo), repeat=3)]


def _maximise(objective, starts, bounds, constraints=()) -> tuple[float, np.ndarray]:
    def negative(x: np.ndarray) -> float:
        return -objective(x)

    best_val, best_x = -np.inf, None
    for x0 in starts:
        res = minimize(
            negative,
            x0,
            method="SLSQP",
            bounds=bounds,
            constraints=constraints,
            options={"ftol": 1e-14, "maxiter": 100},
        )
        x = np.clip(res.x, [b[0] for b in bounds], [b[1] for b in bounds])
        if constraints and any(abs(c["fun"](x)) > 1e-8 for c in constraints):
            continue
        val = objective(x)
        # Keep the first maximiser on ties (relative 1e-10) so the result is deterministic.
        if val > best_val * (1.0 + 1e-10) + 1e-15:
            best_val, best_x = val, x
    assert best_x is not None, "a start meets the constraints"
    return float(best_val), best_x


def max_error_at_gravity(
    gravity: float = STANDARD_GRAVITY, *, nonorthogonality: float = NONORTHOGONALITY
) -> NonOrthogonalityErrorBound:
    """Solve Georgieva et al. Problem 1 (eq. (18)): the largest |a_nonorth − a_orth| for a_nonorth = g.

    Parameters
    ----------
    gravity : float
        g of the constraint a_nonorth = g (the paper's 0.3130299 m/s² needs 9.80665).
    nonorthogonality : float
        The angles lie in [(1 − n)·π/2, (1 + n)·π/2]; 0.02 in the paper.

    Returns
    -------
    NonOrthogonalityErrorBound
        ``value`` in the unit of ``gravity``.
    """
    g = check_gravity(gravity)
    lo, hi = _angle_bounds(nonorthogonality)
    big = 2.0 * g

    def objective(x):
        return float(nonorthogonality_error(x[:3], *x[3:]))

    constraint = {"type": "eq", "fun": lambda x: float(a_nonorth(x[:3], *x[3:])) - g}
    starts = []
    for ang in _corners(lo, hi):
        for d in _directions():
            a0 = d * g / float(a_nonorth(d, *ang))
            starts.append(np.r_[a0, ang])
    value, x = _maximise(objective, starts, [(-big, big)] * 3 + [(lo, hi)] * 3, [constraint])
    return NonOrthogonalityErrorBound(1, value, x[:3].copy(), float(x[3]), float(x[4]), float(x[5]), g, (lo, hi))


def max_relative_error(
    *, range_g: float = 16.0, gravity: float = STANDARD_GRAVITY, nonorthogonality: float = NONORTHOGONALITY
) -> NonOrthogonalityErrorBound:
    """Solve Georgieva et al. Problem 2 (eq. (19)): the largest |(a_nonorth − a_orth)/a_nonorth|.

    Parameters
    ----------
    range_g : float
        The readings lie in [−range_g·g, range_g·g] (the paper tries 4, 8 and 16; the ratio is
        scale-free, so the value does not depend on it).
    gravity : float
        g, only to scale the returned acceleration.
    nonorthogonality : float
        As in :func:`max_error_at_gravity`.

    Returns
    -------
    NonOrthogonalityErrorBound
        ``value`` a fraction (0.03192 in the paper); ``acceleration`` on the boundary of the box.
    """
    g = check_gravity(gravity)
    if not (np.isfinite(range_g) and range_g > 0):
        raise CalibrationError(f"range_g must be positive; got {range_g!r}")
    lo, hi = _angle_bounds(nonorthogonality)
    box = range_g * g

    def objective(x):
        # The ratio is homogeneous of degree 0 in a: optimise the direction on the unit cube.
        if not np.any(x[:3]):
            return 0.0
        return float(relative_nonorthogonality_error(x[:3], *x[3:]))

    starts = [np.r_[d / np.abs(d).max(), ang] for ang in _corners(lo, hi) for d in _directions()]
    value, x = _maximise(objective, starts, [(-1.0, 1.0)] * 3 + [(lo, hi)] * 3)
    a = x[:3] / np.abs(x[:3]).max() * box
    return NonOrthogonalityErrorBound(2, value, a, float(x[3]), float(x[4]), float(x[5]), g, (lo, hi))
