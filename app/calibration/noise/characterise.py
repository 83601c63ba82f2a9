"""Noise characterisation of a still sensor by the Allan deviation: white noise, bias instability,
random walk — what navigation filters (Kalibr, OpenVINS, VINS-Fusion) take as the random errors.

The Allan variance of a sum of independent noise terms is the sum of their Allan variances (IEEE
Std 952-1997, Annex C, Table C.1; IEEE Std 1554-2005; El-Sheimy, Hou and Niu, IEEE Trans. Instrum.
Meas. 57(1) 2008, eqs. (10), (12), (14))::

    σ²(τ) = N² / τ  +  (2 ln 2 / π) B²  +  K² τ / 3

- N, the white-noise (angle / velocity random walk) coefficient: the −½ line σ = N / √τ, read at
  τ = 1 s. Unit: [u]/√Hz (= [u]·√s), Kalibr's ``*_noise_density``.
- B, the bias instability: the flat floor σ = √(2 ln 2 / π) B ≈ 0.664 B. Unit: [u].
- K, the rate (acceleration) random walk: the +½ line σ = K √(τ / 3), read at τ = 3 s.
  Unit: [u]/s/√Hz (= [u]/√s), Kalibr's ``*_random_walk``.

[u] is the sensor's unit (rad/s, m/s², µT). How a term is read: the three-term model is fitted to
the Allan variance by weighted non-negative least squares (each point weighted by its equivalent
degrees of freedom), which says at each τ which term dominates; each term is then read on its own
line at the single τ where its reading is most precise — the χ² interval of σ²(τ) at its
equivalent degrees of freedom (Howe, Allan and Barnes 1981; NIST SP 1065, Table 5 and eq. (45))
divided by the term's share of σ²(τ) — with the other two terms' fitted parts subtracted. The
interval of the term is that χ² interval, mapped the same way. A term whose share never reaches
:data:`SHARE_MIN` is not seen: its value is None, with a warning saying how long to record.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..shared.errors import CalibrationError, InsufficientDataError
from ..shared.headlines import SENSOR_WORDS
from ..shared.plausible import PhysicalFigure
from ..shared.result import FIGURES, PerSensorResult
from .allan import FLICKER, RANDOM_WALK, WHITE, chi2_interval, edf_simple, overlapping_adev

CONFIDENCE = 0.95
FLICKER_VARIANCE = 2.0 * math.log(2.0) / math.pi
"""σ²(τ) of bias instability B is (2 ln 2 / π) B² on its floor: σ = 0.664 B (IEEE Std 952-1997, C.2)."""

FIT_MIN_M = 10
"""τ below 10 sample periods are shown but not fitted: a sensor's digital low-pass filter bends the
curve below the white-noise line there."""

SHARE_MIN = 0.5
"""A term is seen where it is at least half of the Allan variance at some fitted τ."""

RECORD_FACTOR = 10.0
"""A term that would show from τ needs a recording of about 10 τ to be read with a few degrees of
freedom (the overlapping estimator reaches τ = T / 2, with one or two)."""

TERMS = ("noise_density", "bias_instability", "random_walk")
TERM_WORDS = {
    "noise_density": "noise density",
    "random_walk": "random walk",
    "bias_instability": "bias instability",
    "bias": "bias",
}
"""Each figure of a sensor's noise in words, in the order the page's table and the plot's captions name them."""

FILTER_SENSORS = ("acc", "gyr")
FILTER_TERMS = ("noise_density", "random_walk")
"""What a navigation filter's noise model takes (Kalibr's imu.yaml, OpenVINS, VINS-Fusion): each of these sensors'
white noise and random walk, one figure a sensor (app/io/exports/noise.py)."""


@dataclass(frozen=True)
class FilterGap:
    """A figure a filter needs that a noise characterisation lacks: the sensor's, or one term of it (``term`` None:
    the sensor was not recorded); ``record_s``, how long a still recording would show it, where one would."""

    sensor: str
    term: str | None = None
    record_s: float | None = None


_ALPHAS = (WHITE, FLICKER, RANDOM_WALK)

TERM_UNITS = {
    "rad/s": ("rad/s/√Hz", "rad/s²/√Hz"),
    "m/s^2": ("m/s²/√Hz", "m/s³/√Hz"),
    "uT": ("uT/√Hz", "uT/s/√Hz"),
    "raw": ("counts/√Hz", "counts/s/√Hz"),
}


