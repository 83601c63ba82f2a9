"""Fixed-point emulation of the gradient descent of Farago et al. (eqs. (12)–(16)), as a microcontroller runs it.

Farago et al. (IEEE Access), section II.C: the method "can be easily implemented using only fixed-point
arithmetic"; h = 10⁻⁵ suits 32-bit fixed point and h = 0.01 the 16-bit version.  The paper gives
no bit-level detail, so trical defines the scheme below and emulates it bit-exactly with integers
(numpy int64 for products, Python integers for the double-width accumulator).

Scheme (W = 16 or 32 bits, F fraction bits):

- Number format: ``fixed16`` is Q3.12 (W = 16, F = 12: range [−8, 8) g, LSB 2⁻¹² g ≈ 0.244 mg);
  ``fixed32`` is Q7.24 (W = 32, F = 24: range [−128, 128) g, LSB 2⁻²⁴ g ≈ 6e-8 g).  Every
  W-bit quantity (readings, parameters, calibrated values, residuals, gradient, learning rates,
  h) is a signed two's-complement W-bit integer q standing for q / 2^F.
- Conversion of a real x (input readings in g, p₀, h, α): ``q = floor(x·2^F + 1/2)`` (round half
  up), saturated to W bits.  h = 0.01 becomes 41 LSB in Q3.12 (0.0100098 g); h = 10⁻⁵ becomes
  168 LSB in Q7.24.
- Saturation: every W-bit result is clamped to [−2^(W−1), 2^(W−1) − 1]; the 2W-bit accumulator
  to [−2^(2W−1), 2^(2W−1) − 1].  Additions saturate after each single addition, in the order
  written below.
- Multiplication ``mul(x, y)``: the exact 2W-bit product, plus 2^(F−1), arithmetic shift right by
  F (round half up), saturated to W bits.
- Division ``div(n, d)`` (d > 0): round half up, ``floor((2n + d) / (2d))``.
- Calibration, eqs. (7)–(9): ``w = sat(v + o)``; ``a_x = mul(k_xx, w_x)``;
  ``a_y = sat(mul(k_xy, w_x) + mul(k_yy, w_y))``;
  ``a_z = sat(sat(mul(k_xz, w_x) + mul(k_yz, w_y)) + mul(k_zz, w_z))``.
- Residual without the square root (Farago et al. section II.C): ``r = sat(sat(sat(mul(a_x, a_x) +
  mul(a_y, a_y)) + mul(a_z, a_z)) − 2^F)``.
- Cost, eq. (12) as a mean over the N points: ``acc`` = saturating 2W-bit sum of the exact products
  r·r (Q.2F) in point order, then ``f = div(acc, N)`` (Q.2F, 2W bits).
- Gradient, eqs. (13), (15): ``g_i = sat(div(sat₂W(f(p + h eᵢ) − f(p)), h))`` — Q.2F over Q.F gives
  Q.F; ``p + h eᵢ`` is a saturating W-bit addition.
- Step, eqs. (14), (16): ``p_i = sat(p_i − mul(α_i, g_i))`` with α = (α_s, α_s, α_s, α_m, α_m, α_m,
  α_o, α_o, α_o) converted as above.
- Iterations: exactly ``max_iter`` (50 in the paper, section III), ending early only when a whole
  step is zero (the iteration has reached a fixed point and would repeat forever).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..shared.errors import CalibrationError

Q_FORMATS = {16: 12, 32: 24}
"""Fraction bits F per word width W: Q3.12 and Q7.24."""


@dataclass(frozen=True)
class FixedFormat:
    """A signed W-bit two's-complement fixed-point format with F fraction bits."""

    bits: int
    frac: int

    @property
    def lo(self) -> int:
        return -(1 << (self.bits - 1))

    @property
    def hi(self) -> int:
        return (1 << (self.bits - 1)) - 1

    @property
    def lo2(self) -> int:
        return -(1 << (2 * self.bits - 1))

    @property
    def hi2(self) -> int:
        return (1 << (2 * self.bits - 1)) - 1

    @property
    def name(self) -> str:
        return f"Q{self.bits - 1 - self.frac}.{self.frac}"

    def quantize(self, x) -> np.ndarray:
        """Round half up to the nearest LSB and saturate (int64 array)."""
        x = np.asarray(x, dtype=float)
        q = np.floor(x * float(1 << self.frac) + 0.5)
        return np.clip(q, self.lo, self.hi).astype(np.int64)

    def to_float(self, q) -> np.ndarray:
        return np.asarray(q, dtype=np.int64).astype(float) / float(1 << self.frac)

    def sat(self, q):
        return np.clip(q, self.lo, self.hi)

    def mul(self, x, y):
        """W×W → 2W-bit product, + 2^(F−1), arithmetic shift right F, saturate to W bits."""
        z = np.asarray(x, dtype=np.int64) * np.asarray(y, dtype=np.int64)  # |z| < 2^62 for W ≤ 32
        return self.sat((z + (1 << (self.frac - 1))) >> self.frac)


def format_for(bits: int) -> FixedFormat:
    """The format trical uses for a word width (16 → Q3.12, 32 → Q7.24)."""
    if bits not in Q_FORMATS:
        raise CalibrationError(f"fixed-point word width must be 16 or 32 bits; got {bits}")
    return FixedFormat(bits, Q_FORMATS[bits])


def div_round(n: int, d: int) -> int:
    """Integer division rounding half up: floor((2n + d) / (2d)), d > 0 (Python integers)."""
    return (2 * n + d) // (2 * d)


