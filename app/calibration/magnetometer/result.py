"""The frozen result of a compass calibration, ``h = M (m − b)``."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..correction import AffineCorrection
from ..result import CalibrationResult
from ..uncertainty import CONFIDENCE, half_widths
from ..validation import as_samples
from .refine import unpack

SOURCE = ("h = M (m − b), M symmetric: the magnetometer model ỹ = S h + b of Särkkä et al., IEEE Sensors "
          "Journal 17(11) 2017, eq. (6), with S = M⁻¹, fitted on the field's magnitude")


@dataclass(frozen=True)
class MagnetometerResult(CalibrationResult):
    """A magnetometer's hard iron ``b`` and soft iron ``M`` (symmetric), in µT.

    Attributes
    ----------
    M : numpy.ndarray, shape (3, 3)
    b : numpy.ndarray, shape (3,)
    covariance : numpy.ndarray of shape (9, 9), or None
        Of ``(M_xx, M_yy, M_zz, M_xy, M_xz, M_yz, b_x, b_y, b_z)`` (:func:`.refine.pack`).
    dof : int
    metrics : dict
    samples : numpy.ndarray, shape (K, 3)
        Up to 600 of the raw readings, for drawing them on the sphere before and after.
    """

    RESULT_TYPE: ClassVar[str] = "magnetometer"
    MODEL_TYPE: ClassVar[str] = "magnetometer"
    CORRECTION_SOURCE: ClassVar[str] = SOURCE

    M: np.ndarray
    b: np.ndarray
    covariance: np.ndarray | None
    dof: int
    metrics: dict = field(default_factory=dict)
    samples: np.ndarray = field(default_factory=lambda: np.empty((0, 3)))
    warnings: tuple = ()
    reasons: tuple = ()
    method: str = "magnetometer"
    unit: str = "uT"
    gravity: float | None = None

    @property
    def output_unit(self) -> str:
        """µT, or ``raw`` for readings in counts whose field was estimated: M then maps counts to
        counts, and every figure is in counts."""
        if self.unit == "raw" and self.metrics.get("field_source") == "estimated":
            return "raw"
        return "uT"

    def apply(self, raw) -> np.ndarray:
        """``h = M (m − b)`` for readings of shape (3,) or (N, 3)."""
        m = as_samples(raw)
        return ((m.reshape(-1, 3) - self.b) @ self.M.T).reshape(m.shape)

    @property
    def correction(self) -> AffineCorrection:
        return AffineCorrection(np.asarray(self.M, dtype=float), np.asarray(self.b, dtype=float), self.unit,
                                self.output_unit, SOURCE, sensor="mag")

    def corrections(self) -> dict[str, AffineCorrection]:
        return {"mag": self.correction}

    def model_dict(self) -> dict:
        return {"M": np.asarray(self.M).tolist(), "b": np.asarray(self.b).tolist()}

    def uncertainty(self) -> dict:
        if self.covariance is None:
            return {"confidence": CONFIDENCE, "dof": self.dof, "M": None, "b": None}
        half_M, half_b = unpack(half_widths(np.asarray(self.covariance), self.dof, CONFIDENCE))
        return {"confidence": CONFIDENCE, "dof": self.dof, "M": half_M.tolist(), "b": half_b.tolist()}

    def body_dict(self) -> dict:
        return {"covariance": None if self.covariance is None else np.asarray(self.covariance).tolist(),
                "samples": {"raw_ut": np.asarray(self.samples).tolist()}}

    @classmethod
    def _from_body(cls, data: dict) -> "MagnetometerResult":
        cov = data.get("covariance")
        return cls(M=np.asarray(data["model"]["M"], dtype=float), b=np.asarray(data["model"]["b"], dtype=float),
                   covariance=None if cov is None else np.asarray(cov, dtype=float),
                   dof=int((data.get("uncertainty") or {}).get("dof", 0)), metrics=dict(data.get("metrics", {})),
                   samples=np.asarray((data.get("samples") or {}).get("raw_ut") or np.empty((0, 3)),
                                      dtype=float).reshape(-1, 3),
                   warnings=tuple(data.get("warnings", ())), reasons=tuple(data.get("reasons", ())),
                   method=data.get("method", "magnetometer"), unit=data.get("unit", "uT"))
