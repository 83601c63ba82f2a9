"""The in-memory form of a sensor log, whatever file it came from."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal, get_args

import numpy as np

from app.calibration.shared.gravity import STANDARD_GRAVITY

if TYPE_CHECKING:  # the readers' package imports this module
    from .flight.instances import FlightInfo
    from .readers.timing import Timing

AccUnit = Literal["m/s^2", "g", "raw"]
AccPhysicalUnit = Literal["m/s^2", "g"]
GyrPhysicalUnit = Literal["rad/s", "deg/s"]
"""The gyroscope's units of a physical scale (a page's capture of a phone's or a board's rotation rate)."""

UNITS: dict[str, tuple[str, ...]] = {
    "acc": get_args(AccUnit),
    "gyr": (*get_args(GyrPhysicalUnit), "raw"),
    "mag": ("uT", "nT", "raw"),
}
"""Accepted units per sensor; the first is the default when neither header nor caller names one."""

UNITS_IN: dict[str, tuple[str, ...]] = {**UNITS, "mag": ("uT", "nT", "gauss", "raw")}
"""The units a caller or a header may name per sensor (the upload's ``acc_unit``, ``gyr_unit``, ``mag_unit``;
``trical calibrate``'s ``--unit``, ``--gyr-unit``, ``--mag-unit``): :data:`UNITS`, and a magnetometer's gauss,
which becomes µT on reading (app.io.readers.units)."""

ACC_PHYSICAL_UNITS: tuple[str, ...] = get_args(AccPhysicalUnit)
"""The accelerometer's units of a physical scale (counts, ``raw``, are not): what gravity is told in, what a
firmware's driver gives, what a wearable's recording is auto-calibrated in."""

SI_UNITS = {"acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}
"""The unit each sensor is calibrated or characterised in when its log's unit is converted (Kalibr's, the
firmwares'); µT for the magnetometer."""
ACC_TO_M_S2 = {"m/s^2": 1.0, "g": STANDARD_GRAVITY, "raw": 1.0}
GYR_TO_RAD_S = {"rad/s": 1.0, "deg/s": math.pi / 180.0, "raw": 1.0}
MAG_TO_UT = {"uT": 1.0, "nT": 1e-3, "raw": 1.0}
TO_SI = {"acc": ACC_TO_M_S2, "gyr": GYR_TO_RAD_S, "mag": MAG_TO_UT}
"""The factor from each unit of :data:`UNITS` to :data:`SI_UNITS` (counts, ``raw``, stay counts: 1)."""


@dataclass(frozen=True)
class LogData:
    """Samples of one recording.

    Attributes
    ----------
    acc : numpy.ndarray of shape (N, 3), or None
        Accelerometer specific force in ``units["acc"]``; None in a log of other sensors only (a
        magnetometer turned for a compass calibration).
    gyr, mag : numpy.ndarray or None
        Gyroscope and magnetometer samples, when present.
    time_s : numpy.ndarray or None
        Seconds since the first sample, when the file had a time column.
    sampling_rate_hz : float or None
        The sensor's rate (:mod:`app.io.readers.timing`); None when neither the caller nor the file
        gives one (a file of still poses or a compass turn without a time column).
    units : dict
        Unit per present sensor.
    format : str
        Reader that produced it (``csv``...).
    columns : list of str
        The file's column names, for messages.
    notes : tuple of str
        What the reader decided on the way (sign flipped, unit inferred, file chosen in a zip).
    warnings : tuple of str
        What the reader decided against what the caller or the file said (a unit the data
        contradict), and sensors left in counts: every calibration of the log repeats them.
    timing : Timing or None
        How the rate was decided: its source, the time column's jitter and gaps.
    temperature_c : numpy.ndarray of shape (N,), or None
        The sensor's own temperature in °C at each sample, when the log records it (a flight
        controller's IMU, a ``temp_c`` column): what a temperature calibration fits against.
    questions : tuple of dict
        What the data leave open and a calibration's figures hang on (``{"sensor": "gyr", "detail":
        ...}``: a gyroscope's unit neither the data nor anyone said): a calibration of that sensor is
        not ok, and its reasons ask.
    scales : dict or None
        How the file's numbers became each sensor's unit, where they were not in it (``{"mag": {"op": "*",
        "value": 100.0, "words": "100 µT per gauss", "read_in": "gauss"}}``: counts of a part, counts per g,
        gauss); a sensor absent from
        it was read in its unit. None where the reader states its units (a flight log, an array): no board's
        driver gives its numbers. What a snippet scales a driver's readings by (app.io.exports.snippets).
    flight : app.io.flight.instances.FlightInfo or None
        A flight controller's log (PX4 ULog, ArduPilot DataFlash): every sensor instance it holds, the
        IMU and compass read, and the clock the samples are on; None for other logs.
    sign : int
        The factor the file's accelerations were multiplied by on reading: −1 when they came on the
        iOS Core Motion sign (−g on the up axis) and were negated, +1 otherwise.
    parts : tuple of app.io.readers.parts.Part
        A recording made of several files (one per pose): each file's name and its samples; empty
        for a recording of one file.
    """

    acc: np.ndarray | None
    gyr: np.ndarray | None
    mag: np.ndarray | None
    time_s: np.ndarray | None
    sampling_rate_hz: float | None
    units: dict
    format: str
    columns: list
    notes: tuple = ()
    sign: int = 1
    warnings: tuple = ()
    parts: tuple = ()
    timing: Timing | None = None
    temperature_c: np.ndarray | None = None
    flight: FlightInfo | None = None
    questions: tuple = ()
    scales: dict | None = None

    @property
    def gaps(self) -> tuple:
        """Where samples were lost (:class:`app.io.readers.timing.Gap`), from the time column."""
        return () if self.timing is None else self.timing.gaps

    @property
    def n_samples(self) -> int:
        return int(getattr(self, self.channels[0]).shape[0])

    @property
    def channels(self) -> list[str]:
        return [s for s in ("acc", "gyr", "mag") if getattr(self, s) is not None]

    def stacked(self) -> np.ndarray:
        """All present sensors side by side, shape (N, 3·channels), for storage."""
        return np.hstack([getattr(self, s) for s in self.channels])
