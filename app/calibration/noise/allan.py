"""The overlapping Allan deviation of long sample streams, in bounded memory.

The Allan variance of a rate ``y`` sampled at ``fs`` (IEEE Std 952-1997, Annex C; IEEE Std
1554-2005, section 6.2; El-Sheimy, Hou and Niu, IEEE Trans. Instrum. Meas. 57(1) 2008, eq. (2)) at
τ = m / fs, in its fully overlapping form, is computed from the phase ``x`` (the cumulative sum of
``y / fs``, with ``x_0 = 0``)::

    σ²(τ) = 1 / (2 τ² (L − 2m)) · Σ_{i=0}^{L−2m−1} (x_{i+2m} − 2 x_{i+m} + x_i)²

with L = N + 1 phase points (NIST SP 1065, W. J. Riley, *Handbook of Frequency Stability
Analysis*, 2008, eq. (14)).  Each τ costs one pass over the phase; two axes are in memory at a time
(the phase, float64, of the one summed and of the next), whatever the length of the (memory-mapped)
input, and the range of every τ is shared between the cores (:func:`second_difference_sums_fast`). A
core's share is summed by the compiled, fused loop of :mod:`app.calibration.noise.allan_fused` where the
package was built with it (:data:`FUSED`), and otherwise by numpy in blocks of :data:`CHUNK` terms;
:func:`second_difference_sums` is the plain reference both are tested against.

The confidence of each point comes from its equivalent degrees of freedom for the dominant power-law
noise (Howe, Allan and Barnes, *Properties of signal sources and measurement methods*, 35th Annual
Frequency Control Symposium, 1981; the simple formulae of NIST SP 1065, Table 5, which allantools'
``edf_simple`` also implements) and the chi-squared distribution (NIST SP 1065, eq. (45)).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from ..shared.chi2 import chi2_upper_quantile
from ..shared.cores import usable_cores
from ..shared.errors import CalibrationError, InsufficientDataError


def _fused_loop() -> Callable[[np.ndarray, np.ndarray, int, int, np.ndarray], None] | None:
    """The compiled loop's entry, or None where the package was installed without a C compiler."""
    try:
        from .allan_fused import sums_of_share
    except ImportError:
        return None
    return sums_of_share


_fused_sums_of_share = _fused_loop()

FUSED = _fused_sums_of_share is not None
"""Whether a core's share of the sums runs in the compiled, fused loop. ``pip install`` builds it where a C
compiler is present (setup.py). (3 h at 200 Hz, one axis, 61 τ: 0.07 s on one core and 0.03 s on two, against
0.10 s and 0.075 s for the numpy loop.)"""

NOT_BUILT = (
    "the compiled loop (app/calibration/noise/allan_fused.pyx) was not built: reinstall trical where a C compiler is "
    "(pip install -e . in a checkout)"
)
"""What to do when the compiled loop is missing: said by the tests, the bench, and a caller that asks for it."""

CHUNK = 1 << 18
"""Second differences formed per block (2 MB of float64): few enough numpy calls per τ that their own cost
(about a microsecond each, with the interpreter's lock held) stays small beside the arithmetic, so that the
shares' threads seldom wait for each other; the block's buffers stay in the processor's last-level cache.
(3 h at 200 Hz, three axes on two cores: 0.17–0.24 s against 0.26–0.33 s in blocks of 2¹⁶.)"""

ROW = 1 << 13
"""Second differences squared and summed per dot product: a block is summed as rows of this length by one
:func:`numpy.vecdot` call. A BLAS dot product of more than 10 000 terms (OpenBLAS, which numpy's wheels
ship) starts threads of its own, which compete with the shares' threads; rows below that stay on the
calling thread, and the dot product is a third of the cost of squaring and summing in two passes."""

PER_DECADE = 10
"""Points of the τ grid per decade of m (every integer m up to 10)."""

WHITE, FLICKER, RANDOM_WALK = 0, -1, -2
"""Exponents α of the frequency power spectrum S_y(f) ∝ f^α of the three noise terms: white rate
noise (angle random walk, slope −½), flicker (bias instability, flat) and random walk of the rate
(rate random walk, slope +½) — IEEE Std 952-1997, Annex C, Table C.1."""

MIN_SAMPLES = 16
"""Fewest samples with an Allan deviation worth computing (m = 1 … 7)."""


