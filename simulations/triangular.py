"""The simulation of Farago, Maczak and Gingl, IEEE Access (eqs. (17)–(20)) and the Cramér–Rao bound of
its 9-parameter model.

Farago, Maczak and Gingl, IEEE Access, section III.A: true parameters are drawn uniformly — scales in
(0.9, 1.1), misalignments in (−0.05, 0.05), offsets in (−0.1 g, 0.1 g) (eq. (17)) — and combined
into p = [k_xx, k_yy, k_zz, k_xy, k_xz, k_yz, o_x, o_y, o_z] (eq. (18)); random unit vectors a are
"uncalibrated" by the inverse of the model a = K (v + o) (eq. (19)) and given Gaussian noise
(eq. (20)); the calibration points are then selected into nine bins (eq. (10)) as the paper does on
real data.  Everything is in units of g.

Eq. (19) as printed has ``(c_ix − o_x) k_xy`` in the y line; the inverse of eq. (8) needs
``(c_ix + o_x) k_xy`` (the z line has the + sign).  The generator uses the exact inverse.

Selection (Farago, Maczak and Gingl, IEEE Access, section II.B.1, eq. (10)): each axis is split into
[−1.25, −0.75], [−0.25, 0.25] and
[0.75, 1.25] g, giving the nine subsets C_xn … C_zp.  Figure 6, which gives the exact rule, is not
in the text; trical's reading: candidates are taken in the order they are drawn, and a candidate
joins the first subset (order x, y, z) that it falls in and that holds fewer than ``per_bin``
points; drawing stops when every subset holds ``per_bin`` points (2 in the paper, N = 18).

Random numbers are drawn from the ``numpy.random.Generator`` passed in, in a fixed order
(parameters first, then candidate directions and noise in batches), so a seed fixes a scenario.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from app.calibration.shared.errors import CalibrationError

PARAM_NAMES = ("k_xx", "k_yy", "k_zz", "k_xy", "k_xz", "k_yz", "o_x", "o_y", "o_z")

BIN_EDGES = ((-1.25, -0.75), (-0.25, 0.25), (0.75, 1.25))
"""The three intervals of each axis, in g (Farago, Maczak and Gingl, IEEE Access, section II.B.1)."""


def k_matrix(p) -> np.ndarray:
    """Lower-triangular K of a = K (v + o) from p (Farago, Maczak and Gingl, IEEE Access, eqs. (6)–(9))."""
    p = np.asarray(p, dtype=float)
    return np.array([[p[0], 0.0, 0.0], [p[3], p[1], 0.0], [p[4], p[5], p[2]]])


def draw_parameters(rng: np.random.Generator) -> np.ndarray:
    """True parameters of one scenario, Farago, Maczak and Gingl, IEEE Access, eqs. (17)–(18).

    Parameters
    ----------
    rng : numpy.random.Generator

    Returns
    -------
    numpy.ndarray, shape (9,)
        p = [k_xx, k_yy, k_zz, k_xy, k_xz, k_yz, o_x, o_y, o_z], offsets in g.
    """
    delta = rng.random(9)  # δ for S_x, S_y, S_z, T_xy, T_xz, T_yz, O_x, O_y, O_z
    S = 2.0 * (delta[0:3] - 0.5) * 0.1 + 1.0  # Farago, Maczak and Gingl, IEEE Access, eq. (17)
    T = 2.0 * (delta[3:6] - 0.5) * 0.05
    O = 2.0 * (delta[6:9] - 0.5) * 0.1  # noqa: E741 - the offsets, O in the paper
    # Farago, Maczak and Gingl, IEEE Access, eq. (18)
    return np.array([S[0], S[1], S[2], S[1] * T[0], S[2] * T[1], S[2] * T[2], O[0], O[1], O[2]])


def uncalibrate(p, a) -> np.ndarray:
    """Readings c that the model maps onto the accelerations a, Farago, Maczak and Gingl, IEEE Access,
    eq. (19) (sign corrected).

    Parameters
    ----------
    p : array_like, shape (9,)
    a : array_like, shape (N, 3)

    Returns
    -------
    numpy.ndarray, shape (N, 3)
    """
    kxx, kyy, kzz, kxy, kxz, kyz, ox, oy, oz = np.asarray(p, dtype=float)
    a = np.asarray(a, dtype=float).reshape(-1, 3)
    cx = a[:, 0] / kxx - ox
    cy = (a[:, 1] - (cx + ox) * kxy) / kyy - oy  # Farago, Maczak and Gingl, IEEE Access, eq. (19), +
    # o_x: the inverse of eq. (8)
    cz = (a[:, 2] - (cx + ox) * kxz - (cy + oy) * kyz) / kzz - oz
    return np.column_stack([cx, cy, cz])


def bin_indices(points: np.ndarray) -> np.ndarray:
    """Subset of eq. (10) of each point on each axis: 0 (n), 1 (0), 2 (p) or −1 (none); shape (N, 3)."""
    out = np.full(points.shape, -1, dtype=int)
    for j, (lo, hi) in enumerate(BIN_EDGES):
        out[(points >= lo) & (points <= hi)] = j
    return out


def select_points(points, per_bin: int = 2) -> np.ndarray:
    """Indices of the points kept by the nine-bin selection (module docstring), in order.

    Parameters
    ----------
    points : array_like, shape (N, 3)
        Candidate calibration points in g, in the order they were measured.
    per_bin : int
        Points per subset C_ij (2 in the paper).

    Returns
    -------
    numpy.ndarray of int
        Indices of the accepted points (at most 9·per_bin).
    """
    bins = bin_indices(np.asarray(points, dtype=float))
    counts = np.zeros((3, 3), dtype=int)  # [axis, interval]
    kept = []
    for i, row in enumerate(bins):
        for axis in range(3):
            j = row[axis]
            if j >= 0 and counts[axis, j] < per_bin:
                counts[axis, j] += 1
                kept.append(i)
                break
        if counts.min() >= per_bin:
            break
    return np.array(kept, dtype=int)


@dataclass(frozen=True)
class Scenario:
    """One simulated scenario of Farago, Maczak and Gingl, IEEE Access, section III.A.

    Attributes
    ----------
    p : numpy.ndarray, shape (9,)
        True parameters (eq. (18)).
    points : numpy.ndarray, shape (N, 3)
        Selected noisy calibration points u (eq. (20)), in g.
    directions : numpy.ndarray, shape (N, 3)
        The true unit accelerations a behind them.
    noise_g : float
        Standard deviation of the noise on each component, in g.
    """

    p: np.ndarray
    points: np.ndarray
    directions: np.ndarray
    noise_g: float


def random_unit_vectors(rng: np.random.Generator, n: int) -> np.ndarray:
    """n directions uniform on the unit sphere."""
    v = rng.standard_normal((n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def simulate_scenario(
    rng: np.random.Generator, *, noise_g: float, per_bin: int = 2, batch: int = 64, max_candidates: int = 100_000
) -> Scenario:
    """Draw one scenario of the Farago, Maczak and Gingl, IEEE Access simulation: parameters, points,
    noise and selection.

    Parameters
    ----------
    rng : numpy.random.Generator
    noise_g : float
        Noise standard deviation in g (0.001 and 0.005 in Farago, Maczak and Gingl, IEEE Access, Table 2).
    per_bin : int
        Points per subset of eq. (10); N = 9·per_bin.
    batch : int
        Candidates drawn at a time (part of the random stream: keep it fixed for reproducibility).
    max_candidates : int
        Give up after this many candidates.

    Returns
    -------
    Scenario
    """
    if not (np.isfinite(noise_g) and noise_g >= 0):
        raise CalibrationError(f"noise_g must be a non-negative number; got {noise_g!r}")
    p = draw_parameters(rng)
    dirs, pts = [], []
    drawn = 0
    while drawn < max_candidates:
        a = random_unit_vectors(rng, batch)
        u = uncalibrate(p, a) + noise_g * rng.standard_normal((batch, 3))  # Farago, Maczak and Gingl,
        # IEEE Access, eqs. (19)–(20)
        dirs.append(a)
        pts.append(u)
        drawn += batch
        all_a, all_u = np.vstack(dirs), np.vstack(pts)
        idx = select_points(all_u, per_bin)
        if len(idx) == 9 * per_bin:
            return Scenario(p=p, points=all_u[idx], directions=all_a[idx], noise_g=float(noise_g))
    raise CalibrationError(f"no complete selection of 9×{per_bin} points in {max_candidates} candidates")


def _point_jacobians(p: np.ndarray, directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """∂c/∂p (N, 3, 9) and ∂c/∂(two tangent angles of a) (N, 3, 2) for c = K⁻¹ a − o."""
    K = k_matrix(p)
    Ki = np.linalg.inv(K)
    x = directions @ Ki.T  # K⁻¹ a = v + o
    n = len(directions)
    A = np.zeros((n, 3, 9))
    # Position of each k in K, in the order of p (eq. (6)).
    where = [(0, 0), (1, 1), (2, 2), (1, 0), (2, 0), (2, 1)]
    for col, (r, c) in enumerate(where):
        E = np.zeros((3, 3))
        E[r, c] = 1.0
        A[:, :, col] = -(Ki @ E @ x.T).T  # ∂(K⁻¹a)/∂k = −K⁻¹ E K⁻¹ a
    A[:, :, 6:9] = -np.eye(3)
    # Two unit tangents of the sphere at each a.
    helper = np.where(np.abs(directions[:, [0]]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    t1 = np.cross(directions, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    t2 = np.cross(directions, t1)
    B = np.stack([t1 @ Ki.T, t2 @ Ki.T], axis=2)
    return A, B


def cramer_rao_bound(p, directions, noise_g: float) -> np.ndarray:
    """Cramér–Rao bound on the covariance of p for the 9-parameter model of Farago, Maczak and Gingl,
    IEEE Access.

    The readings are u = K⁻¹ a − o + ε with ε ~ N(0, σ² I) (eqs. (19)–(20)); the unit vectors a are
    unknown (two nuisance angles each).  The Fisher information of (p, angles) is JᵀJ / σ²; the
    bound on p is the p-block of its inverse, computed point by point with the Schur complement
    ``Σ Aᵢᵀ (I − Bᵢ(BᵢᵀBᵢ)⁻¹Bᵢᵀ) Aᵢ / σ²``.

    Parameters
    ----------
    p : array_like, shape (9,)
        True parameters.
    directions : array_like, shape (N, 3)
        True unit accelerations of the calibration points.
    noise_g : float
        Standard deviation σ of the noise on each reading component, in g.

    Returns
    -------
    numpy.ndarray, shape (9, 9)
        The bound; its diagonal holds the smallest variances an unbiased estimator can reach.
    """
    p = np.asarray(p, dtype=float)
    d = np.asarray(directions, dtype=float)
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    if not noise_g > 0:
        raise CalibrationError("the Cramér–Rao bound needs a positive noise level")
    A, B = _point_jacobians(p, d)
    fim = np.zeros((9, 9))
    for Ai, Bi in zip(A, B):
        P = np.eye(3) - Bi @ np.linalg.solve(Bi.T @ Bi, Bi.T)
        fim += Ai.T @ P @ Ai
    return np.linalg.inv(fim / noise_g**2)
