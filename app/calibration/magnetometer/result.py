"""The frozen result of a compass calibration, ``h = M (m − b)``."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..shared.correction import AffineCorrection
from ..shared.plausible import PhysicalFigure
from ..shared.result import NO_FIGURE, CalibrationResult, Figure, gate_fields, parameter
from ..shared.uncertainty import CONFIDENCE, half_widths
from .refine import unpack

SOURCE = (
    "h = M (m − b), M symmetric: the magnetometer model ỹ = S h + b of Särkkä et al., IEEE Sensors "
    "Journal 17(11) 2017, eq. (6), with S = M⁻¹, fitted on the field's magnitude"
)


def figure_unit(output_unit: str | None) -> str:
    """The unit of a compass calibration's figures: µT, or counts for a magnetometer left in counts (its
    ``_ut`` metrics are then in counts)."""
    return "counts" if output_unit == "raw" else "µT"


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
    AS_FITTED: ClassVar[str] = (
        "As fitted (Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (6)): h = M (m − b), so b = o."
    )

    M: np.ndarray = parameter()
    b: np.ndarray = parameter()
    covariance: np.ndarray | None  # type: ignore[misc]  # mypy takes parameter() (a field) for a default
    dof: int  # type: ignore[misc]  # mypy takes parameter() (a field) for a default
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

    def _calibrate(self, rows: np.ndarray) -> np.ndarray:
        return (rows - self.b) @ self.M.T  # h = M (m − b)

    def corrected_sensors(self) -> tuple[str, ...]:
        return ("mag",)

    @classmethod
    def figures_from(cls, metrics: dict, output_unit: str | None) -> tuple[Figure, ...]:
        """The error of the field strength |h| against F on directions left out (cross-validated), else on
        the readings fitted; in µT, or counts for a magnetometer left in counts (no chip, no field given)."""
        if "cv_error_ut" not in metrics:
            return (NO_FIGURE,)
        unit = figure_unit(output_unit)
        if metrics.get("cv_error_ut") is not None:
            return (
                Figure(
                    metrics.get("raw_error_ut"),
                    metrics["cv_error_ut"],
                    unit,
                    "error of the field strength on new directions",
                ),
            )
        return (
            Figure(
                metrics.get("raw_error_ut"),
                metrics.get("fit_error_ut"),
                unit,
                "error of the field strength on the readings fitted",
            ),
        )

    @property
    def correction(self) -> AffineCorrection:
        return AffineCorrection(
            np.asarray(self.M, dtype=float),
            np.asarray(self.b, dtype=float),
            self.unit,
            self.output_unit,
            SOURCE,
            sensor="mag",
        )

    def corrections(self) -> dict[str, AffineCorrection]:
        return {"mag": self.correction}

    def physical_figures(self) -> list:
        """Its correction's scale, and the field its readings hold: F det(M)^(−1/3), the radius of the
        readings' sphere in their own unit (F itself where it was estimated, det M = 1). None where the
        refinement ran away: what is shown then only draws the readings (its own reason says so), and a
        field or scale read off it would send the person to the unit or the columns for nothing."""
        if self.metrics.get("fit_stage", "refined") != "refined":
            return []
        out = super().physical_figures()
        field_ut = self.metrics.get("field_ut")
        det = float(np.linalg.det(np.asarray(self.M, dtype=float)))
        if field_ut is not None and det > 0:
            out.append(PhysicalFigure("mag", "field", (float(field_ut) * det ** (-1.0 / 3.0),), self.unit))
        return out

    def uncertainty(self) -> dict:
        if self.covariance is None:
            return {"confidence": CONFIDENCE, "dof": self.dof, "M": None, "b": None}
        half_M, half_b = unpack(half_widths(np.asarray(self.covariance), self.dof, CONFIDENCE))
        return {"confidence": CONFIDENCE, "dof": self.dof, "M": half_M.tolist(), "b": half_b.tolist()}

    def body_dict(self) -> dict:
        return {
            "covariance": None if self.covariance is None else np.asarray(self.covariance).tolist(),
            "samples": {"raw_ut": np.asarray(self.samples).tolist()},
        }

    @classmethod
    def _from_body(cls, data: dict) -> MagnetometerResult:
        cov = data.get("covariance")
        return cls(
            **cls.parameters_from(data["model"]),
            covariance=None if cov is None else np.asarray(cov, dtype=float),
            dof=int((data.get("uncertainty") or {}).get("dof", 0)),
            samples=np.asarray((data.get("samples") or {}).get("raw_ut") or np.empty((0, 3)), dtype=float).reshape(
                -1, 3
            ),
            **gate_fields(data),
            method=data.get("method", "magnetometer"),
            unit=data.get("unit", "uT"),
        )
