"""One compass of a flight controller's log with the flight's context (:mod:`.context`), read by its firmware's part:
PX4's (:mod:`.px4`) for a ULog, ArduPilot's (:mod:`.ardupilot`) for a DataFlash log."""

from __future__ import annotations

from ..errors import LogFormatError
from . import dataflash, ulog
from .ardupilot import read_ardupilot
from .context import FlightCompassLog
from .px4 import read_px4


def read_flight_compass(
    path, *, mag_instance: int | None = None, name: str = "the file", attitude: str | None = None
) -> FlightCompassLog:
    """One compass of a PX4 ULog or ArduPilot DataFlash log, raw, with the flight's context.

    Parameters
    ----------
    path : path-like
    mag_instance : int, optional
        The compass instance (default the first the log has).
    name : str
        How messages name the file.
    attitude : str, optional
        The attitude estimate to read: ArduPilot's ATT (default), AHR2, XKF1, NKF1 or EKF1
        (:data:`.ardupilot.ATTITUDE_MESSAGES`); PX4's vehicle_attitude.

    Raises
    ------
    LogFormatError
        Not a flight log, a damaged file, no compass, an instance the log lacks, or a message without a field
        trical needs (named).
    """
    with open(path, "rb") as f:
        head = f.read(16)
    if head.startswith(ulog.MAGIC):
        with dataflash.unknown_layout(name, "a PX4 ULog"):
            return read_px4(path, mag_instance, name, attitude)
    if head.startswith(dataflash.MAGIC):
        with dataflash.unknown_layout(name):
            return read_ardupilot(path, mag_instance, name, attitude)
    raise LogFormatError(
        f"{name} is not a flight controller's log: a compass from a flight reads a PX4 ULog (.ulg) "
        "or an ArduPilot DataFlash log (.bin)"
    )
