"""Which pose to add next: the up-directions that most shrink a magnitude model's uncertainty.

The magnitude models fit the norms of still readings to g: the triangular model of Farago, Maczak
and Gingl, IEEE Access (a = K (v + o), eq. (6); objective eq. (12)) and the non-orthogonal model
of Georgieva et al., ESGI'95, Approach 1 (calibrated value eq. (16); objective eq. (17)).  Their
parameter covariance is C = σ² (JᵀJ)⁻¹ (Särkkä et al., IEEE Sensors Journal 17(11) 2017,
Appendix A, eq. (22) with V(ε) = σ² I), J the Jacobian of the fit's residuals at the solution.

A further still reading with the device's axis ``u`` up reads m(u) = M⁻¹ (g u) + o (the model's
correction a = M (m − o) inverted at a = g u) and adds one row j(u) = ∂r(m(u); θ)/∂θ to J.  By the
matrix determinant lemma the information JᵀJ + j jᵀ has the determinant
det(JᵀJ) · (1 + jᵀ (JᵀJ)⁻¹ j), so the generalized variance det C shrinks by the factor
1 / (1 + h(u)) with the leverage h(u) = jᵀ (JᵀJ)⁻¹ j = jᵀ C j / σ² — σ² cancels.  The D-optimal
choice (Kiefer and Wolfowitz, Canadian J. Math. 12, 1960: maximise det of the information) is the
candidate with the largest h.  The next advice assumes that pose was added: (JᵀJ)⁻¹ is updated by
Sherman–Morrison, P ← P − P j jᵀ P / (1 + h), so the list does not name one direction three
times.

Decisions:

- The leverage needs JᵀJ, not C, so the advice exists also where the fit has no residual degrees
  of freedom (9 positions: σ² and so C unknown).  J's columns are scaled to unit norm (parameters
  of different units) and a ridge of :data:`RIDGE` keeps a (near-)singular JᵀJ invertible; then
  the directions that resolve what the poses leave undetermined get the largest leverage.
- Before any fit (fewer readings than parameters) there is no Jacobian: :func:`farthest_directions`
  advises the directions farthest from every pose taken, with no gain.
- Candidates are the six axes and a Fibonacci sphere of :data:`CANDIDATES` directions (about 10°
  apart); those
  within :data:`MIN_SEPARATION_DEG` of a pose taken (or advised before) are left out — the wizard
  refuses such a pose as a near duplicate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..shared.orientations import POSE_NAMES
from ..shared.validation import as_vectors, sphere_directions

CANDIDATES = 400
"""Candidate up-directions on a Fibonacci sphere: neighbours about 10° apart."""

ADVICE_COUNT = 3
"""How many directions are advised."""

MIN_SEPARATION_DEG = 10.0
"""A candidate this close to a pose already taken (or advised) is not advised."""

RIDGE = 1e-8
"""Added to the column-scaled JᵀJ (unit diagonal) before inverting it."""

MINUS = "\u2212"

TILT_STEP_DEG = 5
"""Tilts are said in whole multiples of this angle."""

SECOND_AXIS_TAN = float(np.tan(np.radians(22.5)))
"""A tilt is said to go towards two axes when its direction is more than 22.5° from the nearer one."""


@dataclass(frozen=True)
class PoseAdvice:
    """One advised pose.

    Attributes
    ----------
    up : numpy.ndarray, shape (3,)
        Unit vector in the sensor frame that should point up (the axis that reads +g at rest).
    words : str
        The pose in words a person can follow (:func:`describe_up`).
    gain : float or None
        Fractional reduction of the generalized variance det C from adding this pose after the
        advised poses before it, h / (1 + h); None when no model has been fitted yet.
    """

    up: np.ndarray
    words: str
    gain: float | None

    def to_dict(self) -> dict:
        return {"up": [float(v) for v in self.up], "words": self.words, "gain": self.gain}


def fibonacci_sphere(n: int = CANDIDATES) -> np.ndarray:
    """``n`` nearly evenly spread unit vectors (the golden-angle spiral), shape (n, 3); the first is
    next to +z."""
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    phi = np.pi * (3.0 - np.sqrt(5.0)) * i
    r = np.sqrt(1.0 - z * z)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def candidate_directions(n: int = CANDIDATES) -> np.ndarray:
    """The directions searched: the six axes (the easiest poses to set up, first) and a Fibonacci
    sphere of ``n``, shape (n + 6, 3)."""
    axes = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=float)
    return np.vstack([axes, fibonacci_sphere(n)])


def _axis_name(value: float, k: int) -> str:
    return ("+" if value >= 0 else MINUS) + "xyz"[k]


def describe_up(up) -> str:
    """An up-direction in words: the nearest axis up, then the tilt from it towards the next.

    Parameters
    ----------
    up : array_like, shape (3,)
        A direction in the sensor frame (any length but zero).

    Returns
    -------
    str
        E.g. ``"+z up (flat, screen up)"`` or ``"+x up (on its left edge as you face the screen, right
        edge up), tilted 30° towards −z"``; the tilt in multiples of 5°, towards two axes (``"towards −z and +y"``)
        when its direction is more than 22.5° from the nearer one.  The phone words in brackets
        name the pose of the nearest axis (W3C frame: x right, y up the screen, z out of it).
    """
    u = np.asarray(up, dtype=float).reshape(3)
    u = u / np.linalg.norm(u)
    k = int(np.argmax(np.abs(u)))
    label = ("+" if u[k] >= 0 else "-") + "xyz"[k]
    head = f"{_axis_name(u[k], k)} up ({POSE_NAMES[label]})"
    tilt = float(np.degrees(np.arccos(np.clip(abs(u[k]), 0.0, 1.0))))
    tilt_said = int(TILT_STEP_DEG * round(tilt / TILT_STEP_DEG))
    if tilt_said == 0:
        return head
    first, second = sorted((j for j in range(3) if j != k), key=lambda j: -abs(u[j]))
    towards = _axis_name(u[first], first)
    if abs(u[second]) > SECOND_AXIS_TAN * abs(u[first]):
        towards += f" and {_axis_name(u[second], second)}"
    return f"{head}, tilted {tilt_said}° towards {towards}"


def _allowed(directions: np.ndarray, taken: np.ndarray, min_separation_deg: float) -> np.ndarray:
    """Candidates more than ``min_separation_deg`` from every taken direction."""
    if len(taken) == 0:
        return np.ones(len(directions), dtype=bool)
    return np.all(directions @ taken.T < np.cos(np.radians(min_separation_deg)), axis=1)


def next_poses(
    result, *, count: int = ADVICE_COUNT, candidates: int = CANDIDATES, min_separation_deg: float = MIN_SEPARATION_DEG
) -> tuple[PoseAdvice, ...]:
    """The D-optimal next poses for a fitted magnitude model (module docstring).

    Parameters
    ----------
    result : TriangularCalibration or NonOrthogonalCalibration
        A fit of Farago et al.'s triangular model (eq. (6), objective eq. (12)) or Georgieva et
        al.'s Approach 1 (eq. (16), objective eq. (17)): anything with ``gravity``, ``means``,
        ``apply``, ``correction`` and ``jacobian(means)``.
    count : int
        How many directions to advise, each assuming the ones before it were added.
    candidates : int
        Size of the Fibonacci sphere searched (beside the six axes).
    min_separation_deg : float
        Candidates this close to a pose taken (calibrated direction) or advised are left out.

    Returns
    -------
    tuple of PoseAdvice
        Best first; fewer than ``count`` when no candidate is left.
    """
    directions = candidate_directions(candidates)
    g = result.gravity
    correction = result.correction
    # The reading at rest with u up: a = M (m − o) (Farago et al. eq. (6), Georgieva et al. eq. (16))
    # inverted at a = g u.
    readings = (g * directions) @ np.linalg.inv(correction.M).T + correction.o
    J = np.asarray(result.jacobian(result.means), dtype=float)
    rows = np.asarray(result.jacobian(readings), dtype=float)
    scale = np.linalg.norm(J, axis=0)
    scale = np.where(scale > 0, scale, 1.0)
    info = (J / scale).T @ (J / scale) + RIDGE * np.eye(J.shape[1])
    P = np.linalg.inv(info)
    P = 0.5 * (P + P.T)
    R = rows / scale
    allowed = _allowed(directions, sphere_directions(result.apply(result.means)), min_separation_deg)
    advice: list[PoseAdvice] = []
    for _ in range(count):
        if not allowed.any():
            break
        leverage = np.einsum("ij,jk,ik->i", R, P, R)  # h(u) = jᵀ (JᵀJ)⁻¹ j
        leverage = np.where(allowed, leverage, -np.inf)
        best = int(np.argmax(leverage))
        h = float(leverage[best])
        Pj = P @ R[best]
        P = P - np.outer(Pj, Pj) / (1.0 + h)  # Sherman–Morrison: the pose is taken
        allowed &= _allowed(directions, directions[best : best + 1], min_separation_deg)
        advice.append(PoseAdvice(up=directions[best], words=describe_up(directions[best]), gain=h / (1.0 + h)))
    return tuple(advice)


def farthest_directions(ups, *, count: int = ADVICE_COUNT, candidates: int = CANDIDATES) -> tuple[PoseAdvice, ...]:
    """Directions farthest from every pose taken, for when no model can be fitted yet.

    Greedy: each is the candidate whose nearest taken (or earlier advised) direction is farthest.

    Parameters
    ----------
    ups : array_like, shape (N, 3)
        Directions (or raw readings) of the poses taken; N may be 0.
    count, candidates : int
        As in :func:`next_poses`.

    Returns
    -------
    tuple of PoseAdvice
        With ``gain`` None.
    """
    directions = candidate_directions(candidates)
    ups = np.asarray(ups, dtype=float).reshape(-1, 3)
    taken = sphere_directions(as_vectors(ups, "ups")) if len(ups) else np.zeros((0, 3))
    advice: list[PoseAdvice] = []
    for _ in range(count):
        nearest = (directions @ taken.T).max(axis=1) if len(taken) else np.full(len(directions), -1.0)
        best = int(np.argmin(nearest))
        taken = np.vstack([taken, directions[best]])
        advice.append(PoseAdvice(up=directions[best], words=describe_up(directions[best]), gain=None))
    return tuple(advice)