def tau_grid(n_samples: int, sampling_rate_hz: float, per_decade: int = PER_DECADE) -> np.ndarray:
    """Averaging factors m of the τ grid τ = m / fs: every m from 1 to 10, then ``per_decade``
    log-spaced integers per decade up to the largest m the overlapping estimator supports,
    ⌊(N − 1) / 2⌋ (N samples, N + 1 phase points), which is always included.

    Raises
    ------
    InsufficientDataError
        Fewer than :data:`MIN_SAMPLES` samples.
    """
    if n_samples < MIN_SAMPLES:
        raise InsufficientDataError(
            f"{n_samples} still samples are too few for an Allan deviation: record the device resting for at "
            f"least {MIN_SAMPLES} samples (minutes for the noise density, hours for the random walk)"
        )
    m_max = (n_samples - 1) // 2
    small = np.arange(1, min(10, m_max) + 1)
    if m_max <= 10:
        return small
    n = max(2, int(math.ceil(per_decade * math.log10(m_max / 10.0))) + 1)
    large = np.round(np.logspace(1.0, math.log10(m_max), n)).astype(np.int64)
    return np.unique(np.concatenate([small, large, [m_max]]))


PHASE_BLOCK = 1 << 16
"""Samples of a column taken at a time for the phase: each block's mean removed, summed, offset and scaled
while it is in the processor's cache."""


