"""A calibration a device already holds, read from its firmware's parameters: imported, not fitted.

A flight controller or a phone's firmware stores per sensor the numbers of its own correction (ArduPilot's
``INS_ACCOFFS_*``, PX4's ``CAL_ACC0_*``, Betaflight's ``acc_calibration``, INAV's ``acczero_*``/``accgain_*``).
The readers of those files (app.io.imports) turn each sensor's numbers into trical's correction ``f = M (m − o)``
in trical's units (m/s², rad/s, µT); this result holds them beside what was read (the firmware, its version, the
kind of file, the parameters and the unit the firmware holds them in), so that a stored device calibration can be
checked, compared, applied and written out again like any other.

Nothing is fitted: there is no error before or after to tell (:meth:`ImportedCalibration.figures_from` says
"imported, not fitted"), no interval, and ``ok`` says only that the numbers lie within the firmware's own ranges
(the reader names each one outside) and that the plausibility gate found no figure no MEMS part can have.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from .shared.correction import AffineCorrection
from .shared.errors import CalibrationError
from .shared.gravity import STANDARD_GRAVITY
from .shared.result import CalibrationResult, Figure, gate_fields
from .shared.validation import as_samples

SENSOR_UNITS = {"acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}
"""The unit each imported correction maps (in and out): trical's, whatever the firmware holds it in."""

IMPORTED_BASIS = "imported, not fitted"
"""The basis of an imported calibration's figure: it has no error to tell."""


@dataclass(frozen=True)
class ImportedSensor:
    """One sensor's correction as a firmware holds it.

    Attributes
    ----------
    sensor : {"acc", "gyr", "mag"}
    M : numpy.ndarray, shape (3, 3)
    o : numpy.ndarray, shape (3,)
        ``f = M (m − o)`` with ``m`` and ``o`` in :data:`SENSOR_UNITS` of the sensor.
    firmware_unit : str
        The unit the firmware holds the offset in (``m/s^2``, ``rad/s``, ``mGauss``, ``gauss``, ``counts at
        2048 per g``, …).
    parameters : dict
        The firmware's parameters this correction was made of, by name, as read.
    """

    sensor: str
    M: np.ndarray
    o: np.ndarray
    firmware_unit: str
    parameters: dict = field(default_factory=dict)

    @property
    def unit(self) -> str:
        """The unit of ``o`` and of the readings it corrects."""
        return SENSOR_UNITS[self.sensor]


