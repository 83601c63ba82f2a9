"""The frozen result of a compass calibrated from a flight, ``h_body = M (Q m − b − k p)``."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..shared.errors import CalibrationError
from ..shared.uncertainty import CONFIDENCE


@dataclass(frozen=True)
class FlightCompassResult:
    """A compass calibrated from a flight, ``h_body = M (Q m − b − k p)`` in µT.

    Attributes are those of the flight-compass contract (docs/methods.md, ``compass_flight``);
    :meth:`to_dict` gives them as plain lists and numbers, :meth:`correct` applies the model.
    """

    ok: bool
    reasons: tuple
    warnings: tuple
    model: str
    motor: str | None
    offsets_ut: np.ndarray
    offsets_half_width_ut: np.ndarray | None
    matrix: np.ndarray
    matrix_half_width: np.ndarray | None
    motor_coefficients: np.ndarray
    motor_half_width: np.ndarray | None
    rotation: np.ndarray
    rotation_found: np.ndarray
    rotation_nearest: dict
    angle_left_deg: float
    orientation_agrees: bool
    heading_error_deg: dict
    models: dict
    coverage: float
    n_samples: int
    series: dict = field(default_factory=dict)
    intervals: dict = field(default_factory=dict)
    confidence: float = CONFIDENCE
    updated: dict | None = None
    """Where the flight left some numbers undetermined (:mod:`.flight_partial`): ``{"b": [bool, bool, bool],
    "M": bool, "k": [bool, bool, bool]}``, true for those updated from the flight, false for those held at the
    firmware's; None where every number is the flight's."""

    def correct(self, mag, power=None) -> np.ndarray:
        """``h_body = M (Q m − b − k p)`` for raw readings ``mag`` (N, 3) in frame L and ``power`` (N,)."""
        m = np.asarray(mag, dtype=float).reshape(-1, 3)
        v = m @ self.rotation.T - self.offsets_ut
        if self.motor is not None:
            if power is None:
                raise CalibrationError("this calibration has a motor term: give the power (current or throttle)")
            v = v - np.outer(np.asarray(power, dtype=float).reshape(-1), self.motor_coefficients)
        return v @ self.matrix.T

    def to_dict(self) -> dict:
        """Every field as plain JSON: arrays as lists, a non-finite number as None."""
        return {name: plain(getattr(self, name)) for name in self.__dataclass_fields__}


def plain(value):
    """``value`` as JSON has it: arrays and tuples as lists, numpy scalars as numbers, NaN and ±inf as None."""
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return [plain(v) for v in value] if value.ndim else plain(value.item())
    if isinstance(value, (np.floating, float)):
        return float(value) if np.isfinite(value) else None
    if isinstance(value, (np.integer, np.bool_)):
        return value.item()
    return value