def phase_of(column, sampling_rate_hz: float, out: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """The phase x (N + 1 points, x_0 = 0) of one axis and the axis's mean.

    The mean is removed before the cumulative sum (it does not change the second differences, and
    keeps the phase small so that they do not cancel in floating point); the column (which may be a
    strided column of a memory map) is read in blocks, so only the float64 phase is held.

    Parameters
    ----------
    column : array_like, shape (N,)
        One axis's rates.
    sampling_rate_hz : float
    out : numpy.ndarray, optional
        Float64, at least N + 1 long: the phase is written into it (a buffer reused from axis to axis
        costs no fresh pages of memory).

    Returns
    -------
    x : numpy.ndarray, shape (N + 1,)
        The phase, x_{i+1} = x_i + (y_i − ȳ) / fs.
    mean : float
        ȳ.
    """
    n = len(column)
    total = 0.0
    for a in range(0, n, 1 << 20):
        total += float(np.sum(np.asarray(column[a : a + (1 << 20)], dtype=np.float64)))
    mean = total / n
    x = np.empty(n + 1) if out is None else out[: n + 1]
    x[0] = 0.0
    carry = 0.0
    for a in range(0, n, PHASE_BLOCK):
        block = x[1 + a : 1 + a + PHASE_BLOCK]
        np.subtract(column[a : a + PHASE_BLOCK], mean, out=block)
        np.cumsum(block, out=block)
        block += carry
        carry = float(block[-1])
        block /= sampling_rate_hz
    return x, mean


def second_difference_sums(x: np.ndarray, ms: np.ndarray) -> np.ndarray:
    """Σ (x_{i+2m} − 2 x_{i+m} + x_i)² over every i, for each m (NIST SP 1065, eq. (14)), in chunks."""
    out = np.empty(len(ms))
    buf = np.empty(CHUNK)
    for j, m in enumerate(ms):
        m = int(m)
        count = len(x) - 2 * m
        s = 0.0
        for a in range(0, count, CHUNK):
            k = min(CHUNK, count - a)
            d = buf[:k]
            np.multiply(x[a + m : a + m + k], -2.0, out=d)
            np.add(d, x[a + 2 * m : a + 2 * m + k], out=d)
            np.add(d, x[a : a + k], out=d)
            np.square(d, out=d)
            s += float(d.sum())
        out[j] = s
    return out


def _sums_of_share(x: np.ndarray, ms: np.ndarray, share: int, shares: int, fused: bool = FUSED) -> np.ndarray:
    """Σ (x_{i+2m} − 2 x_{i+m} + x_i)² over the ``share``-th of ``shares`` equal parts of the range of i,
    for each m: the part of :func:`second_difference_sums` that one core adds up, in the compiled loop
    (``fused``) or in numpy (:func:`_numpy_sums_of_share`)."""
    if not fused:
        return _numpy_sums_of_share(x, ms, share, shares)
    if _fused_sums_of_share is None:
        raise RuntimeError(NOT_BUILT)
    out = np.empty(len(ms))
    _fused_sums_of_share(x, np.ascontiguousarray(ms, dtype=np.int64), share, shares, out)
    return out


def _numpy_sums_of_share(x: np.ndarray, ms: np.ndarray, share: int, shares: int) -> np.ndarray:
    """:func:`_sums_of_share` in numpy: the reference of the compiled loop, and its stand-in where it was
    not built.

    The second difference is the difference of two first differences (NIST SP 1065, eq. (14) rewritten),
    d_i = D_{i+m} − D_i with D_j = x_{j+m} − x_j; for m up to a block's length the block's D is taken
    once (k + m subtractions) and serves both terms, which saves a third of the passes over the block
    when most τ are short (3 h at 200 Hz: 48 of the 61 points of the grid). Longer m take the three
    windows of the block apart. Every buffer is one block (:data:`CHUNK`), so the work stays in the
    processor's cache; numpy releases the GIL in each operation, so the shares run on threads side by side.
    """
    out = np.empty(len(ms))
    first = np.empty(2 * CHUNK)
    second = np.empty(CHUNK)
    for j, m in enumerate(ms):
        m = int(m)
        count = len(x) - 2 * m
        lo, hi = count * share // shares, count * (share + 1) // shares
        s = 0.0
        for a in range(lo, hi, CHUNK):
            k = min(CHUNK, hi - a)
            d = second[:k]
            if m <= CHUNK:
                e = first[: k + m]
                np.subtract(x[a + m : a + 2 * m + k], x[a : a + m + k], out=e)  # D_j, j = a … a + m + k − 1
                np.subtract(e[m:], e[:k], out=d)
            else:
                e = first[:k]
                np.subtract(x[a + 2 * m : a + 2 * m + k], x[a + m : a + m + k], out=d)
                np.subtract(x[a + m : a + m + k], x[a : a + k], out=e)
                d -= e
            s += _sum_of_squares(d)
        out[j] = s
    return out


def _sum_of_squares(d: np.ndarray) -> float:
    """Σ d_i², as dot products of :data:`ROW` terms (one :func:`numpy.vecdot` call for the whole rows)."""
    whole = len(d) - len(d) % ROW
    s = 0.0
    if whole:
        rows = d[:whole].reshape(-1, ROW)
        s += float(np.vecdot(rows, rows).sum())
    if whole < len(d):
        rest = d[whole:]
        s += float(np.dot(rest, rest))
    return s


def second_difference_sums_fast(
    x: np.ndarray, ms: np.ndarray, pool: ThreadPoolExecutor | None = None, shares: int = 1, fused: bool = FUSED
) -> np.ndarray:
    """:func:`second_difference_sums`, the range of i of every m cut into ``shares`` equal parts summed on
    the threads of ``pool`` (one share per core: each core has the same work at every τ); equal to it up
    to the order of the additions.

    Parameters
    ----------
    x : numpy.ndarray, shape (L,)
        The phase (:func:`phase_of`), float64.
    ms : numpy.ndarray of int
        Averaging factors, each 1 ≤ m ≤ (L − 2) / 2.
    pool : concurrent.futures.ThreadPoolExecutor, optional
        Threads to sum the shares on (none: one share, on the calling thread).
    shares : int
        Parts of the range of i, one per thread of ``pool``.
    fused : bool
        Sum in the compiled loop (default where it was built, :data:`FUSED`), or in numpy.

    Returns
    -------
    numpy.ndarray, shape (len(ms),)
        Σ (x_{i+2m} − 2 x_{i+m} + x_i)² over i = 0 … L − 2m − 1, for each m (NIST SP 1065, eq. (14)).
    """
    if pool is None or shares <= 1:
        return _sums_of_share(x, ms, 0, 1, fused)
    return np.sum(list(pool.map(lambda p: _sums_of_share(x, ms, p, shares, fused), range(shares))), axis=0)


MAX_SHARES = 8
"""Threads at most: past a few cores the sums wait on the memory, not on the arithmetic."""


def cores() -> int:
    """The cores this process may run on (its affinity where the system tells it), at most :data:`MAX_SHARES`.

    Returns
    -------
    int
        At least 1.
    """
    return usable_cores(MAX_SHARES)


def overlapping_adev(samples, sampling_rate_hz: float, ms: np.ndarray | None = None):
    """The overlapping Allan deviation of every column of ``samples`` at τ = m / fs.

    Parameters
    ----------
    samples : array_like, shape (N, k)
        Rates (any unit); may be a memory map: one column is read at a time.
    sampling_rate_hz : float
        Positive.
    ms : numpy.ndarray of int, optional
        Averaging factors (default :func:`tau_grid`); each 1 ≤ m ≤ (N − 1) / 2.

    Returns
    -------
    tau_s : numpy.ndarray, shape (n,)
    adev : numpy.ndarray, shape (n, k)
        In the unit of ``samples``.
    n_terms : numpy.ndarray of int, shape (n,)
        Second differences summed at each τ (N + 1 − 2m).
    mean : numpy.ndarray, shape (k,)
        Each column's mean.
    """
    if not sampling_rate_hz > 0:
        raise CalibrationError(f"the sampling rate must be positive, not {sampling_rate_hz}")
    n, k = samples.shape
    ms = tau_grid(n, sampling_rate_hz) if ms is None else np.asarray(ms, dtype=np.int64)
    if len(ms) == 0 or ms.min() < 1 or 2 * ms.max() > n:
        raise CalibrationError(f"averaging factors must lie in 1 … {(n - 1) // 2} for {n} samples")
    tau = ms / sampling_rate_hz
    n_terms = n + 1 - 2 * ms

    sums = np.empty((len(ms), k))
    mean = np.empty(k)
    # One axis at a time, its sums shared by the cores, while the next axis's phase is taken on a thread of
    # its own into the other of two buffers (two phases, 8 bytes a sample each, are all that is held).
    workers = cores()
    buffers = [np.empty(n + 1), np.empty(n + 1) if k > 1 else None]
    with ThreadPoolExecutor(max_workers=workers) as pool, ThreadPoolExecutor(max_workers=1) as reader:
        upcoming = reader.submit(phase_of, samples[:, 0], sampling_rate_hz, buffers[0])
        for axis in range(k):
            x, mean[axis] = upcoming.result()
            if axis + 1 < k:
                upcoming = reader.submit(phase_of, samples[:, axis + 1], sampling_rate_hz, buffers[(axis + 1) % 2])
            if not np.isfinite(x[-1]):
                raise CalibrationError("the samples hold NaN or infinite values: drop those rows first")
            sums[:, axis] = second_difference_sums_fast(x, ms, pool, workers)
    adev = np.sqrt(sums / (2.0 * tau * tau * n_terms)[:, None])
    return tau, adev, n_terms, mean


def edf_simple(n_phase: int, m, alpha) -> np.ndarray:
    """Equivalent degrees of freedom of the overlapping Allan variance (Howe, Allan and Barnes
    1981; NIST SP 1065, Table 5) for ``n_phase`` phase points, factor ``m`` and the power-law
    exponent ``alpha`` of the dominant noise (:data:`WHITE`, :data:`FLICKER`, :data:`RANDOM_WALK`).
    """
    big = float(n_phase)
    m = np.asarray(m, dtype=float)
    alpha = np.broadcast_to(np.asarray(alpha), m.shape)
    white = (3.0 * (big - 1.0) / (2.0 * m) - 2.0 * (big - 2.0) / big) * (4.0 * m * m) / (4.0 * m * m + 5.0)
    flicker = np.where(m == 1, 2.0 * (big - 2.0) / (2.3 * big - 4.9), 5.0 * big * big / (4.0 * m * (big + 3.0 * m)))
    walk = (big - 2.0) / (m * (big - 3.0) ** 2) * ((big - 1.0) ** 2 - 3.0 * m * (big - 1.0) + 4.0 * m * m)
    edf = np.select([alpha == WHITE, alpha == FLICKER, alpha == RANDOM_WALK], [white, flicker, walk], big - 1.0)
    return np.maximum(edf, 1.0)


def chi2_interval(edf, confidence: float = 0.95) -> tuple[np.ndarray, np.ndarray]:
    """Factors (lo, hi) on an estimated variance for its two-sided ``confidence`` interval:
    edf / χ²_{(1+c)/2}(edf) and edf / χ²_{(1−c)/2}(edf) (NIST SP 1065, eq. (45)).

    The χ² quantiles are :func:`app.calibration.shared.chi2.chi2_upper_quantile`'s (scipy.special.chdtri's to
    10⁻¹², without importing scipy.special, which takes longer than the rest of ``trical noise``'s imports).
    """
    if not 0.0 < confidence < 1.0:
        raise CalibrationError(f"a confidence interval's confidence lies strictly between 0 and 1, not {confidence}")
    edf = np.asarray(edf, dtype=float)
    tail = (1.0 - confidence) / 2.0
    return edf / chi2_upper_quantile(edf, tail), edf / chi2_upper_quantile(edf, 1.0 - tail)
