# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""The Allan sums' fused loop, compiled (Cython): one core's share of

    Σ (x_{i+2m} − 2 x_{i+m} + x_i)²

for each averaging factor m (NIST SP 1065, W. J. Riley, *Handbook of Frequency Stability Analysis*,
2008, eq. (14)), in one pass that reads the three windows of the phase once and keeps the sums in
registers, without the interpreter's lock, so the shares run side by side on threads.

The numpy loop of :mod:`app.calibration.noise.allan` is its reference and its stand-in where the package was
installed without a C compiler. Both take the second difference as a difference of first differences,
(x_{i+2m} − x_{i+m}) − (x_{i+m} − x_i); here consecutive i go to :data:`LANES` running sums, which the
compiler keeps in vector registers, so the additions come in another order than numpy's and the sums
agree to a few units of 1e-14 relative.
"""

from libc.stdint cimport int64_t

LANES = 8
"""Running sums, one per i modulo LANES, added pairwise at the end."""


def sums_of_share(const double[::1] x, const int64_t[::1] ms, Py_ssize_t share, Py_ssize_t shares,
                  double[::1] out):
    """Write into ``out[j]`` the sum over the ``share``-th of ``shares`` equal parts of i = 0 … L − 2m − 1
    of (x_{i+2m} − 2 x_{i+m} + x_i)², with m = ``ms[j]`` and L = ``len(x)``.

    The parts are cut as ``count · share // shares`` … ``count · (share + 1) // shares`` with
    count = L − 2m, as :func:`app.calibration.noise.allan._numpy_sums_of_share` cuts them.

    Raises ValueError for an m outside 1 … (L − 1) / 2, a share outside 0 … shares − 1, or an ``out``
    whose length is not that of ``ms``.
    """
    cdef Py_ssize_t n = x.shape[0]
    cdef Py_ssize_t j, count
    if shares < 1 or share < 0 or share >= shares:
        raise ValueError(f"share {share} of {shares}: a share lies in 0 … shares − 1")
    if out.shape[0] != ms.shape[0]:
        raise ValueError(f"{out.shape[0]} sums to write for {ms.shape[0]} averaging factors")
    for j in range(ms.shape[0]):
        if ms[j] < 1 or 2 * ms[j] > n - 1:
            raise ValueError(f"averaging factor {ms[j]} outside 1 … {(n - 1) // 2} for {n} phase points")
    with nogil:
        for j in range(ms.shape[0]):
            count = n - 2 * ms[j]
            out[j] = _sum_of_squares(&x[0], ms[j], count * share // shares, count * (share + 1) // shares)


cdef double _sum_of_squares(const double* x, Py_ssize_t m, Py_ssize_t lo, Py_ssize_t hi) noexcept nogil:
    """Σ_{i=lo}^{hi−1} ((x_{i+2m} − x_{i+m}) − (x_{i+m} − x_i))², in LANES running sums."""
    cdef const double* a = x + lo
    cdef const double* b = x + lo + m
    cdef const double* c = x + lo + 2 * m
    cdef Py_ssize_t k = hi - lo
    cdef Py_ssize_t i = 0
    cdef double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0, s4 = 0.0, s5 = 0.0, s6 = 0.0, s7 = 0.0
    cdef double d0, d1, d2, d3, d4, d5, d6, d7
    while i + 8 <= k:
        d0 = (c[i] - b[i]) - (b[i] - a[i])
        d1 = (c[i + 1] - b[i + 1]) - (b[i + 1] - a[i + 1])
        d2 = (c[i + 2] - b[i + 2]) - (b[i + 2] - a[i + 2])
        d3 = (c[i + 3] - b[i + 3]) - (b[i + 3] - a[i + 3])
        d4 = (c[i + 4] - b[i + 4]) - (b[i + 4] - a[i + 4])
        d5 = (c[i + 5] - b[i + 5]) - (b[i + 5] - a[i + 5])
        d6 = (c[i + 6] - b[i + 6]) - (b[i + 6] - a[i + 6])
        d7 = (c[i + 7] - b[i + 7]) - (b[i + 7] - a[i + 7])
        s0 += d0 * d0
        s1 += d1 * d1
        s2 += d2 * d2
        s3 += d3 * d3
        s4 += d4 * d4
        s5 += d5 * d5
        s6 += d6 * d6
        s7 += d7 * d7
        i += 8
    while i < k:
        d0 = (c[i] - b[i]) - (b[i] - a[i])
        s0 += d0 * d0
        i += 1
    return ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7))
