"""Accelerometer and magnetometer of the cube method (Särkkä et al., IEEE Sensors Journal 17(11) 2017,
III-C and IV-B).

At each still position p the mean reading is modelled as

    ỹ_p = S R_pᵀ C_l^c(α, β) r + b          (Särkkä et al., IEEE Sensors Journal 17(11) 2017, eqs. (6), (7))

with R_p the known attitude of the position (sensor → calibration frame, ``C_c^s = R_pᵀ``),
``C_l^c`` the two-angle matrix of eq. (8), and r = (0, 0, |r|) the reference in the local frame:
the specific force of gravity (reading +g on the axis that points up, docs/methods.md) or the Earth's
field.  S, b, α and β are estimated together by non-linear generalised least squares (eq. (13))
with the weight W = V(ε)⁻¹, V(ε) = diag(Σ_p / n_p) (Appendix A, eq. (23)); their covariance is
(Jᵀ V(ε)⁻¹ J)⁻¹ (eq. (22)) and the 95 % half-widths are 1.96 σ (Appendix A).  S = D (D⁻¹S) with D
the column norms of S (section III-A).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..shared.errors import CalibrationError, InsufficientDataError
from ..shared.gates import Gates, limit_gate, residual_gate
from ..shared.result import GatedFit, gate_fields
from ..shared.uncertainty import CONFIDENCE
from ..shared.validation import as_samples, as_vectors

MAX_FIT_ERROR = 0.05
"""A calibrated position mean further than 5 % of the reference from its model fails the fit."""

MAX_REDUCED_CHI2 = 25.0
"""Above this χ²/dof the sample covariances do not explain the misfit: intervals are too small."""

N_PARAMETERS = 14


def reference_direction(alpha: float, beta: float) -> np.ndarray:
    """``C_l^c e_z`` of Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (8): the reference
    direction in the calibration frame."""
    return np.array([-np.sin(beta), np.sin(alpha) * np.cos(beta), np.cos(alpha) * np.cos(beta)])


def direction_matrix(alpha: float, beta: float) -> np.ndarray:
    """``C_l^c`` of Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (8) (local → calibration frame)."""
    ca, sa, cb, sb = np.cos(alpha), np.sin(alpha), np.cos(beta), np.sin(beta)
    # Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (8)
    return np.array([[cb, 0.0, -sb], [sa * sb, ca, sa * cb], [ca * sb, -sa, ca * cb]])


def decompose(S: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``S = D (D⁻¹S)``: D the column norms of S (Särkkä et al., IEEE Sensors Journal 17(11) 2017,
    section III-A), returned as a vector."""
    D = np.linalg.norm(S, axis=0)
    return D, S / D[:, None]


