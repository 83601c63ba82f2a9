"""Gyroscope of the cube method (Särkkä et al., IEEE Sensors Journal 17(11) 2017, sections III-B, IV-A,
Appendix B).

The unknowns are the attitude quaternion at every sample of every rotation and the calibration
θ = [s_ω, b_ω], s_ω the columns of S_ω⁻¹ (Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (4));
the adjusted rate is
ω = S_ω⁻¹ (ω̃ − b_ω).  Two residuals:

- r1, the trapezoidal rule of q̇ = ½ W(ω) q between consecutive samples (eq. (4)),
- r2 = G x − x*, the first and last quaternion of each rotation against the known attitudes of
  the positions it joins, on the branch the rotation reaches (eq. (5), footnote 2),

weighted as ‖r1‖² + λ‖r2‖² (eqs. (9)–(10)) and minimised by Gauss–Newton with the sparse
Jacobian (11).  λ is raised until the calibration saturates (section IV-A-1).  The covariance
of θ is C⁻¹ D V(δy) Dᵀ C⁻ᵀ (eq. (28)) with the gyroscope noise from the still positions and
error-free reference attitudes, computed on the whole problem (the paper found it prohibitive;
with sparse matrices it is not).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..shared.errors import CalibrationError, InsufficientDataError
from ..shared.gates import Gates, residual_gate
from ..shared.result import gate_fields
from ..shared.uncertainty import CONFIDENCE
from ..shared.validation import as_samples
from . import quaternion as quat
from .accmag import SensorFit, decomposition_jacobian

if TYPE_CHECKING:
    import scipy.sparse as sp

# scipy's modules are imported where a fit or its intervals use them, not here: importing scipy.stats and
# scipy.linalg takes most of a second, which every start of the server and of the command would pay (the
# cube's protocols are read by the guided sessions, and this package's __init__ imports this module).


def _banded():
    """scipy.linalg, for its banded Cholesky factorisation and solve."""
    import scipy.linalg

    return scipy.linalg


LAMBDAS = tuple(10.0**k for k in range(-3, 7))
"""λ values tried in turn, upwards, until the parameters saturate (Särkkä et al., IEEE Sensors Journal
17(11) 2017, section IV-A-1)."""

SATURATION = 1e-7
"""Largest change of any element of S⁻¹ (and of b in rad/s) that counts as saturated."""

MAX_END_ERROR_DEG = 2.0
"""A calibrated rotation ending further than this from the protocol's attitude fails the fit."""