@dataclass(frozen=True)
class ImportedCalibration(CalibrationResult):
    """A device's own calibration, read from its firmware's parameters (method ``imported``).

    Attributes
    ----------
    sensors : tuple of ImportedSensor
        The accelerometer's, the gyroscope's (a bias: ``M = I``) and the compass's corrections, those the file held.
    firmware : str
        ``ArduPilot``, ``PX4``, ``Betaflight``, ``INAV``.
    version : str or None
        The firmware's version where the file states it.
    file_kind : str
        What was read (``Mission Planner .param``, ``QGroundControl .params``, ``DataFlash log PARM``, …).
    frame : str
        The frame the corrections apply in, in words (the firmwares correct in the sensor's frame, the compass of
        ArduPilot after its rotation into the body frame).
    """

    RESULT_TYPE: ClassVar[str] = "imported"
    MODEL_TYPE: ClassVar[str] = "imported"
    CORRECTION_SOURCE: ClassVar[str] = "the firmware's own parameters, as read (app.io.imports)"
    PER_SENSOR: ClassVar[bool] = True
    EXACT_PARAMETERS: ClassVar[bool] = True

    sensors: tuple[ImportedSensor, ...]
    firmware: str
    version: str | None = None
    file_kind: str = ""
    frame: str = ""
    method: str = "imported"
    gravity: float = STANDARD_GRAVITY
    unit: str = "m/s^2"
    metrics: dict = field(default_factory=dict)
    warnings: tuple = ()
    reasons: tuple = ()

    @classmethod
    def figures_from(cls, metrics: dict, output_unit: str | None) -> tuple[Figure, ...]:
        """No error before or after: the numbers were read, not fitted."""
        return (Figure(basis=IMPORTED_BASIS),)

    def corrections(self) -> dict[str, AffineCorrection]:
        return {
            s.sensor: AffineCorrection(
                np.asarray(s.M, dtype=float),
                np.asarray(s.o, dtype=float),
                s.unit,
                s.unit,
                f"{self.firmware} {self.CORRECTION_SOURCE}",
                s.sensor,
            )
            for s in self.sensors
        }

    def corrected_sensors(self) -> tuple[str, ...]:
        return tuple(s.sensor for s in self.sensors)

    def require_sensor(self, sensor: str | None) -> None:
        """Refuse a sensor the file held no calibration of, naming those it held."""
        held = self.corrected_sensors()
        if sensor is not None and sensor not in held:
            raise CalibrationError(
                f"this imported calibration has no {sensor} model: the file held {', '.join(held)}; send `sensor` as "
                "one of them"
            )

    def apply(self, samples, sensor: str | None = None) -> np.ndarray:
        """Correct raw samples of one sensor (by default the first held) with its ``f = M (m − o)``."""
        self.require_sensor(sensor)
        m = as_samples(samples)
        name = sensor or self.corrected_sensors()[0]
        return self.corrections()[name].apply(m)

    def _calibrate(self, rows: np.ndarray) -> np.ndarray:
        return self.apply(rows)

    @property
    def parameters(self) -> dict:
        """Every parameter read, by name."""
        return {name: value for s in self.sensors for name, value in s.parameters.items()}

    def model_dict(self) -> dict:
        """Each sensor's ``M`` and ``o`` (``acc_M``, ``acc_o``, ``gyr_M``, …): each a small table."""
        out: dict = {}
        for s in self.sensors:
            out[f"{s.sensor}_M"] = np.asarray(s.M, dtype=float).tolist()
            out[f"{s.sensor}_o"] = np.asarray(s.o, dtype=float).tolist()
        return out

    def uncertainty(self) -> dict:
        return {"note": f"{IMPORTED_BASIS}: no intervals"}

    def body_dict(self) -> dict:
        return {
            "read_from": {
                "firmware": self.firmware,
                "version": self.version,
                "file_kind": self.file_kind,
                "frame": self.frame,
                "units": {s.sensor: s.unit for s in self.sensors},
                "firmware_units": {s.sensor: s.firmware_unit for s in self.sensors},
                "parameters": {s.sensor: dict(s.parameters) for s in self.sensors},
            }
        }

    @classmethod
    def _from_body(cls, data: dict) -> ImportedCalibration:
        model = data["model"]
        facts = data.get("read_from") or {}
        units = facts.get("firmware_units") or {}
        params = facts.get("parameters") or {}
        sensors = tuple(
            ImportedSensor(
                name,
                np.asarray(model[f"{name}_M"], dtype=float),
                np.asarray(model[f"{name}_o"], dtype=float),
                units.get(name, SENSOR_UNITS[name]),
                dict(params.get(name) or {}),
            )
            for name in SENSOR_UNITS
            if f"{name}_M" in model
        )
        return cls(
            sensors,
            facts.get("firmware", ""),
            facts.get("version"),
            facts.get("file_kind", ""),
            facts.get("frame", ""),
            method=data.get("method", "imported"),
            gravity=float(data.get("gravity") or STANDARD_GRAVITY),
            unit=data.get("unit", "m/s^2"),
            **gate_fields(data),
        )


def offset_scale_sensor(sensor: str, offset, scale, firmware_unit: str, parameters: dict) -> ImportedSensor:
    """A sensor corrected per axis as the firmwares do, ``f_i = scale_i (m_i − offset_i)``: ``M = diag(scale)``,
    ``o = offset`` (ArduPilot's ``_rotate_and_correct_accel``, PX4's ``Accelerometer::Correct``)."""
    return ImportedSensor(
        sensor,
        np.diag(np.asarray(scale, dtype=float)),
        np.asarray(offset, dtype=float),
        firmware_unit,
        parameters,
    )


def symmetric(diagonal, offdiagonal) -> np.ndarray:
    """The symmetric matrix of a diagonal (xx, yy, zz) and off-diagonal terms (xy, xz, yz), as ArduPilot's
    ``COMPASS_DIA``/``COMPASS_ODI`` and PX4's ``xSCALE``/``xODIAG`` hold a soft iron."""
    d = np.asarray(diagonal, dtype=float)
    xy, xz, yz = (float(v) for v in offdiagonal)
    return np.array([[d[0], xy, xz], [xy, d[1], yz], [xz, yz, d[2]]])
