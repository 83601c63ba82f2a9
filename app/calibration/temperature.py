"""Temperature calibration: each axis's offset as a polynomial of the sensor's temperature.

From a recording of a device resting still while its temperature changes (a cold board powered on
and left alone: PX4's thermal calibration procedure, ``Tools/process_sensor_caldata.py``), each axis
of the accelerometer and of the gyroscope gets an offset

    o(T) = X0 + X1·dT + X2·dT² + X3·dT³,   dT = clamp(T, T_min, T_max) − T_ref,

the form PX4's ``TemperatureCompensation`` applies (``src/modules/sensors/temperature_compensation``),
subtracted from the reading: ``corrected = m − o(T)``. The steps:

1. **Bins of temperature** (as PX4's ``process_sensor_caldata.py``, ``resampleWithDeltaX``): the
   range is cut into :data:`N_BINS` equal bins, each also cut every 1/:data:`N_BINS` of the
   recording's duration (the board resting at its final temperature fills many bins, not one); each
   bin's samples are averaged (temperature and reading). The samples of a still recording are strongly correlated in
   time, and a bin's mean
   stands for a stretch of time: the fit sees bin means, not samples, so its degrees of freedom are
   the bins', not the millions of samples'.
2. **Generalised least squares on the bin means**, per axis, in dT scaled to [−1, 1] for
   conditioning. Over a warm-up the temperature rises with time, so a bias that wanders in time (a
   random walk, the rate random walk of IEEE Std 952-1997, Annex C) looks like drift and moves every
   bin after it together: the bins' covariance is modelled as σ² (I + λ W), the white scatter of each
   bin's mean plus W, the covariance of the bins' means under a unit random walk in time (computed from
   the samples' times), and σ², λ are estimated by restricted maximum likelihood (Patterson and
   Thompson, Biometrika 58(3) 1971). The coefficients' covariance is σ² (Xᵀ V⁻¹ X)⁻¹, with Student-t
   quantiles on the bins' residual degrees of freedom. What correlation is left (the whitened
   residuals' lag-1 autocorrelation ρ, when positive) inflates it by (1 + ρ)/(1 − ρ) — the AR(1)
   effective sample size n' = n (1 − ρ)/(1 + ρ) (Wilks, *Statistical Methods in the Atmospheric
   Sciences*, 3rd ed., 2011, section 5.2.4, eq. (5.12)), the dof reduced to match.
3. **Order 1–3 by bands left out**: the range is cut into :data:`N_BANDS` equal bands of temperature;
   each band in turn is predicted by the fit on the others (the end bands are extrapolations, as the
   firmware's clamp is beyond the calibrated range). The order with the least RMS error on left-out
   bands wins, per axis. Order 0 (a constant: no temperature correction) on the same bands is the
   raw figure.

Decisions (no paper makes them; docs/methods.md says the same):

- ``T_ref`` is the middle of the recorded range (PX4's ``process_sensor_caldata.py`` does so).
- **The gyroscope's offset is its bias**: a still gyroscope reads its bias (plus the Earth's rotation,
  at most 7.3e-5 rad/s, which no offset can tell apart), so X0 is the bias at T_ref.
- **The accelerometer's offset is relative to T_ref**: a still accelerometer reads its bias plus
  gravity's projection, which is constant but unknown without poses; X0 = 0, and the model is the
  drift relative to the reading at T_ref. The six-pose (or any) calibration made near T_ref gives the
  absolute offset; the firmwares apply both (PX4 subtracts the thermal offset then ``CAL_ACC*``).
- **A device that moved**: gravity's projection changes with the pose, which a still recording's fit
  would take for drift. The accelerometer's fit is refused (``ok`` false) when the recording holds
  more than one rest; the gyroscope is fitted on its still samples only, the moving ones left out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from math import comb
from typing import ClassVar

import numpy as np

from .shared.errors import CalibrationError, InsufficientDataError
from .shared.gravity import STANDARD_GRAVITY
from .shared.headlines import FIGURE_WORDS, SENSOR_WORDS, TEMPERATURE_SENSORS
from .shared.result import DRIFT, Figure, PerSensorResult

CONFIDENCE = 0.95
N_BINS = 60
"""Bins of temperature over the range (PX4's script uses 2000 over samples at 50–400 Hz; fewer, fuller
bins keep each mean's noise low and the dof honest)."""
MIN_BIN_SAMPLES = 5
"""A bin with fewer samples is left out (an isolated reading, a jump of the temperature sensor)."""
N_BANDS = 5
"""Bands of temperature left out in turn for the order and the cross-validated figure."""
MIN_SPAN_C = 10.0
"""ArduPilot refuses a range under 10 °C (``TEMP_RANGE_MIN`` in ``AP_InertialSensor_tempcal.cpp``)."""
MIN_BAND_SAMPLES = 100
"""Each band needs at least this many samples…"""
MIN_BAND_BINS = 2
"""…in at least this many bins, for its left-out figure to mean something."""
MAX_ORDER = 3
MAX_RHO = 0.9
MIN_REST_S = 5.0
"""Rests shorter than this (a turn at a steady rate reads as one) are left out of the gyroscope's fit."""
STILL_FRACTION = 0.9
"""A recording whose longest rest is shorter than this fraction of it moved."""
G0 = STANDARD_GRAVITY
SI_UNITS = {"acc": "m/s^2", "gyr": "rad/s"}
FIGURE_UNITS = {"acc": "mg", "gyr": "deg/s"}
FIGURE_SCALE = {"acc": 1000.0 / G0, "gyr": 180.0 / math.pi}
"""SI → the unit a person reads the drift in: mg of standard gravity, °/s."""
CURVE_POINTS = 41


def _t_quantile(dof: float) -> float:
    from scipy.stats import t  # scipy.stats is slow to import: only when a fit runs

    return float(t.ppf(0.5 + CONFIDENCE / 2.0, dof))


def bin_by_temperature(values, temperature_c, time_s=None, n_bins: int = N_BINS):
    """Average the samples falling in equal bins of temperature (PX4's ``resampleWithDeltaX``), each bin
    also cut every 1/``n_bins`` of the recording's duration when ``time_s`` is given — a board resting at
    its final temperature fills many bins of time, not one, so that a bias wandering in time shows.

    Parameters
    ----------
    values : array_like, shape (N, 3)
    temperature_c : array_like, shape (N,)
    time_s : array_like, shape (N,), optional
    n_bins : int

    Returns
    -------
    t_c : ndarray (B,)
        Mean temperature of each kept bin, the bins in the order of their mean time.
    means : ndarray (B, 3)
        Mean reading of each kept bin.
    counts : ndarray (B,)
        Samples in each kept bin (bins under :data:`MIN_BIN_SAMPLES` are left out).
    index : ndarray (N,)
        The kept bin of each sample, −1 for a left-out one.
    """
    v = np.asarray(values, dtype=float)
    t = np.asarray(temperature_c, dtype=float)
    lo, hi = float(t.min()), float(t.max())
    width = (hi - lo) / n_bins if hi > lo else 1.0
    key = np.clip(((t - lo) / width).astype(np.int64), 0, n_bins - 1)
    clock = np.arange(len(t), dtype=float) if time_s is None else np.asarray(time_s, dtype=float)
    if time_s is not None:
        span = float(clock.max() - clock.min()) or 1.0
        key = key * (n_bins + 1) + np.clip(((clock - clock.min()) / span * n_bins).astype(np.int64), 0, n_bins)
    _, inverse = np.unique(key, return_inverse=True)
    counts = np.bincount(inverse)
    keep = counts >= MIN_BIN_SAMPLES
    when = np.bincount(inverse, weights=clock)[keep] / counts[keep]
    order = np.argsort(when, kind="stable")
    number = np.full(len(counts), -1)
    number[np.flatnonzero(keep)[order]] = np.arange(int(keep.sum()))
    index = number[inverse]
    counts = counts[keep][order]
    t_c = np.bincount(inverse, weights=t)[keep][order] / counts
    means = np.column_stack([np.bincount(inverse, weights=v[:, k])[keep][order] for k in range(v.shape[1])])
    return t_c, means / counts[:, None], counts, index


def walk_covariance(time_s, bins: np.ndarray, n_bins: int, blocks: int = 1000) -> np.ndarray:
    """Covariance of the bins' means of a unit random walk started at the first sample (Cov(w(s), w(t)) =
    min(s, t) − t₀): C[a, b] = ∫ n_a(s) n_b(s) ds / (N_a N_b), n_a(s) the samples of bin a later than s,
    summed over blocks of time (the samples within a block taken at its start)."""
    t = np.asarray(time_s, dtype=float)
    order = np.argsort(t, kind="stable")
    t, b = t[order], bins[order]
    kept = b >= 0
    t, b = t[kept], b[kept]
    n = len(t)
    blocks = max(2, min(blocks, n))
    edges = np.linspace(0, n, blocks + 1).astype(int)
    block_of = np.repeat(np.arange(blocks), np.diff(edges))
    counts = np.bincount(block_of * n_bins + b, minlength=blocks * n_bins).reshape(blocks, n_bins).astype(float)
    later = np.cumsum(counts[::-1], axis=0)[::-1]  # samples in this block or after
    start = t[edges[:-1]]
    dt = np.diff(start)  # s from one block's start to the next: the samples of blocks ≥ k are later
    C = (later[1:] * dt[:, None]).T @ later[1:]
    total = counts.sum(axis=0)
    return C / np.outer(total, total)


def _design(u: np.ndarray, order: int) -> np.ndarray:
    return np.vander(u, order + 1, increasing=True)


def _lstsq(u, y, order):
    X = _design(u, order)
    beta, *_ = np.linalg.lstsq(X, y, rcond=None)
    return X, beta


@dataclass(frozen=True)
class AxisFit:
    """One axis's polynomial in the scaled dT, u = dT / h."""

    order: int
    beta: np.ndarray  # (order + 1,) coefficients of u^k
    cov: np.ndarray  # their covariance, inflated for correlated bins
    dof: float  # effective residual degrees of freedom
    rho: float  # lag-1 autocorrelation of the (whitened) residuals (0 when negative)
    walk: float = 0.0  # the random walk's variance per second, in the readings' unit² / s (REML)


WALK_GRID = np.concatenate(([0.0], np.logspace(-4, 4, 33)))
"""Ratios λ of the walk's share to the bins' white share searched by REML (W scaled to a unit mean diagonal)."""


def walk_decomposition(walk: np.ndarray) -> tuple:
    """``(Λ, Q, scale)`` of W / scale = Q Λ Qᵀ, scale its mean diagonal: V = Q (I + λ Λ) Qᵀ, so that each λ
    is a weighted least squares in the rotated bins (one decomposition serves the three axes)."""
    scale = float(np.mean(np.diag(walk))) or 1.0
    eig, Q = np.linalg.eigh(walk / scale)
    return np.clip(eig, 0.0, None), Q, scale


def fit_axis(u: np.ndarray, y: np.ndarray, order: int, walk=None) -> AxisFit:
    """Least squares of one axis's bin means on u^0…u^order, with its honest covariance (module docstring, step 2).

    Parameters
    ----------
    u, y : ndarray (B,)
        Scaled temperature and mean reading of each bin.
    order : int
    walk : ndarray (B, B) or tuple, optional
        The bins' covariance under a unit random walk in time (:func:`walk_covariance`), or its
        :func:`walk_decomposition`. With it, the bins'
        covariance is σ² (I + λ W) and (σ², λ) are estimated by restricted maximum likelihood (Patterson and
        Thompson, Biometrika 58(3) 1971, eq. (9)); β by generalised least squares, Cov β = σ² (Xᵀ V⁻¹ X)⁻¹.

    Raises
    ------
    InsufficientDataError
        No residual degrees of freedom.
    """
    n, p = len(u), order + 1
    if n <= p + 1:
        raise InsufficientDataError(
            f"{n} temperature bins cannot fit an order-{order} polynomial with an interval: "
            "record over a wider range of temperature"
        )
    X = _design(u, order)
    lam, scale = 0.0, 1.0
    if walk is None:
        beta, *_ = np.linalg.lstsq(X, y, rcond=None)
        r = y - X @ beta
        xtvx = X.T @ X
    else:
        eig, Q, scale = walk if isinstance(walk, tuple) else walk_decomposition(walk)
        Xr, yr = Q.T @ X, Q.T @ y
        best: tuple | None = None
        for candidate in WALK_GRID:
            d = 1.0 / (1.0 + candidate * eig)
            xtvx_c = Xr.T @ (Xr * d[:, None])
            beta_c = np.linalg.solve(xtvx_c, Xr.T @ (d * yr))
            res = yr - Xr @ beta_c
            s2_c = max(float(res @ (d * res)) / (n - p), np.finfo(float).tiny)
            # REML: −2 l = (n − p) log σ̂² + log|V| + log|Xᵀ V⁻¹ X| (σ² profiled out)
            loss = (n - p) * np.log(s2_c) - float(np.sum(np.log(d))) + np.linalg.slogdet(xtvx_c)[1]
            if best is None or loss < best[0] - 1e-12:
                best = (loss, candidate, beta_c, res, d, xtvx_c)
        assert best is not None, "a grid of candidates"
        _, lam, beta, res, d, xtvx = best
        r = Q @ (np.sqrt(d) * res)  # the whitened residuals V^(−1/2) r, in temperature order
    s2 = float(r @ r) / (n - p)
    rho = 0.0
    if n > p + 2 and float(r @ r) > 0:
        rho = float(np.clip(np.sum(r[1:] * r[:-1]) / float(r @ r), 0.0, MAX_RHO))
    inflate = (1.0 + rho) / (1.0 - rho)  # Wilks, 3rd ed., eq. (5.12): n' = n (1 − ρ)/(1 + ρ)
    dof = max(n / inflate - p, 1.0)
    cov = s2 * inflate * np.linalg.inv(xtvx)
    return AxisFit(order, beta, cov, dof, rho, s2 * lam / scale)


def band_of(t_c: np.ndarray, lo: float, hi: float, n_bands: int = N_BANDS) -> np.ndarray:
    """The band (0…n_bands − 1) of temperature each bin falls in."""
    width = (hi - lo) / n_bands if hi > lo else 1.0
    return np.clip(((t_c - lo) / width).astype(int), 0, n_bands - 1)


def left_out_residuals(
    u: np.ndarray, y: np.ndarray, bands: np.ndarray, order: int, at: tuple | None = None
) -> np.ndarray:
    """Each bin's residual from the fit made without its band (order 0: a constant, the raw figure);
    NaN where the other bands hold too few bins. ``at = (u, y, bands)`` of other bins (the temperature-only
    bins of the drift figures) are predicted instead, by the same fits."""
    eu, ey, eb = at if at is not None else (u, y, bands)
    out = np.full(len(eu), np.nan)
    for k in np.unique(bands):
        train = bands != k
        if train.sum() < order + 2:
            continue
        _, beta = _lstsq(u[train], y[train], order)
        out[eb == k] = ey[eb == k] - _design(eu[eb == k], order) @ beta
    return out


def _rms(r: np.ndarray) -> float:
    r = r[np.isfinite(r)]
    return float(np.sqrt(np.mean(r**2))) if r.size else math.nan


def _ptp(r: np.ndarray) -> float:
    r = r[np.isfinite(r)]
    return float(np.ptp(r)) if r.size else math.nan


@dataclass(frozen=True)
class _SensorBins:
    """What every axis of one sensor is fitted over: the bins' temperatures scaled to [−1, 1] (``u``; ``du``
    and ``dbands`` for PX4's bins of temperature alone), the random walk's covariance of the bins, the half
    range ``h`` the scaling divides by, the curve's grid scaled alike, and how the sensor's figures read."""

    u: np.ndarray
    du: np.ndarray
    dbands: np.ndarray
    walk_cov: tuple | None
    h: float
    ug: np.ndarray
    relative: bool
    scale: float


@dataclass(frozen=True)
class _AxisDrift:
    """One axis's drift polynomial in the plain values :func:`fit_sensor` reports (coefficients of dT^k, their
    half-widths and covariance, the curve over the range) and its figures (left-out errors, drift)."""

    coefficients: list
    half: list
    cov: list
    curve_offset: list
    curve_half: list
    order: int
    dof: float
    rho: float
    walk: float
    level: float
    cv: float
    cv_raw: float
    cv_by_order: list
    drift_raw: float
    drift_after: float
    drift_cv: float


def _finite_readings(values, temperature_c, time_s):
    """The readings, temperatures and times (or None) where both reading and temperature are finite; too few
    of them is refused."""
    v = np.asarray(values, dtype=float)
    t = np.asarray(temperature_c, dtype=float)
    finite = np.all(np.isfinite(v), axis=1) & np.isfinite(t)
    v, t = v[finite], t[finite]
    times = None if time_s is None else np.asarray(time_s, dtype=float)[finite]
    if len(t) < MIN_BAND_SAMPLES:
        raise InsufficientDataError(
            f"{len(t)} readings with a temperature: a temperature calibration needs a "
            "recording of minutes to hours while the sensor warms up"
        )
    return v, t, times


def _thin_bands(bands, counts, t_min: float, t_max: float, name: str) -> tuple[list, list, list, str | None]:
    """The samples and bins of each of the :data:`N_BANDS` bands of the range, the bands with too few of
    either, and the reason naming them (None when every band is full)."""
    band_samples = [int(counts[bands == k].sum()) for k in range(N_BANDS)]
    band_bins = [int((bands == k).sum()) for k in range(N_BANDS)]
    thin = [k for k in range(N_BANDS) if band_samples[k] < MIN_BAND_SAMPLES or band_bins[k] < MIN_BAND_BINS]
    if not thin:
        return band_samples, band_bins, thin, None
    edges = np.linspace(t_min, t_max, N_BANDS + 1)
    listed = ", ".join(f"{edges[k]:.1f}–{edges[k + 1]:.1f} °C ({band_samples[k]} samples)" for k in thin)
    return (
        band_samples,
        band_bins,
        thin,
        (
            f"too few {name} samples in {listed}: each of the {N_BANDS} bands of the range needs "
            f"{MIN_BAND_SAMPLES} samples or more, in {MIN_BAND_BINS} bins or more — warm the board more "
            "slowly, or record longer at those temperatures"
        ),
    )


def _axis_drift(y: np.ndarray, dy: np.ndarray, b: _SensorBins, order: int | None) -> _AxisDrift:
    """One axis: its order chosen on bands left out (unless forced), its GLS fit on the bins (:func:`fit_axis`),
    the coefficients scaled back to dT^k, the curve with its interval, and the figures."""
    # The order on PX4's bins of temperature alone: each part of the range weighs the same in the
    # fits of the other bands (bins cut in time would weigh the final temperature the most).
    by_order = {q: _rms(left_out_residuals(b.du, dy, b.dbands, q)) for q in range(MAX_ORDER + 1)}
    chosen = order or min(range(1, MAX_ORDER + 1), key=lambda q: (by_order[q], q))
    fit = fit_axis(b.u, y, chosen, b.walk_cov)
    held = left_out_residuals(b.du, dy, b.dbands, chosen)
    level = fit.beta[0] if b.relative else 0.0  # the accelerometer: drift relative to T_ref
    q = _t_quantile(fit.dof)
    beta = np.zeros(MAX_ORDER + 1)
    beta[: chosen + 1] = fit.beta
    beta[0] -= level
    hw = np.zeros(MAX_ORDER + 1)
    hw[: chosen + 1] = q * np.sqrt(np.diag(fit.cov))
    if b.relative:
        hw[0] = 0.0
    powers = b.h ** np.arange(MAX_ORDER + 1)
    cov = np.zeros((MAX_ORDER + 1, MAX_ORDER + 1))
    cov[: chosen + 1, : chosen + 1] = fit.cov
    if b.relative:
        cov[0, :] = cov[:, 0] = 0.0
    G = _design(b.ug, MAX_ORDER)
    if b.relative:
        G = G.copy()
        G[:, 0] = 0.0
    return _AxisDrift(
        coefficients=(beta / powers).tolist(),  # X_k of dT^k, from the scaled b_k of u^k
        half=(hw / powers).tolist(),
        cov=(cov / np.outer(powers, powers)).tolist(),
        curve_offset=(G @ beta).tolist(),
        curve_half=(q * np.sqrt(np.einsum("ij,jk,ik->i", G, cov, G))).tolist(),
        order=chosen,
        dof=fit.dof,
        rho=fit.rho,
        walk=math.sqrt(fit.walk),
        level=level,
        cv=by_order[chosen] * b.scale,
        cv_raw=by_order[0] * b.scale,
        cv_by_order=[by_order[k] * b.scale for k in range(1, MAX_ORDER + 1)],
        drift_raw=_ptp(dy) * b.scale,
        drift_after=_ptp(dy - _design(b.du, chosen) @ fit.beta) * b.scale,
        drift_cv=_ptp(held) * b.scale,
    )


def fit_sensor(values, temperature_c, sensor: str, *, order: int | None = None, time_s=None) -> tuple[dict, list[str]]:
    """The temperature model of one sensor (``acc`` in m/s², ``gyr`` in rad/s) and the reasons it fails.

    Parameters
    ----------
    values : array_like, shape (N, 3)
        Still readings in the sensor's SI unit.
    temperature_c : array_like, shape (N,)
        The sensor's temperature at each reading.
    sensor : {"acc", "gyr"}
    order : int, optional
        Force the polynomial's order (1–3) instead of choosing it on bands left out (the benchmark's
        coverage of a known order).
    time_s : array_like, shape (N,), optional
        Each reading's time: with it, a random walk of the bias in time is estimated beside the bins' white
        scatter (:func:`fit_axis`), since over a warm-up a bias wandering in time looks like drift.

    Returns
    -------
    part : dict
        ``model``, ``uncertainty``, ``metrics``, ``bins``, ``curve`` (plain values).
    reasons : list of str
        Failed gates (span, samples per band, a fit worse than raw on left-out bands).
    """
    v, t, times = _finite_readings(values, temperature_c, time_s)
    name = SENSOR_WORDS[sensor]
    t_min, t_max = float(t.min()), float(t.max())
    span = t_max - t_min
    t_ref = 0.5 * (t_min + t_max)  # PX4's process_sensor_caldata.py: TREF = (TMIN + TMAX) / 2
    h = max(span / 2.0, 1e-9)
    reasons: list[str] = []
    if span < MIN_SPAN_C:
        reasons.append(
            f"the {name}'s temperature spans {span:.1f} °C ({t_min:.1f}–{t_max:.1f} °C), under the "
            f"{MIN_SPAN_C:g} °C a temperature calibration needs: start from a cold board (cooled for half "
            "an hour) and record while it warms up"
        )
    t_c, means, counts, index = bin_by_temperature(v, t, times)
    # The bins cut in time (for the random walk) can be many at one temperature; a polynomial of temperature
    # needs distinct temperatures: as many bins of temperature alone as a cubic has coefficients, and two more.
    dt_c, dmeans, dcounts, _ = bin_by_temperature(v, t)
    if len(dt_c) < MAX_ORDER + 3:
        raise InsufficientDataError(
            f"the {name}'s readings fill only {len(dt_c)} bins of temperature ({t_min:.1f}–{t_max:.1f} °C): a "
            f"temperature calibration needs the sensor to warm through {MIN_SPAN_C:g} °C or more — start from a "
            "cold board (cooled for half an hour) and record while it warms up, still all the while"
        )
    walk_cov = None if times is None else walk_decomposition(walk_covariance(times, index, len(t_c)))
    band_samples, band_bins, thin, thin_reason = _thin_bands(band_of(t_c, t_min, t_max), counts, t_min, t_max, name)
    if thin_reason:
        reasons.append(thin_reason)
    grid = np.linspace(t_min, t_max, CURVE_POINTS)
    # The drift figures on PX4's bins, of temperature alone (dt_c above): the same bins however long the recording.
    bins = _SensorBins(
        u=(t_c - t_ref) / h,
        du=(dt_c - t_ref) / h,
        dbands=band_of(dt_c, t_min, t_max),
        walk_cov=walk_cov,
        h=h,
        ug=(grid - t_ref) / h,
        relative=sensor == "acc",
        scale=FIGURE_SCALE[sensor],
    )
    axes = [_axis_drift(means[:, axis], dmeans[:, axis], bins, order) for axis in range(v.shape[1])]
    cv, cv_raw = [a.cv for a in axes], [a.cv_raw for a in axes]
    drift_raw, drift_cv = [a.drift_raw for a in axes], [a.drift_cv for a in axes]
    unit = FIGURE_UNITS[sensor]
    worse = float(np.sqrt(np.mean(np.square(cv)))) >= float(np.sqrt(np.mean(np.square(cv_raw))))
    if worse and not thin:
        reasons.append(
            f"the {name}'s polynomial predicts the bands left out no better than no correction at all "
            f"(RMS {np.sqrt(np.mean(np.square(cv))):.3g} {unit} against {np.sqrt(np.mean(np.square(cv_raw))):.3g} "
            f"{unit} raw): its offset does not follow the temperature here — leave its temperature "
            "calibration off"
        )
    offsets = dmeans - np.asarray([a.level for a in axes])
    part = {
        "model": {
            "unit": SI_UNITS[sensor],
            "t_ref_c": t_ref,
            "t_min_c": t_min,
            "t_max_c": t_max,
            "relative": bins.relative,
            "order": [a.order for a in axes],
            "coefficients": [a.coefficients for a in axes],
        },
        "uncertainty": {
            "coefficients": [a.half for a in axes],
            "dof": [a.dof for a in axes],
            "autocorrelation": [a.rho for a in axes],
            "covariance": [a.cov for a in axes],
            "random_walk": [a.walk for a in axes],
        },
        "metrics": {
            "unit": unit,
            "span_c": span,
            "drift_raw": drift_raw,
            "drift_after": [a.drift_after for a in axes],
            "drift_cv": drift_cv,
            "cv_error": cv,
            "cv_error_raw": cv_raw,
            "cv_error_by_order": [a.cv_by_order for a in axes],
            "drift_raw_max": max(drift_raw),
            "drift_cv_max": max(drift_cv),
            "n_samples": int(len(t)),
            "n_bins": int(len(t_c)),
            "samples_per_band": band_samples,
            "bins_per_band": band_bins,
        },
        "bins": {"t_c": dt_c.tolist(), "offset": offsets.tolist(), "count": dcounts.tolist()},
        "curve": {
            "t_c": grid.tolist(),
            "offset": np.array([a.curve_offset for a in axes]).T.tolist(),
            "half_width": np.array([a.curve_half for a in axes]).T.tolist(),
        },
    }
    return part, reasons


def shift_polynomial(coefficients, from_c: float, to_c: float) -> np.ndarray:
    """Coefficients of the same polynomials written about ``to_c`` instead of ``from_c``.

    Parameters
    ----------
    coefficients : array_like, shape (axes, order + 1)
        Increasing powers of (T − from_c).
    from_c, to_c : float

    Returns
    -------
    numpy.ndarray
        Increasing powers of (T − to_c), by the binomial expansion of ((T − to_c) + d)^k, d = to_c − from_c.
    """
    c = np.atleast_2d(np.asarray(coefficients, dtype=float))
    d = to_c - from_c
    out = np.zeros_like(c)
    # (x + d)^k = Σ_j C(k, j) d^(k − j) x^j with x = T − to_c
    for k in range(c.shape[1]):
        for j in range(k + 1):
            out[:, j] += c[:, k] * comb(k, j) * d ** (k - j)
    return out


def offset_at(model: dict, temperature_c) -> np.ndarray:
    """The offset o(T) a sensor's model gives (PX4's form: dT = clamp(T, T_min, T_max) − T_ref), shape (N, 3)."""
    t = np.clip(np.asarray(temperature_c, dtype=float), model["t_min_c"], model["t_max_c"]) - model["t_ref_c"]
    c = np.asarray(model["coefficients"], dtype=float)  # (3, 4): X0…X3 per axis
    return _design(np.atleast_1d(t), MAX_ORDER) @ c.T


def movement(sensors: list, sampling_rate_hz: float) -> tuple[np.ndarray, str | None]:
    """The samples inside a rest of every sensor (a boolean mask) and, when the device moved (its longest
    rest, by any sensor, under :data:`STILL_FRACTION` of the recording), what was seen."""
    from .noise.still_part import still_runs

    n = len(sensors[0])
    mask = np.ones(n, dtype=bool)
    worst = None
    for samples in sensors:
        runs = still_runs(samples, sampling_rate_hz)
        inside = np.zeros(n, dtype=bool)
        for a, b in runs:
            if b - a >= MIN_REST_S * sampling_rate_hz:  # a turn at a steady rate is a short "rest" of its own
                inside[a:b] = True
        mask &= inside
        longest = max((b - a for a, b in runs), default=0)
        if longest < STILL_FRACTION * n and (worst is None or longest < worst[0]):
            worst = (longest, len(runs))
    if worst is None:
        return mask, None
    return mask, (
        f"the device moved: its longest rest is {worst[0] / sampling_rate_hz:.0f} s of "
        f"{n / sampling_rate_hz:.0f} s ({worst[1]} rests)"
    )


@dataclass(frozen=True)
class TemperatureResult(PerSensorResult):
    """Per-sensor offset polynomials of temperature (``acc``, ``gyr``), PX4's form.

    Corrects with the temperature of each reading (:meth:`correct`); it holds no affine correction,
    so the affine exporters refuse it and its own (PX4 ``.params``, ArduPilot ``.parm``) write it.
    """

    RESULT_TYPE: ClassVar[str] = "temperature"
    MODEL_TYPE: ClassVar[str] = "temperature"
    KIND: ClassVar[str] = DRIFT

    method: str = "temperature"

    @property
    def correction(self):
        raise CalibrationError(
            "a temperature calibration has no fixed correction: its offset depends on the temperature of each reading"
        )

    @property
    def output_unit(self) -> str:
        return self.unit

    @classmethod
    def figures_from(cls, metrics: dict, output_unit: str | None) -> tuple[Figure, ...]:
        """Per sensor (the accelerometer's in mg first, then the gyroscope's in °/s): its offset drift over
        the range raw, against bands of temperature left out (each predicted by the fit made without it);
        none without a temperature model."""
        return tuple(
            Figure(
                metrics[s]["drift_raw_max"],
                metrics[s]["drift_cv_max"],
                FIGURE_WORDS[metrics[s]["unit"]],
                "offset drift over the temperature range, on bands of temperature left out",
            )
            for s in TEMPERATURE_SENSORS
            if s in metrics
        )

    def apply(self, samples, sensor: str | None = None):
        raise CalibrationError(
            "a temperature calibration needs each sample's temperature: export it for the "
            "firmware (px4, ardupilot), or correct readings with their temperatures"
        )

    def correct(self, sensor: str, readings, temperature_c) -> np.ndarray:
        """Readings (SI) less their offset at their temperatures: m − o(clamp(T)).

        Raises
        ------
        CalibrationError
            A sensor the calibration has no model of.
        """
        if sensor not in self.sensors:
            raise CalibrationError(
                f"this temperature calibration has no {sensor} model (it has {', '.join(self.sensors)})"
            )
        return np.asarray(readings, dtype=float) - offset_at(self.sensors[sensor]["model"], temperature_c)

    def body_dict(self) -> dict:
        return {
            "bins": {n: p["bins"] for n, p in self.sensors.items()},
            "curve": {n: p["curve"] for n, p in self.sensors.items()},
        }

    @classmethod
    def _from_body(cls, data: dict) -> TemperatureResult:
        return cls(
            sensors=cls.parts_from(data, "bins", "curve"),
            warnings=tuple(data.get("warnings", ())),
            reasons=tuple(data.get("reasons", ())),
            unit=data.get("unit", ""),
        )


def calibrate_temperature(
    temperature_c, *, acc=None, gyr=None, sampling_rate_hz: float = 100.0, time_s=None, order: int | None = None
) -> TemperatureResult:
    """Temperature calibration of the accelerometer and/or gyroscope of a still recording.

    Parameters
    ----------
    temperature_c : array_like, shape (N,)
        The sensor's temperature at each sample, °C.
    acc : array_like, shape (N, 3), optional
        Accelerometer, m/s².
    gyr : array_like, shape (N, 3), optional
        Gyroscope, rad/s.
    sampling_rate_hz : float
        For finding the rests (:func:`app.calibration.noise.still_part.still_runs`).
    time_s : array_like, shape (N,), optional
        Each sample's time (default: sample index / rate), for the bias's random walk in time.
    order : int, optional
        Force the order (1–3) instead of choosing it on bands left out.

    Returns
    -------
    TemperatureResult
        ``ok`` false with reasons on a failed gate (span, samples per band, worse than raw, a move).

    Raises
    ------
    CalibrationError
        No sensor, shapes that disagree, temperatures that are not finite.
    """
    t = np.asarray(temperature_c, dtype=float).reshape(-1)
    given = {k: np.asarray(v, dtype=float) for k, v in (("acc", acc), ("gyr", gyr)) if v is not None}
    if not given:
        raise CalibrationError("a temperature calibration needs accelerometer or gyroscope readings")
    for k, v in given.items():
        if v.ndim != 2 or v.shape[1] != 3 or len(v) != len(t):
            raise CalibrationError(
                f"the {SENSOR_WORDS[k]}'s readings and the temperatures do not line up: give "
                "one temperature per reading"
            )
    if not np.any(np.isfinite(t)):
        raise CalibrationError("the temperature column holds no number: give the sensor's temperature in °C")
    times = np.arange(len(t)) / sampling_rate_hz if time_s is None else np.asarray(time_s, dtype=float).reshape(-1)
    if len(times) != len(t):
        raise CalibrationError("the times and the temperatures do not line up: give one time per sample")
    still, moved = movement(list(given.values()), sampling_rate_hz)
    reasons: list[str] = []
    warnings: list[str] = []
    sensors = {}
    for name, values in given.items():
        use: slice | np.ndarray = slice(None)
        if moved is not None:
            if name == "acc":
                reasons.append(
                    moved + ": the accelerometer's reading then changes with its pose (gravity's "
                    "projection), which a fit would take for drift — record it resting in one "
                    "pose, untouched, as it warms up"
                )
            else:
                use = still
                warnings.append(moved + f": the gyroscope was fitted on its {int(still.sum())} still samples only")
        part, why = fit_sensor(values[use], t[use], name, order=order, time_s=times[use])
        sensors[name] = part
        reasons += why
    return TemperatureResult(
        sensors=sensors,
        warnings=tuple(reasons + warnings),
        reasons=tuple(reasons),
        unit=", ".join(SI_UNITS[k] for k in sensors),
    )
