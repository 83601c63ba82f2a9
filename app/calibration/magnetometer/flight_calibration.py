"""A compass calibrated from a flight as a stored calibration: ``h = M (Q m − b − k p)`` in the result family.

:func:`.flight.fit_flight_compass` returns the fit (:class:`.flight_result.FlightCompassResult`); this
class is what trical stores, exports and judges (:class:`~app.calibration.shared.result.CalibrationResult`):
its parameters are the model's ``M``, ``b``, ``k`` and ``Q``; its figure is the heading error on flight
segments left out of the fit, the firmware's own calibration before and this one after, in degrees; its
``flight`` holds what the log is and what the firmware stored, and ``series`` what the page draws.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..shared.correction import AffineCorrection
from ..shared.result import NO_FIGURE, CalibrationResult, Figure, gate_fields, parameter

SOURCE = (
    "h = M (Q m − b − k p): the compass's offsets b, soft iron M and motor interference k p after the "
    "rotation Q of its axes onto the vehicle's, fitted against the geomagnetic field turned into the body "
    "frame by the log's attitude"
)
FIGURE_BASIS = "heading error on flight segments left out"
FIGURE_UNIT = "°"


@dataclass(frozen=True)
class FlightCompassCalibration(CalibrationResult):
    """A compass's correction fitted on a flight log.

    Attributes
    ----------
    M : numpy.ndarray, shape (3, 3)
        Symmetric soft iron (the identity, or diagonal, for the simpler structures).
    b : numpy.ndarray, shape (3,)
        Offsets in µT, in the body frame.
    k : numpy.ndarray, shape (3,)
        Motor interference, µT per ampere (or per unit of throttle 0–1); zeros without a motor term.
    Q : numpy.ndarray, shape (3, 3)
        The rotation from the axes the log gives the raw readings in onto the body frame.
    half_widths : dict
        95 % half-widths of ``M``, ``b`` and ``k`` (None where the structure does not fit them).
    flight : dict
        The firmware, its generation, the compass instance, the structure and motor term chosen, the
        orientation found, what the firmware stored, how the raw readings were had, the candidates' figures.
    series : dict
        A thinned series over the flight for the page.
    """

    RESULT_TYPE: ClassVar[str] = "compass_flight"
    MODEL_TYPE: ClassVar[str] = "compass_flight"
    CORRECTION_SOURCE: ClassVar[str] = SOURCE

    M: np.ndarray = parameter()
    b: np.ndarray = parameter()
    k: np.ndarray = parameter()
    Q: np.ndarray = parameter()
    half_widths: dict = field(default_factory=dict)
    flight: dict = field(default_factory=dict)
    series: dict = field(default_factory=dict)
    metrics: dict = field(default_factory=dict)
    warnings: tuple = ()
    reasons: tuple = ()
    method: str = "compass_flight"
    unit: str = "uT"
    gravity: float | None = None

    @classmethod
    def from_fit(cls, fit, *, flight: dict, metrics: dict) -> FlightCompassCalibration:
        """The stored form of a :class:`.flight_result.FlightCompassResult` with the log's ``flight`` facts."""
        d = fit.to_dict()
        figures = {}
        for when in ("before", "after"):
            summary = d["heading_error_deg"].get(when) or {}
            figures[f"heading_error_{when}_deg"] = summary.get("rms")
            figures[f"heading_error_{when}_p95_deg"] = summary.get("p95")
        flight = {
            **flight,
            "structure": d["model"],
            "motor": d["motor"],
            **{
                key: d[key]
                for key in (
                    "rotation_found",
                    "rotation_nearest",
                    "angle_left_deg",
                    "orientation_agrees",
                    "models",
                    "intervals",
                    "updated",
                )
            },
        }
        return cls(
            M=np.asarray(fit.matrix, float),
            b=np.asarray(fit.offsets_ut, float),
            k=np.asarray(fit.motor_coefficients, float) if fit.motor else np.zeros(3),
            Q=np.asarray(fit.rotation, float),
            half_widths={
                "M": d["matrix_half_width"],
                "b": d["offsets_half_width_ut"],
                "k": d["motor_half_width"] if fit.motor else None,
            },
            flight=flight,
            series=d["series"],
            metrics={**metrics, **figures, "coverage": d["coverage"], "n_samples": d["n_samples"]},
            warnings=tuple(fit.warnings),
            reasons=tuple(fit.reasons),
        )

    def _calibrate(self, rows: np.ndarray) -> np.ndarray:
        return (rows @ self.Q.T - self.b) @ self.M.T  # h = M (Q m − b), at no current

    def corrected_sensors(self) -> tuple[str, ...]:
        return ("mag",)

    @property
    def correction(self) -> AffineCorrection:
        """The correction at no current, ``M Q (m − Qᵀ b)``: what a reading with the motors off gets."""
        return AffineCorrection(self.M @ self.Q, self.Q.T @ self.b, self.unit, "uT", SOURCE, sensor="mag")

    def corrections(self) -> dict[str, AffineCorrection]:
        return {"mag": self.correction}

    def physical_figures(self) -> list:
        """None: a flight log states its compass's unit, so an implausible scale or offset is no misread unit (the
        remedy the generic check gives, a unit to give, is one a flight log's upload refuses). The fit's own gates
        judge them with what a flight can change (:data:`.flight.MATRIX_EIGEN_RANGE`, :data:`.flight.MAX_OFFSET_UT`:
        a wrong expected field, a magnet); on the PX4 1.6 log of tests/data/real/flight, parked one way, the
        undetermined scale of -8.6 is refused by them and by the headings."""
        return []

    @classmethod
    def figures_from(cls, metrics: dict, output_unit: str | None) -> tuple[Figure, ...]:
        """The rms heading error on flight segments left out of the fit: with the firmware's own calibration
        before, with this one after, in degrees."""
        if metrics.get("heading_error_after_deg") is None:
            return (NO_FIGURE,)
        return (
            Figure(
                metrics.get("heading_error_before_deg"), metrics["heading_error_after_deg"], FIGURE_UNIT, FIGURE_BASIS
            ),
        )

    def uncertainty(self) -> dict:
        return {"confidence": 0.95, **self.half_widths}

    def body_dict(self) -> dict:
        return {"flight": dict(self.flight), "series": dict(self.series)}

    @classmethod
    def _from_body(cls, data: dict) -> FlightCompassCalibration:
        half = {k: v for k, v in (data.get("uncertainty") or {}).items() if k != "confidence"}
        return cls(
            **cls.parameters_from(data["model"]),
            half_widths=half,
            flight=dict(data.get("flight") or {}),
            series=dict(data.get("series") or {}),
            **gate_fields(data),
            method=data.get("method", "compass_flight"),
            unit=data.get("unit", "uT"),
        )