def _sat2(fmt: FixedFormat, x: int) -> int:
    return min(max(x, fmt.lo2), fmt.hi2)


def _calibrated(fmt: FixedFormat, P: np.ndarray, v: np.ndarray) -> np.ndarray:
    """a = K (v + o) for each row of P (M, 9) and each point of v (N, 3): shape (M, N, 3)."""
    kxx, kyy, kzz, kxy, kxz, kyz = (P[:, [i]] for i in range(6))
    w = fmt.sat(v[None, :, :] + P[:, None, 6:9])  # Farago et al. eqs. (7)–(9): v + o
    wx, wy, wz = w[..., 0], w[..., 1], w[..., 2]
    ax = fmt.mul(kxx, wx)
    ay = fmt.sat(fmt.mul(kxy, wx) + fmt.mul(kyy, wy))
    az = fmt.sat(fmt.sat(fmt.mul(kxz, wx) + fmt.mul(kyz, wy)) + fmt.mul(kzz, wz))
    return np.stack([ax, ay, az], axis=-1)


def _costs(fmt: FixedFormat, P: np.ndarray, v: np.ndarray) -> list[int]:
    """Eq. (12) without the square root, mean over the points, in Q.2F (Python ints)."""
    a = _calibrated(fmt, P, v)
    one = 1 << fmt.frac
    r = fmt.sat(
        fmt.sat(fmt.sat(fmt.mul(a[..., 0], a[..., 0]) + fmt.mul(a[..., 1], a[..., 1])) + fmt.mul(a[..., 2], a[..., 2]))
        - one
    )
    rr = r * r  # exact: |r| ≤ 2^(W−1), so rr ≤ 2^62
    n = v.shape[0]
    out = []
    for row in rr.tolist():
        acc = 0
        for term in row:  # saturating 2W-bit accumulation, in point order
            acc = _sat2(fmt, acc + term)
        out.append(div_round(acc, n))
    return out


@dataclass(frozen=True)
class FixedPointRun:
    """Outcome of :func:`fixed_point_descent`.

    Attributes
    ----------
    p : numpy.ndarray, shape (9,)
        Final parameters as real numbers (offsets in g).
    p_raw : numpy.ndarray of int64, shape (9,)
        The same as W-bit integers.
    iterations : int
    saturated : bool
        Whether any parameter, gradient or the cost hit a saturation limit.
    q_format : str
        ``Q3.12`` or ``Q7.24``.
    h, alphas : float, numpy.ndarray
        The step h and learning rates actually used (after quantisation).
    cost : float
        Final value of the mean cost (Q.2F as a real number).
    """

    p: np.ndarray
    p_raw: np.ndarray
    iterations: int
    saturated: bool
    q_format: str
    h: float
    alphas: np.ndarray
    cost: float


def fixed_point_descent(
    points_g,
    *,
    bits: int,
    h: float,
    alphas,
    max_iter: int = 50,
    p0=(1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
) -> FixedPointRun:
    """Run the finite-difference gradient descent of Farago et al. eqs. (12)–(16) in W-bit fixed point.

    Parameters
    ----------
    points_g : array_like, shape (N, 3)
        Calibration points in g.
    bits : int
        16 or 32 (module docstring for the formats).
    h : float
        Finite-difference spacing (0.01 for 16 bits, 1e-5 for 32 bits in the paper).
    alphas : array_like, shape (9,)
        Vectorised learning rates of eq. (16).
    max_iter : int
        Iteration cap.
    p0 : array_like, shape (9,)
        Start, the ideal sensor by default (Farago et al. section II.C).

    Returns
    -------
    FixedPointRun
    """
    fmt = format_for(bits)
    v = fmt.quantize(points_g)
    P = fmt.quantize(p0)
    h_q = int(fmt.quantize(h))
    if h_q <= 0:
        raise CalibrationError(f"h = {h} is below one LSB of {fmt.name}: use a larger h")
    a_q = fmt.quantize(alphas)
    saturated = bool(np.any(np.abs(np.asarray(points_g, dtype=float)) * (1 << fmt.frac) > fmt.hi))
    eye = np.eye(9, dtype=np.int64) * h_q
    it = 0
    f0 = _costs(fmt, P[None, :], v)[0]
    for it in range(1, max_iter + 1):  # noqa: B007 - the count of iterations is read after the loop
        trial = fmt.sat(P[None, :] + eye)  # eq. (15)
        f = _costs(fmt, np.vstack([P[None, :], trial]), v)
        f0, fi = f[0], f[1:]
        grad = np.array(
            [min(max(div_round(_sat2(fmt, x - f0), h_q), fmt.lo), fmt.hi) for x in fi], dtype=np.int64
        )  # eq. (13)
        step = fmt.mul(a_q, grad)  # eq. (16)
        new = fmt.sat(P - step)  # eq. (14)
        saturated |= bool(
            np.any(np.abs(grad) >= fmt.hi)
            or np.any(np.abs(new) >= fmt.hi)
            or f0 >= fmt.hi2
            or any(x >= fmt.hi2 for x in fi)
        )
        if np.all(new == P):
            break
        P = new
    else:
        f0 = _costs(fmt, P[None, :], v)[0]
    return FixedPointRun(
        p=fmt.to_float(P),
        p_raw=P.copy(),
        iterations=it,
        saturated=saturated,
        q_format=fmt.name,
        h=h_q / float(1 << fmt.frac),
        alphas=fmt.to_float(a_q),
        cost=f0 / float(1 << (2 * fmt.frac)),
    )
