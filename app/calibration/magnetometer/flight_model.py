"""The algebra of a compass calibrated from a flight: ``h_body = M (Q m − b − k p)``.

For a fixed rotation Q the model read forwards, ``u = Q m = S e + b + k p`` with ``S = M⁻¹`` (symmetric),
is linear in ``(S, b, k)``: the fit is one linear least squares (:func:`design`, :func:`solve_normal`), no
iteration, and its residual lies where the compass's noise does — in the readings. (The same residual
taken in the body frame, ``M (u − b − k p) − e``, is linear too, in ``(M, M b, M k)``, but it puts the
noisy readings among the regressors: on a flight that stays near level the vertical axis varies little,
and the noise dilutes ``M_zz`` and ``b_z`` by several of their standard errors — Fuller, *Measurement
Error Models*, Wiley 1987, section 1.1, the attenuation of a slope by an error in its regressor; on
simulated flights the intervals then held the truth 71 % of the time for b instead of 95 %.)

The orientation comes first (:func:`orientation`): the readings regressed on the expected field,
``m ≈ A e + c₀ (+ d₀ p)`` (the model read backwards: ``m = Qᵀ M⁻¹ e + Qᵀ b + Qᵀ k p``, so
``A = Qᵀ M⁻¹`` with M⁻¹ symmetric positive definite), and Q the orthogonal factor of A's polar
decomposition, ``Qᵀ = U Vᵀ`` for ``A = U Σ Vᵀ``: the rotation nearest A in the Frobenius norm (Higham,
"Computing the polar decomposition — with applications", SIAM J. Sci. Stat. Comput. 7(4) 1986), the
SVD solution of Wahba's problem ``min Σ wᵢ |eᵢ − Q cᵢ|²`` on readings whose hard iron (and motor term) the
regression took out (Markley, "Attitude determination using vector observations and singular value
decomposition", J. Astronautical Sciences 36(3) 1988, eqs. (7)–(12)).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MODELS = ("offsets", "scale", "soft_iron")
"""M fixed to the identity; M diagonal; M symmetric (soft iron)."""

MATRIX_PARAMETERS = {
    "offsets": (),
    "scale": ((0, 0), (1, 1), (2, 2)),
    "soft_iron": ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)),
}
"""The entries of M each model fits (a symmetric pair counts once)."""


def candidate_name(model: str, motor: bool) -> str:
    """``soft_iron`` or ``soft_iron+motor``."""
    return model + ("+motor" if motor else "")


def parse_candidate(name: str) -> tuple[str, bool]:
    """``(model, motor)`` of a candidate's name; ValueError for a name not of :data:`MODELS`."""
    model, _, rest = name.partition("+")
    if model not in MODELS or rest not in ("", "motor"):
        raise ValueError(name)
    return model, rest == "motor"


def n_parameters(model: str, motor: bool) -> int:
    return len(MATRIX_PARAMETERS[model]) + 3 + (3 if motor else 0)


def _basis(model: str) -> list[np.ndarray]:
    out = []
    for i, j in MATRIX_PARAMETERS[model]:
        E = np.zeros((3, 3))
        E[i, j] = E[j, i] = 1.0
        out.append(E)
    return out


@dataclass(frozen=True)
class Fit:
    """One fitted candidate: ``h = M (u − b − k p)`` with ``u = Q m``."""

    model: str
    motor: bool
    M: np.ndarray
    b: np.ndarray
    k: np.ndarray

    def field(self, u: np.ndarray, p: np.ndarray | None) -> np.ndarray:
        v = u - self.b
        if self.motor:
            assert p is not None, "the motor term needs the power"
            v = v - np.outer(p, self.k)
        return v @ self.M.T