def term_units(unit: str) -> dict:
    """The units of N, K and B for a sensor in ``unit`` (Kalibr's continuous-time units); readings of
    unknown scale (``raw``) are counts."""
    n, k = TERM_UNITS.get(unit, (f"{unit}/√Hz", f"{unit}/s/√Hz"))
    return {
        "noise_density_unit": n,
        "random_walk_unit": k,
        "bias_instability_unit": "counts" if unit == "raw" else unit,
    }


def _basis(tau: np.ndarray, f0: float | None = None) -> np.ndarray:
    """Columns of the three-term model in (N², B², K²): 1/τ, 2 ln 2/π, τ/3 (IEEE Std 952, Table C.1); with a
    frequency ``f0``, a fourth for a periodic disturbance there, (sin² πf₀τ / πf₀τ)² (the Allan variance of a
    sinusoid of amplitude Ω is Ω² times it: IEEE Std 952-1997, C.1.1)."""
    columns = [1.0 / tau, np.full_like(tau, FLICKER_VARIANCE), tau / 3.0]
    if f0 is None:
        return np.column_stack(columns)
    x = np.pi * f0 * tau
    return np.column_stack([*columns, (np.sin(x) ** 2 / x) ** 2])


def _nnls(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """min ‖a θ − b‖ over θ ≥ 0 for a few columns: the least squares of every subset of the columns,
    the best one whose solution is non-negative (exact; 7 subsets for the three terms, and no 0.4 s
    import of scipy.optimize)."""
    k = a.shape[1]
    best, best_cost = np.zeros(k), float(b @ b)
    for mask in range(1, 1 << k):
        cols = [j for j in range(k) if mask >> j & 1]
        sol, *_ = np.linalg.lstsq(a[:, cols], b, rcond=None)
        if np.any(sol < 0):
            continue
        theta = np.zeros(k)
        theta[cols] = sol
        r = a @ theta - b
        if (cost := float(r @ r)) < best_cost:
            best, best_cost = theta, cost
    return best


def _fit_terms(tau, avar, n_phase, ms, f0: float | None = None) -> tuple[np.ndarray, float]:
    """(N², B², K²) — and the amplitude² of a periodic disturbance at ``f0`` — by non-negative least squares on
    the relative residuals, each point weighted by its equivalent degrees of freedom (var σ̂² ≈ 2 σ⁴ / edf), the
    dominant term choosing the edf; and the weighted residual's sum of squares."""
    a = _basis(tau, f0)
    scale = avar * np.sqrt(2.0 / edf_simple(n_phase, ms, WHITE))
    theta = np.zeros(a.shape[1])
    for _ in range(3):
        theta = _nnls(a / scale[:, None], avar / scale)
        model = a @ theta
        if not np.all(model > 0):
            break
        scale = model * np.sqrt(2.0 / edf_simple(n_phase, ms, _dominant(a, theta)))
    return theta, float(np.sum(((a @ theta - avar) / scale) ** 2))


def _periodic_fit(tau, avar, n_phase, ms, peak_tau: float) -> tuple[np.ndarray, float]:
    """The terms with a periodic disturbance whose hump peaks at ``peak_tau``: its frequency the one, within
    a factor of two of 0.371 / τ (:data:`HUMP_TAU_F0`), whose sinusoid's curve leaves the least residual."""
    fits = [(*_fit_terms(tau, avar, n_phase, ms, f0), f0) for f0 in HUMP_TAU_F0 / peak_tau * np.geomspace(0.5, 2.0, 41)]
    theta, _, f0 = min(fits, key=lambda f: f[1])
    return theta, float(f0)


def _dominant(a: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """The power-law exponent α of the largest term at each τ (a periodic disturbance's counted as white)."""
    return np.asarray((*_ALPHAS, WHITE)[: a.shape[1]])[np.argmax(a * theta, axis=1)]


@dataclass(frozen=True)
class AxisNoise:
    """One axis's terms: values (None where not seen), intervals, the τ each was read at, the fit."""

    values: dict
    intervals: dict
    taus: dict
    theta: np.ndarray
    edf: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    hump: tuple[float, float, float] | None = None
    """A periodic disturbance's hump: the τ of its peak, how far above the white-noise line (in σ), and the
    disturbance's fitted frequency."""


HUMP_FACTOR = 1.3
"""σ²(τ)·τ, flat on the white-noise line and rising with the bias instability and the random walk, never falls
with τ for the three terms; where it falls by more than this factor beyond both points' intervals
(:data:`HUMP_CONFIDENCE`), a
periodic disturbance's hump lies above the white-noise line (the Allan variance of a sinusoid of frequency f₀,
Ω²(sin² πf₀τ / πf₀τ)², peaks at τ ≈ 0.371/f₀ and falls as τ⁻² after it: IEEE Std 952-1997, C.1.1)."""
HUMP_CONFIDENCE = 0.999
"""The hump stands above the line beyond both points' intervals at this confidence: a white-noise curve's
highest short-τ point and lowest longer-τ point are the extremes of some twenty, so 95 % would name a hump in
one clean recording of a hundred."""
HUMP_TAU_F0 = 0.371
"""τ·f₀ at the peak of a sinusoid's Allan deviation (IEEE Std 952-1997, C.1.1)."""


def _past_hump(tau, avar, ms, n_phase, fit) -> tuple[float, float] | None:
    """Where a periodic disturbance's hump stands above the white-noise line (:data:`HUMP_FACTOR`): the τ of its
    peak and how far above the line it stands (in σ); else None."""
    idx = np.flatnonzero(fit)
    if len(idx) < 4:
        return None
    w = avar[idx] * tau[idx]
    lo, hi = chi2_interval(edf_simple(n_phase, ms[idx], WHITE), HUMP_CONFIDENCE)
    q = int(np.argmin(w * hi))  # the white-noise line's surest low point: the terms rise from it to longer τ
    if q == 0:
        return None
    p = int(np.argmax(w[:q] * lo[:q]))
    if w[p] * lo[p] <= HUMP_FACTOR * w[q] * hi[q] or len(idx) - q < 3:
        return None
    return float(tau[idx[p]]), math.sqrt(w[p] / w[q])


def _read_axis(tau, avar, ms, n_phase) -> AxisNoise:
    fit = ms >= FIT_MIN_M
    if fit.sum() < 3:
        fit = np.ones_like(ms, dtype=bool)
    found = _past_hump(tau, avar, ms, n_phase, fit)
    f0, hump = None, None
    if found is None:
        theta = _fit_terms(tau[fit], avar[fit], n_phase, ms[fit])[0]
    else:  # the disturbance fitted as a term of its own, so that each term is read where it stands alone
        theta, f0 = _periodic_fit(tau[fit], avar[fit], n_phase, ms[fit], found[0])
        hump = (*found, f0)
    a = _basis(tau, f0)
    parts = a * theta
    edf = edf_simple(n_phase, ms, _dominant(a, theta))
    total = parts.sum(axis=1)
    best = {}
    for j in range(len(TERMS)):
        share = np.where(total > 0, parts[:, j] / np.where(total > 0, total, 1.0), 0.0)
        share[~fit] = 0.0
        if theta[j] > 0 and share.max() >= SHARE_MIN:
            with np.errstate(divide="ignore"):
                score = np.where(share >= SHARE_MIN, np.sqrt(2.0 / edf) / share, np.inf)
            i = int(np.argmin(score))
            best[j] = (i, float(score[i]))  # the τ it is read at, and its relative standard error there
    # The other terms' fitted parts are subtracted with their own errors (each read where it is most
    # precise): their variances add to σ̂²'s, giving the effective degrees of freedom (Satterthwaite's
    # approximation) of each term's χ² interval.
    edf_terms = []
    for j, (i, _) in best.items():
        var = 2.0 * avar[i] ** 2 / edf[i] + sum((parts[i, o] * best[o][1]) ** 2 for o in best if o != j)
        edf_terms.append(max(2.0 * avar[i] ** 2 / var, 1.0) if var > 0 else edf[i])
    # Every τ's interval and every term's in one call: the quantiles' iterations run once for them all.
    lo_all, hi_all = chi2_interval(np.concatenate([edf, edf_terms]), CONFIDENCE)
    lo_f, hi_f = lo_all[: len(edf)], hi_all[: len(edf)]
    term_factors = dict(zip(best, zip(lo_all[len(edf) :], hi_all[len(edf) :])))
    values: dict[str, float | None] = {}
    intervals: dict[str, list[float] | None] = {}
    taus: dict[str, float | None] = {}
    for j, name in enumerate(TERMS):
        if j not in best:
            values[name] = intervals[name] = taus[name] = None
            continue
        i = best[j][0]
        others = total[i] - parts[i, j]
        lo_i, hi_i = term_factors[j]
        read = [(avar[i] * f - others) / a[i, j] for f in (1.0, float(lo_i), float(hi_i))]
        values[name] = math.sqrt(max(read[0], 0.0))
        intervals[name] = [math.sqrt(max(read[1], 0.0)), math.sqrt(max(read[2], 0.0))]
        taus[name] = float(tau[i])
    return AxisNoise(values, intervals, taus, theta[:3], edf, lo_f, hi_f, hump)


def _random_walk_bound(readings: list[AxisNoise], tau, avar_hi) -> tuple[float, float]:
    """An unseen random walk: the largest K² the Allan variance's upper bounds allow, and the τ from which a
    random walk that large would rise above the white noise and the floor (IEEE Std 952, Annex C: σ² = N²/τ
    + 2 ln2 B²/π + K² τ/3)."""
    n2 = max(r.theta[0] for r in readings)
    k2 = float(np.max(np.min(3.0 * avar_hi / tau[:, None], axis=0)))  # the curve's upper end bounds K at every τ
    b2 = max(r.theta[1] for r in readings)
    need = (FLICKER_VARIANCE * b2 + math.sqrt((FLICKER_VARIANCE * b2) ** 2 + 4.0 * k2 * n2 / 3.0)) / (2.0 * k2 / 3.0)
    return k2, need


def record_for_s(name: str, readings: list[AxisNoise], tau, avar_hi) -> float | None:
    """How long a still recording would show a term it did not (seconds), or None where a longer one would not
    (a floor hidden by a random walk, a white noise that no τ shows)."""
    tau_max = float(tau[-1])
    if name == "random_walk":
        _, need = _random_walk_bound(readings, tau, avar_hi)
    elif name == "bias_instability" and not any(r.values["random_walk"] is not None for r in readings):
        b2 = float(np.min(avar_hi)) / FLICKER_VARIANCE
        need = max(r.theta[0] for r in readings) / (FLICKER_VARIANCE * b2) if b2 > 0 else math.inf
    else:
        return None
    seconds = max(RECORD_FACTOR * need, 4.0 * tau_max)
    return seconds if math.isfinite(seconds) else None


def _unseen_warning(name: str, axes: list[str], readings: list[AxisNoise], tau, avar_hi, sensor: str, unit: str) -> str:
    """Why a term is null on some axes, and how long a recording would show it."""
    tau_max = float(tau[-1])
    which = f"{sensor} {'/'.join(axes)}"
    n2 = max(r.theta[0] for r in readings)
    if name == "random_walk":
        k2, need = _random_walk_bound(readings, tau, avar_hi)
        return (
            f"{which}: random_walk is null — the Allan deviation does not turn up to τ = {tau_max:.3g} s "
            f"(the longest this still recording supports); a random walk of at most {math.sqrt(k2):.3g} "
            f"{term_units(unit)['random_walk_unit']} would show from τ ≈ {need:.3g} s: record the device still for "
            f"at least {duration_words(max(RECORD_FACTOR * need, 4.0 * tau_max))}"
        )
    if name == "bias_instability":
        b2 = float(np.min(avar_hi)) / FLICKER_VARIANCE
        if any(r.values["random_walk"] is not None for r in readings):
            return (
                f"{which}: bias_instability is null — the floor is hidden where white noise gives way to the "
                f"random walk (B ≤ {math.sqrt(b2):.3g} {unit}); a longer recording does not reveal it"
            )
        need = n2 / (FLICKER_VARIANCE * b2) if b2 > 0 else math.inf
        return (
            f"{which}: bias_instability is null — the Allan deviation still falls as white noise at "
            f"τ = {tau_max:.3g} s; a floor of B ≤ {math.sqrt(b2):.3g} {unit} would show from τ ≈ {need:.3g} s: "
            f"record the device still for at least {duration_words(max(RECORD_FACTOR * need, 4.0 * tau_max))}"
        )
    return (
        f"{which}: noise_density is null — white noise dominates no τ from {FIT_MIN_M} samples on: sample "
        "faster, or check that the samples are not filtered or rounded to a few steps"
    )


def duration_words(seconds: float) -> str:
    """A length of time as a person reads it: ``0.5 s``, ``40 s``, ``12 min``, ``3.5 h``."""
    if not math.isfinite(seconds):
        return "much longer"
    if seconds < 10:
        return f"{seconds:.2g} s"
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def characterise_noise(samples, sampling_rate_hz: float, *, unit: str, sensor: str = "gyr") -> dict:
    """The noise terms of one still three-axis sensor from its overlapping Allan deviation.

    Parameters
    ----------
    samples : array_like, shape (N, 3)
        Still samples in ``unit``; may be a memory map (read one column at a time).
    sampling_rate_hz : float
        Positive.
    unit : str
        The samples' unit (``rad/s``, ``m/s^2``, ``uT``...): the terms' units follow from it.
    sensor : str
        Its name, for the warnings.

    Returns
    -------
    dict
        Plain parts ``model`` (unit, bias, noise_density, random_walk, bias_instability and their
        units; None entries where a term is not seen), ``adev`` (tau_s, value, lo, hi, edf, n_terms),
        ``uncertainty`` (``[lo, hi]`` per axis and term, 95 %), ``metrics`` (the τ each term was
        read at, the curve's minimum) and ``warnings``.

    Raises
    ------
    InsufficientDataError
        Fewer samples than an Allan deviation needs.
    CalibrationError
        Not N×3, or non-finite samples.
    """
    if getattr(samples, "ndim", 0) != 2 or samples.shape[1] != 3:
        raise CalibrationError(f"{sensor}: expected N×3 samples, got shape {getattr(samples, 'shape', None)}")
    tau, adev, n_terms, mean = overlapping_adev(samples, sampling_rate_hz)
    n = samples.shape[0]
    ms = np.round(tau * sampling_rate_hz).astype(np.int64)
    avar = adev**2
    flat = [axis for k, axis in enumerate("xyz") if not np.all(avar[:, k] > 0)]
    if flat:  # a sensor printing one value (absent, or quantised coarser than its noise) has no noise to read
        raise InsufficientDataError(
            f"the {SENSOR_WORDS.get(sensor, sensor)}'s {', '.join(flat)} axis readings do not change over the "
            "recording, so they hold no noise to characterise (a sensor that is absent and prints a constant, or one "
            "quantised coarser than its noise): leave this sensor out, or log it at a finer resolution"
        )
    readings = [_read_axis(tau, avar[:, k], ms, n + 1) for k in range(3)]
    lo = np.column_stack([adev[:, k] * np.sqrt(r.lo) for k, r in enumerate(readings)])
    hi = np.column_stack([adev[:, k] * np.sqrt(r.hi) for k, r in enumerate(readings)])
    duration = n / sampling_rate_hz
    # The bias: the mean of the still part; its standard error is the fitted model's Allan deviation
    # extrapolated to the whole duration (σ/√n for white noise alone).
    se = np.array([math.sqrt(max(float(_basis(np.array([duration]))[0] @ r.theta), 0.0)) for r in readings])
    z = 1.959963984540054
    model = {
        "unit": unit,
        "bias": mean.tolist(),
        **{name: [r.values[name] for r in readings] for name in TERMS},
        **term_units(unit),
    }
    uncertainty = {name: [r.intervals[name] for r in readings] for name in TERMS}
    uncertainty["bias"] = [[float(m - z * s), float(m + z * s)] for m, s in zip(mean, se)]
    warnings = []
    record_for = {}
    for name in ("noise_density", "random_walk", "bias_instability"):
        axes = [ax for ax, r in zip("xyz", readings) if r.values[name] is None]
        if axes:
            warnings.append(_unseen_warning(name, axes, readings, tau, hi**2, sensor, unit))
            if (seconds := record_for_s(name, readings, tau, hi**2)) is not None:
                record_for[name] = seconds
    humps = [(axis, r.hump) for axis, r in zip("xyz", readings) if r.hump is not None]
    if humps:
        f0 = [h[2] for _, h in humps]
        near = f"{min(f0):.2g} Hz" if max(f0) < 1.2 * min(f0) else f"{min(f0):.2g}–{max(f0):.2g} Hz"
        warnings.append(
            f"{sensor} {'/'.join(a for a, _ in humps)}: a hump in the Allan deviation at τ ≈ "
            f"{max(h[0] for _, h in humps):.2g} s stands {max(h[1] for _, h in humps):.2g}× above the white-noise "
            f"line — a periodic disturbance near {near} (a fan, a motor, a pump, a vibrating table or a frame still "
            "ringing; mains hum aliased by the sampling), not the sensor's noise: fitted as a term of its own, so that "
            "the noise density is read on the white-noise line; record away from what vibrates for the sensor's own "
            "curve"
        )
    imin = np.argmin(adev, axis=0)
    metrics = {
        "hump_tau_s": [None if r.hump is None else r.hump[0] for r in readings],
        "hump_hz": [None if r.hump is None else r.hump[2] for r in readings],
        **{f"tau_{name}_s": [r.taus[name] for r in readings] for name in TERMS},
        "adev_min": [float(adev[imin[k], k]) for k in range(3)],
        "tau_adev_min_s": [float(tau[imin[k]]) for k in range(3)],
        "bias_standard_error": se.tolist(),
        "record_for_s": record_for,
    }
    adev_plain = {
        "tau_s": tau.tolist(),
        "value": adev.tolist(),
        "lo": lo.tolist(),
        "hi": hi.tolist(),
        "edf": np.column_stack([r.edf for r in readings]).tolist(),
        "n_terms": n_terms.tolist(),
    }
    return {
        "model": model,
        "adev": adev_plain,
        "uncertainty": uncertainty,
        "metrics": metrics,
        "warnings": warnings,
        "duration_s": duration,
    }


@dataclass(frozen=True)
class NoiseResult(PerSensorResult):
    """The noise characterisation of a still recording: one entry per sensor (``acc``, ``gyr``, ``mag``).

    It corrects nothing: :meth:`corrections` is empty and :meth:`apply` refuses, so exporters that
    write a correction refuse it too; the noise exporters (Kalibr, OpenVINS, VINS-Fusion, JSON, CSV)
    read its figures.
    """

    RESULT_TYPE: ClassVar[str] = "noise"
    MODEL_TYPE: ClassVar[str] = "noise"
    KIND: ClassVar[str] = FIGURES

    sampling_rate_hz: float
    duration_s: float
    still: dict | None = None
    units_stated: bool = False
    """The recording's format states its units (a flight controller's log): an implausible figure is no misread
    unit (app.calibration.shared.plausible)."""
    method: str = "noise"

    @property
    def correction(self):
        raise CalibrationError("a noise characterisation has no correction: it measures the random errors only")

    def apply(self, samples, sensor: str | None = None):
        raise CalibrationError("a noise characterisation corrects nothing: apply a calibration of another method")

    @classmethod
    def filter_gaps(cls, metrics: dict) -> tuple[FilterGap, ...]:
        """What a filter's noise model needs (:data:`FILTER_SENSORS`' :data:`FILTER_TERMS`) that these metrics
        lack: a sensor not characterised, or a term not seen on some axis (its τ is null), with how long a still
        recording would show it. Read from the metrics, so that a stored body answers as its result does."""
        gaps = []
        for sensor in FILTER_SENSORS:
            part = metrics.get(sensor)
            if not part:
                gaps.append(FilterGap(sensor))
                continue
            for term in FILTER_TERMS:
                if any(t is None for t in part.get(f"tau_{term}_s") or [None]):
                    gaps.append(FilterGap(sensor, term, (part.get("record_for_s") or {}).get(term)))
        return tuple(gaps)

    def physical_figures(self) -> list:
        """Each sensor's noise density and the gyroscope's bias (its mean at rest), in the unit it was
        characterised in."""
        out = []
        for name, part in self.sensors.items():
            model = part["model"]
            density = tuple(v for v in model.get("noise_density") or () if v is not None)
            if density:
                out.append(
                    PhysicalFigure(
                        name,
                        "noise_density",
                        density,
                        model.get("unit", ""),
                        sampling_rate_hz=self.sampling_rate_hz,
                        stated=self.units_stated,
                    )
                )
            if name == "gyr" and model.get("bias") is not None:
                out.append(
                    PhysicalFigure(name, "bias", tuple(model["bias"]), model.get("unit", ""), stated=self.units_stated)
                )
        return out

    def body_dict(self) -> dict:
        return {
            "adev": {name: part["adev"] for name, part in self.sensors.items()},
            "sampling_rate_hz": self.sampling_rate_hz,
            "duration_s": self.duration_s,
            "still": self.still,
            **({"units_stated": True} if self.units_stated else {}),
        }

    @classmethod
    def _from_body(cls, data: dict) -> NoiseResult:
        return cls(
            sensors=cls.parts_from(data, "adev"),
            sampling_rate_hz=float(data["sampling_rate_hz"]),
            duration_s=float(data["duration_s"]),
            still=data.get("still"),
            units_stated=bool(data.get("units_stated", False)),
            warnings=tuple(data.get("warnings", ())),
            reasons=tuple(data.get("reasons", ())),
            unit=data.get("unit", ""),
        )