def decomposition_jacobian(S: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Derivatives of D (3) and D⁻¹S (9, row-major) with respect to S (9, row-major)."""
    D, _M = decompose(S)
    JD = np.zeros((3, 9))
    for j in range(3):
        for i in range(3):
            JD[j, 3 * i + j] = S[i, j] / D[j]
    JM = np.zeros((9, 9))
    for i in range(3):
        for j in range(3):
            row = 3 * i + j
            JM[row, 3 * i + j] += 1.0 / D[i]
            JM[row] -= S[i, j] / D[i] ** 2 * JD[i]
    return JD, JM


def _quantile(confidence: float) -> float:
    from scipy import stats  # here: scipy.stats takes ~0.5 s to import, which every start of the server would pay

    return float(stats.norm.ppf(0.5 + confidence / 2.0))


@dataclass(frozen=True)
class SensorFit(GatedFit):
    """A cube sensor's fit, ``raw = S f + b`` (Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (1)), with
    its own gates: the scale factors and misalignments of its S."""

    if TYPE_CHECKING:  # every sensor's fields

        @property
        def S(self) -> np.ndarray: ...

        @property
        def b(self) -> np.ndarray: ...

    @property
    def D(self) -> np.ndarray:
        """Scale factors: the column norms of S (Särkkä et al. section III-A), shape (3,)."""
        return decompose(self.S)[0]

    @property
    def misalignment(self) -> np.ndarray:
        """D⁻¹S, (3, 3): misalignments and cross-coupling (soft iron for the magnetometer, the gyroscope's
        D_ω⁻¹ S_ω)."""
        return decompose(self.S)[1]

    def model(self) -> dict:
        """S, b, D and the misalignment as plain lists, then the sensor's own parameters (:meth:`own_model`)."""
        return {
            "S": self.S.tolist(),
            "b": self.b.tolist(),
            "D": self.D.tolist(),
            "misalignment": self.misalignment.tolist(),
            **self.own_model(),
        }

    def own_model(self) -> dict:  # pragma: no cover - every sensor defines it
        raise NotImplementedError


@dataclass(frozen=True)
class FieldSensorCalibration(SensorFit):
    """Result of the accelerometer or magnetometer fit of Särkkä et al. (eqs. (6)–(8), (13)).

    Attributes
    ----------
    sensor : str
        ``acc`` or ``mag``.
    S, b : numpy.ndarray
        Model ``raw = S f + b`` (Särkkä et al. eq. (1)), S (3, 3) in raw units per reference unit, b (3,).
    alpha_deg, beta_deg : float
        Direction of the reference in the calibration frame (Särkkä et al. eq. (8)).
    reference : float
        Magnitude |r| of the reference (gravity, or the field in µT).
    covariance : numpy.ndarray, shape (14, 14)
        Covariance of [S (row-major), b, α, β] in radians for the angles (Särkkä et al. eq. (22)).
    means, covariances, counts : numpy.ndarray
        Position means (P, 3), their sample covariances (P, 3, 3) and sample counts (P,).
    attitudes : numpy.ndarray, shape (P, 3, 3)
        R_p of every fitted position.
    positions : tuple of int
        1-based protocol position of every fitted mean.
    angles_estimated : bool
        False when α and β were held at zero (headings unknown).
    metrics, warnings, reasons
        As everywhere in the core; ``ok`` is true when ``reasons`` is empty.
    """

    sensor: str
    S: np.ndarray
    b: np.ndarray
    alpha_deg: float
    beta_deg: float
    reference: float
    covariance: np.ndarray
    means: np.ndarray
    covariances: np.ndarray
    counts: np.ndarray
    attitudes: np.ndarray
    positions: tuple = ()
    angles_estimated: bool = True

    def apply(self, raw) -> np.ndarray:
        """Calibrate readings: ``f = S⁻¹ (raw − b)`` (Särkkä et al. eq. (1) without noise)."""
        m = as_samples(raw)
        return np.linalg.solve(self.S, (m - self.b).reshape(-1, 3).T).T.reshape(m.shape)

    def predicted(self) -> np.ndarray:
        """Model means ``S R_pᵀ C r + b`` at the fitted positions, (P, 3)."""
        u = reference_direction(np.radians(self.alpha_deg), np.radians(self.beta_deg)) * self.reference
        return np.einsum("ij,pkj,k->pi", self.S, self.attitudes, u) + self.b

    def uncertainty(self, confidence: float = CONFIDENCE) -> dict:
        """95 % half-widths of S, b, D, D⁻¹S, α and β in the shapes of the model (Särkkä et al. App. A).

        D and D⁻¹S are propagated from the covariance of S to first order (the paper neglects
        the error of D for D⁻¹S; here it is included).
        """
        z = _quantile(confidence)
        cov = self.covariance
        sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
        JD, JM = decomposition_jacobian(self.S)
        cs = cov[:9, :9]
        sd_D = np.sqrt(np.clip(np.diag(JD @ cs @ JD.T), 0.0, None))
        sd_M = np.sqrt(np.clip(np.diag(JM @ cs @ JM.T), 0.0, None))
        return {
            "confidence": confidence,
            "S": (z * sd[:9]).reshape(3, 3).tolist(),
            "b": (z * sd[9:12]).tolist(),
            "D": (z * sd_D).tolist(),
            "misalignment": (z * sd_M).reshape(3, 3).tolist(),
            "alpha_deg": float(np.degrees(z * sd[12])) if self.angles_estimated else None,
            "beta_deg": float(np.degrees(z * sd[13])) if self.angles_estimated else None,
        }

    def own_model(self) -> dict:
        """The angles α and β of the reference direction C_l^c(α, β) (Särkkä et al. eq. (8)), in degrees."""
        return {"alpha_deg": self.alpha_deg, "beta_deg": self.beta_deg}

    def to_dict(self) -> dict:
        """Plain-JSON form: model, uncertainty, covariance, fitted positions, metrics, gates."""
        return {
            "sensor": self.sensor,
            "model": self.model(),
            "uncertainty": self.uncertainty(),
            "covariance": self.covariance.tolist(),
            "reference": self.reference,
            "angles_estimated": self.angles_estimated,
            "positions": [
                {
                    "position": int(p),
                    "mean": m.tolist(),
                    "covariance": c.tolist(),
                    "count": int(n),
                    "attitude": R.tolist(),
                }
                for p, m, c, n, R in zip(self.positions, self.means, self.covariances, self.counts, self.attitudes)
            ],
            **self.gate_dict(),
        }

    @classmethod
    def from_dict(cls, data: dict) -> FieldSensorCalibration:
        """Rebuild a result from :meth:`to_dict` output."""
        model = data["model"]
        rows = data.get("positions") or []
        return cls(
            sensor=data["sensor"],
            S=np.asarray(model["S"], dtype=float),
            b=np.asarray(model["b"], dtype=float),
            alpha_deg=float(model["alpha_deg"]),
            beta_deg=float(model["beta_deg"]),
            reference=float(data["reference"]),
            covariance=np.asarray(data["covariance"], dtype=float),
            means=np.asarray([r["mean"] for r in rows], dtype=float).reshape(-1, 3),
            covariances=np.asarray([r["covariance"] for r in rows], dtype=float).reshape(-1, 3, 3),
            counts=np.asarray([r["count"] for r in rows], dtype=int),
            attitudes=np.asarray([r["attitude"] for r in rows], dtype=float).reshape(-1, 3, 3),
            positions=tuple(int(r["position"]) for r in rows),
            angles_estimated=bool(data.get("angles_estimated", True)),
            **gate_fields(data),
        )


def _model_and_jacobian(x: np.ndarray, attitudes: np.ndarray, ref: float):
    """h(x) of Särkkä et al., IEEE Sensors Journal 17(11) 2017, eqs. (6)–(7) stacked over positions,
    and its Jacobian (3P, 14)."""
    S = x[:9].reshape(3, 3)
    alpha, beta = x[12], x[13]
    u = reference_direction(alpha, beta) * ref
    du_da = np.array([0.0, np.cos(alpha) * np.cos(beta), -np.sin(alpha) * np.cos(beta)]) * ref
    du_db = np.array([-np.cos(beta), -np.sin(alpha) * np.sin(beta), -np.cos(alpha) * np.sin(beta)]) * ref
    Rt = np.transpose(attitudes, (0, 2, 1))
    v = Rt @ u  # (P, 3): reference in the sensor frame, C_c^s C_l^c r
    h = v @ S.T + x[9:12]
    P = len(attitudes)
    J = np.zeros((P, 3, N_PARAMETERS))
    for i in range(3):
        J[:, i, 3 * i : 3 * i + 3] = v  # ∂h_i/∂S_ij = v_j
        J[:, i, 9 + i] = 1.0
    J[:, :, 12] = (Rt @ du_da) @ S.T
    J[:, :, 13] = (Rt @ du_db) @ S.T
    return h.reshape(-1), J.reshape(3 * P, N_PARAMETERS)


def _whitener(covariances: np.ndarray, counts: np.ndarray, warnings: list, extra=None) -> np.ndarray:
    """W with WᵀW = V(ε)⁻¹, V(ε) = diag(Σ_p / n_p) (Särkkä et al., IEEE Sensors Journal 17(11) 2017,
    eq. (23)) plus ``extra`` (3P × 3P).

    ``extra`` carries errors shared between positions, e.g. those of a removed drift.  Singular
    blocks (rounded or constant readings) are floored, with a warning.
    """
    V = covariances / counts[:, None, None]
    P = len(V)
    scale = np.median(np.trace(V, axis1=1, axis2=2)) / 3.0
    floored = False
    full = np.zeros((3 * P, 3 * P))
    for p, Vp in enumerate(V):
        w, Q = np.linalg.eigh(Vp)
        floor = max(1e-6 * scale, 1e-300)
        if not np.all(w > floor):
            floored = True
            w = np.maximum(w, floor if scale > 0 else 1.0)
        full[3 * p : 3 * p + 3, 3 * p : 3 * p + 3] = Q @ np.diag(w) @ Q.T
    if floored:
        warnings.append(
            "some positions have a (near-)zero sample variance, e.g. rounded or constant readings: "
            "their weight was floored and the intervals are not reliable"
        )
    if extra is not None:
        full = full + np.asarray(extra, dtype=float)
    Lc = np.linalg.cholesky(full)
    return np.linalg.inv(Lc)  # W = L⁻¹: WᵀW = (L Lᵀ)⁻¹


def drift_covariance(times_s, covariances, counts) -> np.ndarray:
    """Covariance (3P × 3P) added to the position means by removing an affine drift (Särkkä et al.,
    IEEE Sensors Journal 17(11) 2017, §II).

    The drift is the difference of the last mean (the return to position 1, not fitted) and
    the first over their time apart; position p is corrected by τ_p (m_E − m_1), τ_p = (t_p −
    t_1)/(t_E − t_1).  ``times_s``, ``covariances`` and ``counts`` cover the P fitted positions
    followed by the return.
    """
    t = np.asarray(times_s, float)
    V = np.asarray(covariances, float) / np.asarray(counts, float)[:, None, None]
    P = len(t) - 1
    tau = (t[:P] - t[0]) / (t[-1] - t[0])
    Vd = V[0] + V[-1]
    extra = np.kron(np.outer(tau, tau), Vd)
    # Cross terms with position 1, whose own error enters the drift estimate.
    for q in range(1, P):
        extra[0:3, 3 * q : 3 * q + 3] += tau[q] * V[0]
        extra[3 * q : 3 * q + 3, 0:3] += tau[q] * V[0]
    return extra


def _initial_guess(means: np.ndarray, attitudes: np.ndarray, ref: float, estimate_angles: bool) -> np.ndarray:
    """Start of the iteration (Särkkä et al., IEEE Sensors Journal 17(11) 2017, section IV-B): a linear
    fit of S and b with the field direction
    guessed from the data, so that a far-from-vertical field (the magnetometer) converges too."""
    if estimate_angles:
        b0 = means.mean(axis=0)
        # With S ≈ s I, R_p (ỹ_p − b) ≈ s C r: the mean over positions points along the reference.
        d = np.einsum("pij,pj->i", attitudes, means - b0)
        n = np.linalg.norm(d)
        u = d / n if n > 0 else np.array([0.0, 0.0, 1.0])
        beta = float(np.arcsin(np.clip(-u[0], -1.0, 1.0)))
        alpha = float(np.arctan2(u[1], u[2]))
    else:
        alpha = beta = 0.0
    v = np.transpose(attitudes, (0, 2, 1)) @ (reference_direction(alpha, beta) * ref)
    A = np.hstack([v, np.ones((len(v), 1))])
    W, *_ = np.linalg.lstsq(A, means, rcond=None)
    return np.concatenate([W[:3].T.reshape(-1), W[3], [alpha, beta]])


def _validated(means, covariances, counts, attitudes, reference, sensor: str, estimate_angles: bool):
    """Checked means, covariances, counts, attitudes and the number of free parameters
    (Särkkä et al., IEEE Sensors Journal 17(11) 2017, section III-C: three equations per position)."""
    m = as_vectors(means, f"{sensor} means")
    P = len(m)
    C = np.asarray(covariances, dtype=float)
    n = np.asarray(counts, dtype=float).reshape(-1)
    Rs = np.asarray(attitudes, dtype=float)
    if C.shape != (P, 3, 3) or n.shape != (P,) or Rs.shape != (P, 3, 3):
        raise CalibrationError(
            f"{sensor}: give one 3×3 covariance, one count and one 3×3 attitude per mean "
            f"({P} means; got {C.shape}, {n.shape}, {Rs.shape})"
        )
    if not (np.isfinite(reference) and reference > 0):
        raise CalibrationError(f"{sensor}: the reference magnitude must be positive and finite; got {reference!r}")
    if not np.all(np.isfinite(C)) or np.any(n < 1):
        raise CalibrationError(f"{sensor}: covariances must be finite and counts at least 1")
    n_par = N_PARAMETERS if estimate_angles else 12
    if n_par >= 3 * P:
        raise InsufficientDataError(
            f"{sensor}: {P} still positions give {3 * P} equations for {n_par} parameters (Särkkä et al. section "
            f"III-C); at least {n_par // 3 + 1} positions are needed, 24 in the cube protocol"
        )
    return m, C, n, Rs, n_par


def _gauss_newton(x, free, m, Rs, ref: float, L, sensor: str, max_iterations: int, tolerance: float):
    """The iteration of Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (13), in whitened
    least-squares form; returns the parameters, the iterations and whether it converged."""
    y = m.reshape(-1)
    converged = False
    it = 0
    for it in range(1, max_iterations + 1):  # noqa: B007 - the count of iterations is read after the loop
        h, J = _model_and_jacobian(x, Rs, ref)
        p = h - y  # Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (12)
        # Eq. (13), step 3: (Jᵀ W J) Δx = Jᵀ W p, solved in whitened least-squares form.
        Jw = L @ J[:, free]
        pw = L @ p
        scale = np.linalg.norm(Jw, axis=0)
        if np.any(scale == 0) or not np.all(np.isfinite(Jw)):
            raise CalibrationError(
                f"{sensor}: the readings do not change between positions, so S cannot be determined; "
                "check that the sensor was sampled and the device turned"
            )
        dx, *_ = np.linalg.lstsq(Jw / scale, pw, rcond=None)
        dx = dx / scale
        x[free] -= dx
        if (
            np.linalg.norm(dx * scale) <= tolerance * max(1.0, float(np.linalg.norm(pw)))
            or np.max(np.abs(dx) / np.maximum(np.abs(x[free]), 1e-12)) < tolerance
        ):
            converged = True
            break
    return x, it, converged


def _covariance(x, free, m, Rs, ref: float, L, sensor: str):
    """(Jᵀ V(ε)⁻¹ J)⁻¹ of Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (22), embedded in
    14 × 14 (zeros for held angles), with the condition number, the model h and the whitened misfit."""
    h, J = _model_and_jacobian(x, Rs, ref)
    Jw = L @ J[:, free]
    pw = L @ (h - m.reshape(-1))
    info = Jw.T @ Jw
    cond = float(np.linalg.cond(info))
    if not np.isfinite(cond) or cond > 1e15:
        raise InsufficientDataError(
            f"{sensor}: the positions do not determine the model (information matrix singular); "
            "use positions that point every axis both up and down"
        )
    cov = np.zeros((N_PARAMETERS, N_PARAMETERS))
    cov[np.ix_(free, free)] = np.linalg.inv(info)  # eq. (22)
    return cov, cond, h, pw


def _metrics(m, h, S, pw, reference, n_par: int, it: int, converged: bool, cond: float):
    """χ², misfit in the reference's unit (S⁻¹ applied to the residual means) and the relative
    misfit of each position."""
    P = len(m)
    chi2 = float(pw @ pw)
    dof = 3 * P - n_par
    resid = m - h.reshape(P, 3)
    resid_ref = np.linalg.solve(S, resid.T).T
    rel = np.linalg.norm(resid_ref, axis=1) / reference
    metrics = {
        "iterations": it,
        "converged": converged,
        "chi2": chi2,
        "dof": dof,
        "reduced_chi2": chi2 / dof,
        "rms_residual": float(np.sqrt(np.mean(resid_ref**2))),
        "max_relative_error": float(rel.max()),
        "condition_number": cond,
        "n_positions": P,
    }
    return metrics, rel


def _gates(metrics: dict, rel, positions, sensor: str, max_iterations: int, gates: Gates) -> None:
    """Convergence and misfit per position (reasons); χ²/dof beyond the sample noise (warning,
    Särkkä et al., IEEE Sensors Journal 17(11) 2017, section VII-A-2)."""
    if not metrics["converged"]:
        gates.fail(
            f"{sensor}: the generalised least squares did not converge in {max_iterations} iterations; "
            "check the positions and the protocol"
        )
    gates.fail(
        residual_gate(
            rel,
            MAX_FIT_ERROR,
            lambda index, percent, gate_percent, **_: (
                f"{sensor}: position {positions[index]} is {percent:.1f} % of the reference away from "
                f"the model after calibration (gate {gate_percent:.0f} %): the position is not the one "
                "the protocol expects, or the sensor moved"
            ),
        )
    )
    gates.warn(
        limit_gate(
            metrics["reduced_chi2"],
            MAX_REDUCED_CHI2,
            "{sensor}: χ²/dof = {value:.3g}: the misfit is larger than the sample noise explains "
            "(unmodelled errors or drift, Särkkä et al. section VII-A-2), so the intervals are too narrow",
            sensor=sensor,
        )
    )


def fit_field_sensor(
    means,
    covariances,
    counts,
    attitudes,
    *,
    reference: float,
    sensor: str = "acc",
    estimate_angles: bool = True,
    positions=None,
    mean_covariance_extra=None,
    max_iterations: int = 50,
    tolerance: float = 1e-10,
) -> FieldSensorCalibration:
    """Generalised least-squares fit of Särkkä et al., IEEE Sensors Journal 17(11) 2017, eqs. (6)–(8)
    and (13) with 95 % intervals.

    Parameters
    ----------
    means : array_like, shape (P, 3)
        Mean raw reading in each still position.
    covariances : array_like, shape (P, 3, 3)
        Sample covariance of the readings in each position.
    counts : array_like, shape (P,)
        Number of samples behind each mean; V(ε) = diag(Σ_p / n_p) (Särkkä et al., IEEE Sensors Journal
        17(11) 2017, eq. (23)).
    attitudes : array_like, shape (P, 3, 3)
        Attitude R_p (sensor → calibration frame) of each position.
    reference : float
        Magnitude of the reference: gravity (m/s², or 1 for g) or the field (µT).
    sensor : str
        ``acc`` or ``mag``, for messages.
    estimate_angles : bool
        Estimate α and β (Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (8)); False holds them
        at 0 (positions known only by their up
        axis, so the reference is vertical in the calibration frame).
    positions : sequence of int, optional
        1-based protocol number of each position, for messages.
    mean_covariance_extra : array_like, shape (3P, 3P), optional
        Covariance added to V(ε), e.g. :func:`drift_covariance` after a drift was removed.
    max_iterations, tolerance
        Stopping rule of the iteration of Särkkä et al., IEEE Sensors Journal 17(11) 2017, section IV-B
        (relative step size).

    Returns
    -------
    FieldSensorCalibration

    Raises
    ------
    CalibrationError
        Wrong shapes or non-finite values, a non-positive reference, a singular fit.
    InsufficientDataError
        Fewer positions than the 14 (or 12) parameters need (3 equations per position).
    """
    m, C, n, Rs, n_par = _validated(means, covariances, counts, attitudes, reference, sensor, estimate_angles)
    P = len(m)
    positions = tuple(range(1, P + 1)) if positions is None else tuple(int(p) for p in positions)
    gates = Gates()
    L = _whitener(C, n, gates.warnings, extra=mean_covariance_extra)
    x = _initial_guess(m, Rs, float(reference), estimate_angles)
    free = np.arange(n_par)
    x, it, converged = _gauss_newton(x, free, m, Rs, float(reference), L, sensor, max_iterations, tolerance)
    cov, cond, h, pw = _covariance(x, free, m, Rs, float(reference), L, sensor)
    S = x[:9].reshape(3, 3)
    b = x[9:12]
    # Keep α in (−180°, 180°] for the report.
    alpha = float(np.degrees(np.arctan2(np.sin(x[12]), np.cos(x[12]))))
    beta = float(np.degrees(x[13]))
    metrics, rel = _metrics(m, h, S, pw, reference, n_par, it, converged, cond)
    _gates(metrics, rel, positions, sensor, max_iterations, gates)
    return FieldSensorCalibration(
        sensor=sensor,
        S=S,
        b=b,
        alpha_deg=alpha,
        beta_deg=beta,
        reference=float(reference),
        covariance=cov,
        means=m,
        covariances=C,
        counts=n.astype(int),
        attitudes=Rs,
        positions=positions,
        angles_estimated=estimate_angles,
        metrics=metrics,
        **gates.fields(),
    )


def expected_covariance(S, b, alpha_deg, beta_deg, attitudes, noise_cov, count, *, reference) -> np.ndarray:
    """Covariance (14, 14) of the estimates at the true parameters (Särkkä et al., IEEE Sensors Journal
    17(11) 2017, eq. (22)).

    For a design (attitudes, samples per position, noise covariance) this is what the intervals
    of a fit converge to; it reproduces the half-widths of Särkkä et al., IEEE Sensors Journal 17(11)
    2017, Table VII without simulation.
    """
    x = np.concatenate(
        [np.asarray(S, float).reshape(-1), np.asarray(b, float), [np.radians(alpha_deg), np.radians(beta_deg)]]
    )
    Rs = np.asarray(attitudes, dtype=float)
    _, J = _model_and_jacobian(x, Rs, float(reference))
    Vinv = np.linalg.inv(np.asarray(noise_cov, float) / count)
    Wfull = np.kron(np.eye(len(Rs)), Vinv)
    return np.linalg.inv(J.T @ Wfull @ J)