def design(
    u: np.ndarray, e: np.ndarray, p: np.ndarray | None, model: str, motor: bool
) -> tuple[np.ndarray, np.ndarray]:
    """The linear system ``X θ = y`` of ``u = S e + b + k p`` (``S = M⁻¹``), shapes (N, 3, P) and (N, 3):
    θ is S's fitted entries, then b, then k; for ``offsets`` (S = I) the target is ``u − e``."""
    n = len(u)
    cols = [e @ E.T for E in _basis(model)]  # ∂(S e)/∂θ_j
    eye = np.eye(3)
    cols += [np.broadcast_to(eye[:, c], (n, 3)) for c in range(3)]  # b
    if motor:
        assert p is not None, "the motor term needs the power"
        cols += [np.outer(p, eye[:, c]) for c in range(3)]  # k p
    return np.stack(cols, axis=2), ((u - e) if model == "offsets" else u)


def normal_equations(X: np.ndarray, y: np.ndarray, w: np.ndarray, groups: np.ndarray, count: int):
    """``Σ wᵢ Xᵢᵀ Xᵢ`` and ``Σ wᵢ Xᵢᵀ yᵢ`` of each group of samples, shapes (count, P, P) and (count, P):
    the fits that leave a group out subtract its sums from the totals (one pass over the samples)."""
    P = X.shape[2]
    A = np.zeros((count, P, P))
    g = np.zeros((count, P))
    for k in range(count):
        sel = groups == k
        Xk = X[sel].reshape(-1, P)
        wk = np.repeat(w[sel], 3)
        A[k] = (Xk * wk[:, None]).T @ Xk
        g[k] = (Xk * wk[:, None]).T @ y[sel].reshape(-1)
    return A, g


def from_theta(theta: np.ndarray, model: str, motor: bool) -> Fit:
    """``(M, b, k)`` from the linear parameters ``(S's entries, b, k)``, ``M = S⁻¹``."""
    basis = _basis(model)
    nm = len(basis)
    S = np.eye(3) if model == "offsets" else sum(t * E for t, E in zip(theta[:nm], basis))
    k = theta[nm + 3 : nm + 6] if motor else np.zeros(3)
    return Fit(model, motor, np.linalg.inv(S), theta[nm : nm + 3].copy(), k)


def solve_normal(A: np.ndarray, g: np.ndarray, model: str, motor: bool, held=None) -> Fit:
    """The fit from summed normal equations (columns scaled to unit diagonal before solving). ``held``, a pair
    ``(mask, values)``, fixes those entries of θ: ``A_ff θ_f = g_f − A_fx θ_x`` (:mod:`.flight_partial`)."""
    theta = np.zeros(len(g))
    free = np.ones(len(g), dtype=bool)
    if held is not None:
        mask, values = held
        free = ~mask
        theta = values.copy()
        g = g[free] - A[np.ix_(free, mask)] @ values[mask]
        A = A[np.ix_(free, free)]
    d = np.sqrt(np.diag(A))
    d[d == 0] = 1.0
    theta[free] = np.linalg.solve(A / np.outer(d, d), g / d) / d
    return from_theta(theta, model, motor)


def parameters(fit: Fit) -> np.ndarray:
    """``(M's fitted entries, b, k)`` of a fit as one vector (k only with the motor term)."""
    M = np.array([fit.M[i, j] for i, j in MATRIX_PARAMETERS[fit.model]])
    return np.concatenate([M, fit.b] + ([fit.k] if fit.motor else []))