def _tmm(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Batched aᵀ b."""
    return np.swapaxes(a, 1, 2) @ b


def _tmv(a: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Batched aᵀ v."""
    return (np.swapaxes(a, 1, 2) @ v[:, :, None])[:, :, 0]


def _angle_deg(q1: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """Rotation angle between attitudes (sign-blind), degrees."""
    d = np.abs(np.sum(q1 * q2, axis=-1)) / (np.linalg.norm(q1, axis=-1) * np.linalg.norm(q2, axis=-1))
    return np.degrees(2 * np.arccos(np.clip(d, -1.0, 1.0)))


@dataclass(frozen=True)
class GyroCalibration(SensorFit):
    """Result of the gyroscope calibration of Särkkä et al. (eqs. (4), (5), (9)–(11), Appendix B).

    Attributes
    ----------
    S_inv : numpy.ndarray, shape (3, 3)
        The estimate S_ω⁻¹ (docs/methods.md): ``ω = S_inv (raw − b)``.
    b : numpy.ndarray, shape (3,)
        Bias, in the unit of the raw rates.
    lam : float
        Regularisation parameter λ of eq. (9) that was used (NaN for the full-turn method).
    covariance : numpy.ndarray, shape (12, 12)
        Covariance of [columns of S_ω⁻¹, b] (Särkkä et al. eq. (28)).
    rotations : tuple of int
        1-based numbers of the protocol rotations used.
    sampling_rate_hz : float
    metrics, warnings, reasons
        As everywhere in the core; ``ok`` is true when ``reasons`` is empty.
    """

    S_inv: np.ndarray
    b: np.ndarray
    lam: float
    covariance: np.ndarray
    rotations: tuple
    sampling_rate_hz: float

    @property
    def S(self) -> np.ndarray:
        """S_ω of Särkkä et al. eq. (1): raw = S ω + b."""
        return np.linalg.inv(self.S_inv)

    def apply(self, raw) -> np.ndarray:
        """Calibrate rates: ``ω = S_ω⁻¹ (raw − b)``."""
        m = as_samples(raw)
        return (m - self.b) @ self.S_inv.T

    def _S_jacobian(self) -> np.ndarray:
        """d vec_row(S) / d vec_col(S⁻¹): dS = −S dM S."""
        S = self.S
        J = np.zeros((9, 9))
        for c in range(3):
            for r in range(3):
                E = np.zeros((3, 3))
                E[r, c] = 1.0
                J[:, 3 * c + r] = (-S @ E @ S).ravel()
        return J

    def uncertainty(self, confidence: float = CONFIDENCE) -> dict:
        """95 % half-widths of S, b, D, D⁻¹S and S⁻¹ in the shapes of the model (Särkkä et al. App. B)."""
        from scipy import stats  # when asked: see the module's imports

        z = float(stats.norm.ppf(0.5 + confidence / 2.0))
        cov = self.covariance
        sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
        JS = self._S_jacobian()
        cov_S = JS @ cov[:9, :9] @ JS.T
        JD, JM = decomposition_jacobian(self.S)
        return {
            "confidence": confidence,
            "S": (z * np.sqrt(np.clip(np.diag(cov_S), 0, None))).reshape(3, 3).tolist(),
            "b": (z * sd[9:12]).tolist(),
            "D": (z * np.sqrt(np.clip(np.diag(JD @ cov_S @ JD.T), 0, None))).tolist(),
            "misalignment": (z * np.sqrt(np.clip(np.diag(JM @ cov_S @ JM.T), 0, None))).reshape(3, 3).tolist(),
            "S_inv": (z * sd[:9]).reshape(3, 3).T.tolist(),
        }

    def own_model(self) -> dict:
        """S_ω⁻¹ as estimated, and the regularisation λ of eq. (9) (null for full turns)."""
        return {"S_inv": self.S_inv.tolist(), "lambda": None if np.isnan(self.lam) else self.lam}

    def to_dict(self) -> dict:
        """Plain-JSON form."""
        return {
            "sensor": "gyr",
            "model": self.model(),
            "uncertainty": self.uncertainty(),
            "covariance": self.covariance.tolist(),
            "rotations": list(self.rotations),
            "sampling_rate_hz": self.sampling_rate_hz,
            **self.gate_dict(),
        }

    @classmethod
    def from_dict(cls, data: dict) -> GyroCalibration:
        """Rebuild a result from :meth:`to_dict` output."""
        model = data["model"]
        return cls(
            S_inv=np.asarray(model["S_inv"], dtype=float),
            b=np.asarray(model["b"], dtype=float),
            lam=float("nan") if model.get("lambda") is None else float(model["lambda"]),
            covariance=np.asarray(data["covariance"], dtype=float),
            rotations=tuple(data.get("rotations", ())),
            sampling_rate_hz=float(data["sampling_rate_hz"]),
            **gate_fields(data),
        )


class _Problem:
    """The stacked rotations and the residual/Jacobian of Särkkä et al., IEEE Sensors Journal 17(11)
    2017, eqs. (4), (5), (10), (11)."""

    def __init__(self, rotations, q_start, q_end, h, estimate_bias, bias):
        self.h = h
        self.Y = np.vstack(rotations)
        lengths = np.array([len(r) for r in rotations])
        self.N = int(lengths.sum())
        ends = np.cumsum(lengths)
        self.first = ends - lengths
        self.last = ends - 1
        same = np.ones(self.N - 1, dtype=bool)
        same[self.last[:-1]] = False  # no trapezoid across two rotations
        self.a = np.flatnonzero(same)
        self.c = self.a + 1
        self.qs = np.asarray(q_start, float)
        self.qe = np.asarray(q_end, float)
        self.estimate_bias = estimate_bias
        self.fixed_bias = np.asarray(bias, float)
        self.n_theta = 12 if estimate_bias else 9
        self.n_q = 4 * self.N
        self.n_x = self.n_q + self.n_theta
        nb = len(self.a)
        self.n_r1 = 4 * nb
        R = len(rotations)
        self._pattern = None
        self.n_rows = self.n_r1 + 8 * R

    def pattern(self) -> tuple[np.ndarray, np.ndarray]:
        """Row and column indices of the non-zeros of J (r1 blocks, then the r2 rows), cached."""
        if self._pattern is None:
            nb, nt = len(self.a), self.n_theta
            idx = np.int32 if self.n_x < 2**31 else np.int64
            rows1 = np.repeat(np.arange(self.n_r1, dtype=idx).reshape(nb, 4), 8 + nt, axis=1)
            cols_a = 4 * self.a[:, None].astype(idx) + np.arange(4, dtype=idx)
            cols_c = 4 * self.c[:, None].astype(idx) + np.arange(4, dtype=idx)
            cols_t = self.n_q + np.arange(nt, dtype=idx)
            cols1 = np.concatenate(
                [
                    np.repeat(cols_a[:, None, :], 4, axis=1),
                    np.repeat(cols_c[:, None, :], 4, axis=1),
                    np.broadcast_to(cols_t, (nb, 4, nt)),
                ],
                axis=2,
            )
            R = len(self.first)
            rows2 = self.n_r1 + np.arange(8 * R, dtype=idx)
            cols2 = np.concatenate(
                [4 * self.first[:, None] + np.arange(4), 4 * self.last[:, None] + np.arange(4)], axis=1
            )
            self._pattern = (
                np.concatenate([rows1.reshape(-1), rows2]),
                np.concatenate([cols1.reshape(-1), cols2.reshape(-1).astype(idx)]),
            )
        return self._pattern

    def theta_parts(self, theta):
        M = theta[:9].reshape(3, 3).T  # columns of S⁻¹ (Särkkä et al., IEEE Sensors Journal 17(11)
        # 2017, eq. (4))
        b = theta[9:12] if self.estimate_bias else self.fixed_bias
        return M, b

    def evaluate(self, x, lam):
        """Residual (r1, √λ r2) and sparse Jacobian at x (Särkkä et al., IEEE Sensors Journal 17(11)
        2017, eqs. (10)–(11))."""
        h = self.h
        Q = x[: self.n_q].reshape(self.N, 4)
        M, b = self.theta_parts(x[self.n_q :])
        U = self.Y - b
        om = U @ M.T
        Wm = quat.omega_matrix(om)
        I4 = np.eye(4)
        A = I4 + 0.25 * h * Wm[self.a]
        C = 0.25 * h * Wm[self.c] - I4
        Qa, Qc = Q[self.a], Q[self.c]
        # Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (4)
        r1 = (A @ Qa[:, :, None] + C @ Qc[:, :, None])[:, :, 0]
        # dω/dθ: [uᵀ ⊗ I3, −M]
        nt = self.n_theta
        dom = np.zeros((self.N, 3, nt))
        for col in range(3):
            for r in range(3):
                dom[:, r, 3 * col + r] = U[:, col]
        if self.estimate_bias:
            dom[:, :, 9:12] = -M
        Th = 0.25 * h * (quat.xi_matrix(Qa) @ dom[self.a] + quat.xi_matrix(Qc) @ dom[self.c])
        sl = np.sqrt(lam)
        # Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (5), weighted as in eq. (10)
        r2 = sl * np.concatenate([Q[self.first] - self.qs, Q[self.last] - self.qe], axis=1)
        return _Linearisation(self, A, C, Th, r1, r2, sl, Qa, Qc, M)


@dataclass
class _Linearisation:
    """Residuals and Jacobian blocks of eq. (11) at one point."""

    prob: _Problem
    A: np.ndarray  # ∂r1_j/∂q_j, (nb, 4, 4)
    C: np.ndarray  # ∂r1_j/∂q_{j+1}
    Th: np.ndarray  # ∂r1_j/∂θ, (nb, 4, n_θ)
    r1: np.ndarray
    r2: np.ndarray
    sl: float  # √λ
    Qa: np.ndarray
    Qc: np.ndarray
    M: np.ndarray

    @property
    def r(self) -> np.ndarray:
        return np.concatenate([self.r1.reshape(-1), self.r2.reshape(-1)])

    def jacobian(self) -> sp.csr_matrix:
        """The sparse Jacobian J of Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (11) (r1 rows,
        then the √λ G rows)."""
        import scipy.sparse as sp  # when a fit runs: see the module's imports

        p = self.prob
        vals1 = np.concatenate([self.A, self.C, self.Th], axis=2)
        vals2 = np.full(8 * len(p.first), self.sl)
        rows, cols = p.pattern()
        return sp.csr_matrix((np.concatenate([vals1.reshape(-1), vals2]), (rows, cols)), shape=(p.n_rows, p.n_x))

    def normal_equations(self):
        """Blocks of JᵀJ and Jᵀr, assembled from the sparsity of J: the quaternion block in
        banded storage (block-tridiagonal, half-bandwidth 7), the border and the θ block."""
        p = self.prob
        A, C, Th, r1 = self.A, self.C, self.Th, self.r1
        N, nt, lam = p.N, p.n_theta, self.sl**2
        Dg = np.zeros((N, 4, 4))
        Dg[p.a] += _tmm(A, A)
        Dg[p.c] += _tmm(C, C)
        Dg[p.first] += lam * np.eye(4)
        Dg[p.last] += lam * np.eye(4)
        Of = np.zeros((N, 4, 4))  # block (i, i+1)
        Of[p.a] = _tmm(A, C)
        ab = np.zeros((8, 4 * N))
        cols = 4 * np.arange(N)
        for i in range(4):
            for j in range(4):
                if i <= j:
                    ab[7 + i - j, cols + j] = Dg[:, i, j]
                ab[3 + i - j, cols[1:] + j] = Of[:-1, i, j]
        Hqt = np.zeros((N, 4, nt))
        Hqt[p.a] += _tmm(A, Th)
        Hqt[p.c] += _tmm(C, Th)
        Htt = Th.reshape(-1, nt).T @ Th.reshape(-1, nt)
        gq = np.zeros((N, 4))
        gq[p.a] += _tmv(A, r1)
        gq[p.c] += _tmv(C, r1)
        gq[p.first] += self.sl * self.r2[:, :4]
        gq[p.last] += self.sl * self.r2[:, 4:]
        gt = Th.reshape(-1, nt).T @ r1.reshape(-1)
        return ab, Hqt.reshape(4 * N, nt), Htt, np.concatenate([gq.reshape(-1), gt])


class _NormalSolver:
    """Solves (JᵀJ) z = g by the Schur complement of its quaternion block.

    The quaternion block is block-tridiagonal (each r1 block of eq. (4) touches two consecutive
    quaternions), factorised as a band matrix by Cholesky; the calibration parameters form a
    dense 12×12 Schur complement.  Memory and time grow linearly with the samples.
    """

    def __init__(self, lin: _Linearisation):
        ab, self.Hqt, Htt, self.g = lin.normal_equations()
        self.n_q = lin.prob.n_q
        self.cb = _banded().cholesky_banded(ab, lower=False)
        self.Xt = _banded().cho_solve_banded((self.cb, False), self.Hqt)
        self.schur_inv = np.linalg.inv(Htt - self.Hqt.T @ self.Xt)

    def solve(self, g: np.ndarray) -> np.ndarray:
        gq, gt = g[: self.n_q], g[self.n_q :]
        Xg = _banded().cho_solve_banded((self.cb, False), gq)
        dt = self.schur_inv @ (gt - self.Hqt.T @ Xg)
        return np.concatenate([Xg - self.Xt @ dt, dt])

    def step(self) -> np.ndarray:
        """Gauss–Newton step Δx = −(JᵀJ)⁻¹ Jᵀr."""
        return self.solve(-self.g)

    def theta_columns(self) -> np.ndarray:
        """Columns of (JᵀJ)⁻¹ that belong to the calibration parameters, shape (n, n_θ)."""
        return np.vstack([-self.Xt @ self.schur_inv, self.schur_inv])


def _gauss_newton(prob: _Problem, x, lam, max_iterations, tolerance):
    """Gauss–Newton on eq. (10) until the calibration parameters stop moving.

    For fixed θ the residuals are linear in the quaternions, so once a step leaves θ unchanged
    (below ``tolerance``) that same step has put the quaternions at their optimum.
    """
    it = 0
    for it in range(1, max_iterations + 1):  # noqa: B007 - the count of iterations is read after the loop
        dx = _NormalSolver(prob.evaluate(x, lam)).step()
        x = x + dx
        if np.max(np.abs(dx[prob.n_q :])) < tolerance:
            break
    return x, it


def _validated(
    rotations, q_start, q_end, sampling_rate_hz, noise_cov, bias0, S_inv0, estimate_bias: bool, rotation_numbers
):
    """Checked rotations, their numbers, start and end attitudes, rate, noise covariance and the
    initial bias and S_ω⁻¹ (Särkkä et al., IEEE Sensors Journal 17(11) 2017, section III-B:
    three attitude equations per rotation)."""
    rots = [np.asarray(r, dtype=float) for r in rotations]
    K = len(rots)
    for k, r in enumerate(rots):
        if r.ndim != 2 or r.shape[1] != 3 or len(r) < 3:
            raise CalibrationError(f"rotation {k + 1}: rates must be N×3 with N ≥ 3; got shape {r.shape}")
        if not np.all(np.isfinite(r)):
            raise CalibrationError(f"rotation {k + 1}: NaN or infinite rates; drop those samples")
    numbers = tuple(range(1, K + 1)) if rotation_numbers is None else tuple(int(n) for n in rotation_numbers)
    n_theta = 12 if estimate_bias else 9
    if n_theta > 3 * K:
        raise InsufficientDataError(
            f"{K} rotations give {3 * K} attitude equations for {n_theta} gyroscope parameters "
            f"(Särkkä et al. section III-B): at least {-(-n_theta // 3)} rotations about different axes are needed"
        )
    qs = np.asarray(q_start, float).reshape(K, 4)
    qe = np.asarray(q_end, float).reshape(K, 4)
    fs = float(sampling_rate_hz)
    if not (np.isfinite(fs) and fs > 0):
        raise CalibrationError(f"sampling_rate_hz must be positive; got {sampling_rate_hz!r}")
    Sigma = np.asarray(noise_cov, float)
    Sigma = np.diag(Sigma) if Sigma.shape == (3,) else Sigma.reshape(3, 3)
    b0 = np.zeros(3) if bias0 is None else np.asarray(bias0, float).reshape(3)
    M0 = np.eye(3) if S_inv0 is None else np.asarray(S_inv0, float).reshape(3, 3)
    return rots, numbers, qs, qe, fs, Sigma, b0, M0


def _initial_state(rots, qs, h: float, b0, M0, estimate_bias: bool) -> tuple[np.ndarray, np.ndarray]:
    """Initial guess of Särkkä et al., IEEE Sensors Journal 17(11) 2017, section IV-A: the forward
    solution of eq. (2) over each rotation from its known start, with the pre-adjusted rates.

    Returns the stacked unknowns x and the end attitude of each rotation before calibration.
    """
    q_init = [quat.integrate((r - b0) @ M0.T, h, q0) for r, q0 in zip(rots, qs)]
    pre_end = np.array([q[-1] for q in q_init])
    theta0 = np.concatenate([M0.T.ravel(), b0 if estimate_bias else []])
    return np.concatenate([np.vstack(q_init).ravel(), theta0]), pre_end


def _saturated_lambda(prob: _Problem, x, lambdas, max_iterations: int, tolerance: float, gates: Gates):
    """λ by the saturation rule of Särkkä et al., IEEE Sensors Journal 17(11) 2017, section IV-A-1.

    λ is raised until the calibration parameters saturate, and the greater saturation point is
    taken: a plateau is accepted only if the largest λ agrees with it.  Returns x, the chosen λ,
    the path of changes and the total Gauss–Newton iterations.
    """
    path = []
    total_it = 0
    prev = None
    chosen = None
    grid = list(lambdas)
    i = 0
    while i < len(grid):
        value = grid[i]
        x, it = _gauss_newton(prob, x, value, max_iterations, tolerance)
        total_it += it
        theta = x[prob.n_q :].copy()
        change: float | None = None if prev is None else float(np.max(np.abs(theta - prev)))
        path.append({"lambda": value, "max_change": change})
        if change is not None and change < SATURATION:
            if value == grid[-1]:
                chosen = value
                break
            # Probe the top of the range: if it agrees, this plateau is the greater one.
            x_top, it = _gauss_newton(prob, x.copy(), grid[-1], max_iterations, tolerance)
            total_it += it
            top_change = float(np.max(np.abs(x_top[prob.n_q :] - theta)))
            path.append({"lambda": grid[-1], "max_change": top_change, "probe": True})
            if top_change < SATURATION:
                chosen = value
                break
        prev = theta
        i += 1
    if chosen is None:
        chosen = float(grid[-1])
        gates.warn(
            f"gyr: the parameters did not saturate for λ up to {chosen:g} (Särkkä et al. section IV-A-1); "
            "the last value was used"
        )
    return x, chosen, path, total_it


def _covariance(
    prob: _Problem,
    lin: _Linearisation,
    Sigma,
    estimate_bias: bool,
    bias_covariance,
    rate_error_weights,
    rate_error_covariance,
) -> np.ndarray:
    """Covariance (12, 12) of [columns of S_ω⁻¹, b] by Särkkä et al., IEEE Sensors Journal 17(11)
    2017, Appendix B, eq. (28): V(θ) = [H⁻¹ Jᵀ J_y Σ J_yᵀ J H⁻¹]_θθ (Gauss–Newton C ≈ 2H,
    D = 2JᵀJ_y), plus a removed drift's error and a held bias's covariance."""
    h, n_theta = prob.h, prob.n_theta
    Z = _NormalSolver(lin).theta_columns()
    J = lin.jacobian()
    T = (J[: prob.n_r1] @ Z).reshape(-1, 4, n_theta)
    Uy = np.zeros((prob.N, 3, n_theta))
    ka = 0.25 * h * quat.xi_matrix(lin.Qa) @ lin.M  # ∂r_j/∂ω̃_a
    kc = 0.25 * h * quat.xi_matrix(lin.Qc) @ lin.M  # ∂r_j/∂ω̃_c
    Uy[prob.a] += _tmm(ka, T)
    Uy[prob.c] += _tmm(kc, T)
    cov_t = np.tensordot(Uy, Sigma @ Uy, axes=([0, 1], [0, 1]))
    if rate_error_weights is not None and rate_error_covariance is not None:
        tau = np.concatenate([np.asarray(t, float).reshape(-1) for t in rate_error_weights])
        G = np.tensordot(tau, Uy, axes=(0, 0))  # (3, n_θ): δθ = Gᵀ e
        cov_t = cov_t + G.T @ np.asarray(rate_error_covariance, float).reshape(3, 3) @ G
    cov = np.zeros((12, 12))
    cov[:n_theta, :n_theta] = cov_t
    if not estimate_bias and bias_covariance is not None:
        cov[9:12, 9:12] = np.asarray(bias_covariance, float).reshape(3, 3)
    return cov


def _metrics(
    prob: _Problem,
    lin: _Linearisation,
    x,
    rots,
    qs,
    qe,
    pre_end,
    M_hat,
    b_hat,
    chosen: float,
    path: list,
    total_it: int,
) -> tuple[dict, np.ndarray]:
    """Residual sizes and the check of every rotation: the forward solution with the calibrated
    rates against the protocol's end attitudes, before and after (degrees)."""
    h = prob.h
    cal_end = np.array([quat.integrate((rr - b_hat) @ M_hat.T, h, q0)[-1] for rr, q0 in zip(rots, qs)])
    err_after = _angle_deg(cal_end, qe)
    err_before = _angle_deg(pre_end, qe)
    r = lin.r
    r1 = r[: prob.n_r1]
    metrics = {
        "lambda": chosen,
        "lambda_path": path,
        "iterations": total_it,
        "n_rotations": len(rots),
        "n_samples": prob.N,
        "n_unknowns": prob.n_x,
        "rms_r1": float(np.sqrt(np.mean(r1**2))),
        "rms_r2": float(np.sqrt(np.mean(r[prob.n_r1 :] ** 2) / chosen)),
        "end_error_deg_before": err_before.tolist(),
        "end_error_deg_after": err_after.tolist(),
        "max_end_error_deg": float(err_after.max()),
        "quaternion_norm_max_deviation": float(
            np.max(np.abs(np.linalg.norm(x[: prob.n_q].reshape(-1, 4), axis=1) - 1))
        ),
    }
    return metrics, err_after


def fit_gyroscope(
    rotations,
    q_start,
    q_end,
    *,
    sampling_rate_hz: float,
    noise_cov,
    bias0=None,
    S_inv0=None,
    lam: float | None = None,
    lambdas=LAMBDAS,
    estimate_bias: bool = True,
    bias_covariance=None,
    rate_error_weights=None,
    rate_error_covariance=None,
    rotation_numbers=None,
    max_iterations: int = 20,
    tolerance: float = 1e-9,
) -> GyroCalibration:
    """Calibrate a gyroscope from rotations between known attitudes (Särkkä et al., IEEE Sensors
    Journal 17(11) 2017, sections III-B, IV-A).

    Parameters
    ----------
    rotations : sequence of numpy.ndarray, each (N_k, 3)
        Raw rates over each rotation, starting and ending at rest, in pre-adjusted rad/s
        (datasheet scale, Särkkä et al., IEEE Sensors Journal 17(11) 2017, section IV-A).
    q_start, q_end : array_like, shape (K, 4)
        Known attitude at the start and at the end of each rotation, on the branch the rotation
        reaches (a 360° turn ends at −q_start).
    sampling_rate_hz : float
        Sampling rate; the step is h = 1 / rate.
    noise_cov : array_like, shape (3, 3) or (3,)
        Noise covariance of one raw sample (from the still positions), for Appendix B.
    bias0 : array_like, shape (3,), optional
        Initial bias: the mean rate of the still positions (pre-adjustment).
    S_inv0 : array_like, shape (3, 3), optional
        Initial S_ω⁻¹; identity by default (off-diagonals zero, Särkkä et al., IEEE Sensors Journal
        17(11) 2017, section IV-A).
    lam : float, optional
        Fixed λ; by default it is chosen by the saturation rule of Särkkä et al., IEEE Sensors Journal
        17(11) 2017, section IV-A-1.
    lambdas : sequence of float
        The λ values tried upwards.
    estimate_bias : bool
        False holds b at ``bias0`` (for protocols with fewer than four rotations).
    bias_covariance : array_like, shape (3, 3), optional
        Covariance of ``bias0`` when it is held (the still positions' covariance over their
        sample count, Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (23)); it fills the bias
        block of the covariance.
    rate_error_weights : sequence of numpy.ndarray, optional
        Per rotation, per sample, the factor τ by which an error e common to all samples enters
        the rates (a removed drift: τ = (t − t_1)/(t_E − t_1)); with ``rate_error_covariance``
        (of e, 3×3) its effect is added to the covariance.
    rate_error_covariance : array_like, shape (3, 3), optional
    rotation_numbers : sequence of int, optional
        1-based protocol numbers of the rotations, for messages.
    max_iterations, tolerance
        Gauss–Newton stops when no element of S⁻¹ or b moves by more than ``tolerance`` (well
        below :data:`SATURATION`).

    Returns
    -------
    GyroCalibration

    Raises
    ------
    CalibrationError
        Shapes, non-finite values, rotations of fewer than 3 samples.
    InsufficientDataError
        Too few rotations for the parameters (3 attitude equations per rotation).
    """
    rots, numbers, qs, qe, fs, Sigma, b0, M0 = _validated(
        rotations,
        q_start,
        q_end,
        sampling_rate_hz,
        noise_cov,
        bias0,
        S_inv0,
        estimate_bias,
        rotation_numbers,
    )
    h = 1.0 / fs
    prob = _Problem(rots, qs, qe, h, estimate_bias, b0)
    x, pre_end = _initial_state(rots, qs, h, b0, M0, estimate_bias)
    gates = Gates()
    if lam is not None:
        x, total_it = _gauss_newton(prob, x, float(lam), max_iterations, tolerance)
        chosen, path = float(lam), []
    else:
        x, chosen, path, total_it = _saturated_lambda(prob, x, lambdas, max_iterations, tolerance, gates)
    lin = prob.evaluate(x, chosen)
    cov = _covariance(prob, lin, Sigma, estimate_bias, bias_covariance, rate_error_weights, rate_error_covariance)
    M_hat, b_hat = prob.theta_parts(x[prob.n_q :])
    metrics, err_after = _metrics(prob, lin, x, rots, qs, qe, pre_end, M_hat, b_hat, chosen, path, total_it)
    gates.fail(
        residual_gate(
            err_after,
            MAX_END_ERROR_DEG,
            lambda index, value, limit, **_: (
                f"gyr: rotation {numbers[index]} still ends {value:.1f}° from the protocol's attitude "
                f"after calibration (gate {limit}°): it was not the rotation the protocol expects, "
                "or the gyroscope saturated"
            ),
        )
    )
    if not estimate_bias:
        gates.warn("gyr: the bias was held at the mean rate of the still positions (too few rotations)")
    return GyroCalibration(
        S_inv=M_hat,
        b=np.asarray(b_hat, float).copy(),
        lam=chosen,
        covariance=cov,
        rotations=numbers,
        sampling_rate_hz=fs,
        metrics=metrics,
        **gates.fields(),
    )


def fit_gyroscope_full_turns(
    rotations,
    body_axes,
    angles_deg,
    *,
    sampling_rate_hz: float,
    noise_cov,
    bias,
    bias_covariance,
    rotation_numbers=None,
) -> GyroCalibration:
    """S_ω⁻¹ from full turns about three sensor axes (the ferraris protocol), bias from rest.

    A 360° turn ends where it started whatever the axis, so the attitude residual (5) of Särkkä et al.,
    IEEE Sensors Journal 17(11) 2017
    constrains only the turn's magnitude, not its axis.  Here, as in Ferraris' method, the
    integrated rate of each turn must equal the turn's rotation vector:
    ``S_ω⁻¹ ∫(ω̃ − b) dt = θ_k a_k`` (trapezoidal rule), three columns for the nine elements.
    The covariance propagates the sample noise of the integrals and the error of the bias.
    Like Ferraris' method it assumes each turn keeps a fixed axis; a wandering axis biases S⁻¹.

    Parameters
    ----------
    rotations : sequence of numpy.ndarray (N_k, 3)
        Raw rates over each turn (three turns about independent axes).
    body_axes : array_like, shape (3, 3)
        Unit axis of each turn in the sensor frame.
    angles_deg : array_like, shape (3,)
        Signed angle of each turn.
    sampling_rate_hz, noise_cov
        As in :func:`fit_gyroscope`.
    bias, bias_covariance : array_like
        Bias from the still positions and its covariance (noise / count, Särkkä et al., IEEE Sensors
        Journal 17(11) 2017, eq. (23)).

    Returns
    -------
    GyroCalibration
    """
    rots = [np.asarray(r, float) for r in rotations]
    if len(rots) != 3:
        raise InsufficientDataError(f"full-turn calibration needs three turns about independent axes; got {len(rots)}")
    h = 1.0 / float(sampling_rate_hz)
    b = np.asarray(bias, float).reshape(3)
    Sigma = np.asarray(noise_cov, float).reshape(3, 3)
    Vb = np.asarray(bias_covariance, float).reshape(3, 3)
    U = np.zeros((3, 3))
    T = np.zeros(3)
    for k, r in enumerate(rots):
        u = r - b
        U[:, k] = h * (u.sum(axis=0) - 0.5 * (u[0] + u[-1]))  # trapezoidal rule
        T[k] = h * (len(r) - 1)
    A = np.asarray(body_axes, float).T * np.radians(np.asarray(angles_deg, float))
    if abs(np.linalg.det(U)) < 1e-12 * np.prod(np.linalg.norm(U, axis=0)):
        raise InsufficientDataError("the three turns are not about independent axes")
    M = A @ np.linalg.inv(U)
    # δM = −M δU U⁻¹, vec(δM) = −(U⁻ᵀ ⊗ M) vec(δU); δU_k = δs_k − T_k δb.
    JU = -np.kron(np.linalg.inv(U).T, M)
    dU_de = np.hstack([np.eye(9), -np.kron(T[:, None], np.eye(3))])
    Je = np.vstack([JU @ dU_de, np.hstack([np.zeros((3, 9)), np.eye(3)])])
    Ce = np.zeros((12, 12))
    for k, r in enumerate(rots):
        Ce[3 * k : 3 * k + 3, 3 * k : 3 * k + 3] = (len(r) - 1) * h * h * Sigma
    Ce[9:, 9:] = Vb
    cov = Je @ Ce @ Je.T
    numbers = tuple(range(1, 4)) if rotation_numbers is None else tuple(int(n) for n in rotation_numbers)
    return GyroCalibration(
        S_inv=M,
        b=b.copy(),
        lam=float("nan"),
        covariance=cov,
        rotations=numbers,
        sampling_rate_hz=float(sampling_rate_hz),
        metrics={"method": "full_turns", "n_rotations": 3},
        warnings=(
            "gyr: full turns calibrate S⁻¹ from their integrated rates (Ferraris); the bias is the "
            "mean rate of the still positions",
        ),
        reasons=(),
    )
