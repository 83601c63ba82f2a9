"""How to read a log: the reader's options (:class:`ReadOptions`), given once by the upload, the command line or a
stored recording, and passed whole to :func:`app.io.readers.read_log`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class ReadOptions:
    """The options :func:`app.io.readers.read_log` reads a log with; each default lets the file decide.

    Attributes
    ----------
    format : str
        One of :data:`app.io.readers.FORMATS`; ``auto`` detects it from the header.
    sampling_rate_hz : float, optional
        Required when the file has no time column; overrides the rate the time column gives.
    units : dict, optional
        Units per sensor (``{"acc": "g"}``), overriding what the format and the data say.
    lsb_per_g : float, optional
        Sensitivity of an accelerometer read in counts: readings are divided by it into g.  A
        comment ``# lsb_per_g=16384`` in the file gives it too.
    columns : str, dict or list, optional
        Column mapping of a CSV whose header trical does not recognise, ``"acc_x:north,acc_y:east,
        acc_z:down,time_ms:t"``, or one name per column, ``"t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z"``
        (a table without a header row, or instead of its header row; :func:`app.io.readers.parse_columns`);
        the file is then read as a generic (or Arduino) CSV.
    sign : {1, -1}, optional
        Factor on the file's accelerations (−1 for Core Motion's sign); detected when None
        (:mod:`app.io.readers.ios_sign`).
    chip : str or list of str, optional
        The parts and ranges of the file's sensors in counts, separated by commas or listed (``mpu6050-4g,
        ak8963-16bit``; :data:`app.io.readers.chips.CHIPS`): their counts become g, °/s and µT.
    instance, mag_instance : int, optional
        A flight controller's log (:data:`app.io.readers.FLIGHT_FORMATS`): the IMU instance read (default:
        PX4 the source with the most samples, ArduPilot the first) and the compass instance (default the
        first); an instance the log lacks is refused naming those it has.
    clock : {"imu", "mag"}
        A flight controller's log: the samples on the IMU's times (no compass), or on the compass's
        with the IMU interpolated onto them (what the compass methods read; :mod:`app.io.flight.instances`).
    """

    format: str = "auto"
    sampling_rate_hz: float | None = None
    units: dict[str, str] | None = None
    lsb_per_g: float | None = None
    columns: str | dict[str, str] | list[str] | None = None
    sign: int | None = None
    chip: str | list[str] | None = None
    instance: int | None = None
    mag_instance: int | None = None
    clock: str = "imu"

    def stored(self, sign: int) -> dict[str, object]:
        """The plain form kept with a recording (its ``read_with``, docs/rest.md), with the ``sign`` the reader
        applied, so that the stored file is read again the same way; the clock is the reader's choice of the
        moment, not the recording's, and is not kept."""
        return {
            "format": self.format,
            "units": self.units or {},
            "lsb_per_g": self.lsb_per_g,
            "columns": self.columns,
            "chip": self.chip,
            "sampling_rate_hz": self.sampling_rate_hz,
            "instance": self.instance,
            "mag_instance": self.mag_instance,
            "sign": sign,
        }

    # Any: the body is read back from a recording's stored JSON, its values of the fields' several types.
    @classmethod
    def from_stored(cls, read_with: dict[str, Any]) -> ReadOptions:
        """The options of a recording's stored ``read_with`` (:meth:`stored`; bodies stored before it give only
        some of its keys, the others keep their defaults)."""
        return cls(**read_with)


UPLOAD_FIELDS = {
    "text": ("format", "sampling_rate_hz", "acc_unit", "gyr_unit", "mag_unit", "lsb_per_g", "columns", "sign", "chip"),
    "array": ("format", "sampling_rate_hz", "acc_unit", "gyr_unit", "mag_unit", "sign"),
    "flight": ("format", "sampling_rate_hz", "instance", "mag_instance"),
}
"""The fields of the upload (``trical``'s options of the same names) that change how a log of each family is read:
a text log (CSV, a phone app's export, JSON samples, a zip of them) takes them all but a flight log's instances; an
array (``.npy``, Parquet, a wearable's binary) its unit, rate and sign (its samples are not counts); a flight
controller's log (PX4 ULog, ArduPilot DataFlash) states its units, frame and columns, so only which IMU and which
compass to read (app.io.readers.plan_read refuses the others). A message's remedy names only these
(tests/api/test_remedies.py)."""


def units_named(acc: str | None, gyr: str | None, mag: str | None) -> dict[str, str]:
    """The units a caller named, by sensor (``ReadOptions.units``): the upload's ``acc_unit``, ``gyr_unit``,
    ``mag_unit``, ``trical calibrate``'s ``--unit``, ``--gyr-unit``, ``--mag-unit``; a sensor not named is left out."""
    return {sensor: unit for sensor, unit in (("acc", acc), ("gyr", gyr), ("mag", mag)) if unit}