def block_jackknife(A: np.ndarray, g: np.ndarray, model: str, motor: bool, held=None) -> np.ndarray:
    """The covariance of ``(M's entries, b, k)`` by the jackknife that leaves out one block of time at a time.

    With G contiguous blocks, θ₍g₎ the fit without block g and θ̄ their mean,
    ``V = (G − 1)/G Σ_g (θ₍g₎ − θ̄)(θ₍g₎ − θ̄)ᵀ`` — the blockwise jackknife of Künsch, "The jackknife and the
    bootstrap for general stationary observations", Annals of Statistics 17(3) 1989, eq. (2.2) with
    non-overlapping blocks: residuals correlated within a block (the attitude's error wanders over seconds)
    stay together, so the spread of the refits carries their correlation, where ``σ² (JᵀJ)⁻¹`` would count
    every sample as news. It is the delete-one-cluster (CR3) variance of Cameron and Miller, "A
    practitioner's guide to cluster-robust inference", J. Human Resources 50(2) 2015, section VI.B, which
    keeps its coverage with few blocks where the plain sandwich falls short; intervals take Student's t at
    G − 1 degrees of freedom (their section VI.C). ``b = M⁻¹ c`` and ``k = M⁻¹ d`` are refitted, not linearised.

    Parameters
    ----------
    A, g : numpy.ndarray, shapes (G, P, P) and (G, P)
        Each block's normal equations (:func:`normal_equations`).
    held : (mask, values), optional
        Entries of θ held fixed in every refit (:func:`solve_normal`).

    Returns
    -------
    numpy.ndarray, shape (P, P)
    """
    G = len(A)
    At, gt = A.sum(axis=0), g.sum(axis=0)
    thetas = np.array([parameters(solve_normal(At - A[k], gt - g[k], model, motor, held)) for k in range(G)])
    dev = thetas - thetas.mean(axis=0)
    return (G - 1.0) / G * dev.T @ dev


def orientation(mag: np.ndarray, e: np.ndarray, p: np.ndarray | None, w: np.ndarray) -> np.ndarray:
    """The rotation Q (frame L → body) the data show: the orthogonal polar factor of A in
    ``m ≈ A e + c₀ (+ d₀ p)`` (module docstring), transposed."""
    cols = [e, np.ones((len(e), 1))] + ([p[:, None]] if p is not None else [])
    X = np.hstack(cols)
    sw = np.sqrt(w)[:, None]
    coef, *_ = np.linalg.lstsq(X * sw, mag * sw, rcond=None)
    A = coef[:3].T  # m ≈ A e
    U, _, Vt = np.linalg.svd(A)
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(U @ Vt))])
    return (U @ D @ Vt).T


def correlation_time(r: np.ndarray, factor: float = 10.0) -> float:
    """The integrated autocorrelation time of the residuals, in samples: ``τ = 1 + 2 Σ_{l=1}^{W} ρ(l)``
    with ρ the autocorrelation summed over the three axes and the window W the smallest with
    ``W ≥ 5 τ(W)`` (Sokal, "Monte Carlo methods in statistical mechanics: foundations and new
    algorithms", Cargèse lectures 1996, section 3, eq. (3.19) and the automatic windowing after it).
    The variance of a mean of N correlated samples is that of N/τ independent ones."""
    x = r - r.mean(axis=0)
    n = len(x)
    size = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.rfft(x, size, axis=0)
    acf = np.fft.irfft(np.sum(np.abs(f) ** 2, axis=1), size)[:n]
    if acf[0] <= 0:
        return 1.0
    rho = acf / acf[0]
    tau = 1.0 + 2.0 * np.cumsum(rho[1 : n // 2])
    ok = np.arange(1, len(tau) + 1) >= factor * tau
    return float(max(tau[np.argmax(ok)] if ok.any() else tau[-1], 1.0))


def headings_deg(field_body: np.ndarray, attitude: np.ndarray) -> np.ndarray:
    """The azimuth of a body-frame field turned into NED by the attitude ``C_nb``: ``atan2(h_E, h_N)``
    in degrees (the declination a compass would read; its error is the heading error)."""
    h = np.einsum("nij,nj->ni", attitude, field_body)
    return np.degrees(np.arctan2(h[:, 1], h[:, 0]))


def wrap_deg(angle) -> np.ndarray:
    """Angles into (−180, 180]."""
    return -((-np.asarray(angle) + 180.0) % 360.0 - 180.0)


def error_summary(errors_deg: np.ndarray) -> dict:
    """``{"rms": …, "p95": …}`` of heading errors in degrees (p95 of their magnitude)."""
    a = np.abs(np.asarray(errors_deg, dtype=float))
    return {"rms": float(np.sqrt(np.mean(a * a))), "p95": float(np.percentile(a, 95))}
