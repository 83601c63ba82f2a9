"""The in-memory form of a sensor log, whatever file it came from."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

UNITS: dict[str, tuple[str, ...]] = {
    "acc": ("m/s^2", "g", "raw"),
    "gyr": ("rad/s", "deg/s", "raw"),
    "mag": ("uT", "nT", "raw"),
}
"""Accepted units per sensor; the first is the default when neither header nor caller names one."""


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
    sampling_rate_hz : float
    units : dict
        Unit per present sensor.
    format : str
        Reader that produced it (``csv``...).
    columns : list of str
        The file's column names, for messages.
    notes : tuple of str
        What the reader decided on the way (sign flipped, unit inferred, file chosen in a zip).
    sign : int
        The factor the file's accelerations were multiplied by on reading: −1 when they came on the
        iOS Core Motion sign (−g on the up axis) and were negated, +1 otherwise.
    parts : tuple of app.io.parts.Part
        A recording made of several files (one per pose): each file's name and its samples; empty
        for a recording of one file.
    """

    acc: np.ndarray | None
    gyr: np.ndarray | None
    mag: np.ndarray | None
    time_s: np.ndarray | None
    sampling_rate_hz: float
    units: dict
    format: str
    columns: list
    notes: tuple = ()
    sign: int = 1
    parts: tuple = ()

    @property
    def n_samples(self) -> int:
        return int(getattr(self, self.channels[0]).shape[0])

    @property
    def channels(self) -> list[str]:
        return [s for s in ("acc", "gyr", "mag") if getattr(self, s) is not None]

    def stacked(self) -> np.ndarray:
        """All present sensors side by side, shape (N, 3·channels), for storage."""
        return np.hstack([getattr(self, s) for s in self.channels])
