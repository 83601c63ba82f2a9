"""The correction firmware applies, ``f = M (m − o)``, shared by every model of every sensor."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .validation import as_samples


@dataclass(frozen=True)
class AffineCorrection:
    """One sensor's correction ``f = M (m − o)`` and the units it maps between.

    Attributes
    ----------
    M : numpy.ndarray, shape (3, 3)
    o : numpy.ndarray, shape (3,)
        In the unit of the readings.
    input_unit, output_unit : str or None
    source : str
        The paper and equation the correction comes from.
    sensor : str
        ``acc``, ``gyr`` or ``mag``.
    """

    M: np.ndarray
    o: np.ndarray
    input_unit: str | None = None
    output_unit: str | None = None
    source: str = ""
    sensor: str = "acc"

    def apply(self, raw) -> np.ndarray:
        """``f = M (m − o)`` for samples of shape (3,) or (N, 3)."""
        m = as_samples(raw)
        return ((m.reshape(-1, 3) - self.o) @ self.M.T).reshape(m.shape)


def correction_of(apply, *, input_unit=None, output_unit=None, source: str = "") -> AffineCorrection:
    """The correction of an affine calibration function: M and o from its values at the origin
    and at the unit vectors (``apply(m) = M m − M o``)."""
    origin = apply(np.zeros((1, 3)))[0]
    M = (apply(np.eye(3)) - origin).T
    o = -np.linalg.solve(M, origin)
    return AffineCorrection(M, o, input_unit, output_unit, source)
