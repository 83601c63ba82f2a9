"""PX4's ULog (``.ulg``), read through pyulog: every IMU and compass instance, with its temperature.

Recognised by the file header's magic, ``ULog`` then ``0x01 0x12 0x35`` (PX4 "ULog File Format",
the file header section).  The topics read (their fields as PX4's message definitions give them,
msg/SensorAccel.msg, msg/SensorGyro.msg, msg/SensorMag.msg, msg/SensorCombined.msg):

===================  ================================  ===============  ==========================
topic                fields                            unit             trical's unit
===================  ================================  ===============  ==========================
``sensor_accel``     x, y, z; temperature; device_id   m/s², °C         m/s²
``sensor_gyro``      x, y, z; temperature; device_id   rad/s, °C        rad/s
``sensor_mag``       x, y, z; temperature; device_id   gauss, °C        µT (× 100)
``sensor_combined``  accelerometer_m_s2, gyro_rad      m/s², rad/s      m/s², rad/s
                     magnetometer_ga (PX4 ≤ 1.8)       gauss            µT (× 100)
===================  ================================  ===============  ==========================

Generations: PX4 1.6–1.8 logs (``sample.ulg``) hold ``sensor_combined`` alone, with the compass in it
(``magnetometer_ga``, at ``timestamp + magnetometer_timestamp_relative``); from PX4 1.9 the compass left
``sensor_combined`` for ``vehicle_magnetometer`` (the selected compass, calibrated, body frame), and
``sensor_accel``/``sensor_gyro``/``sensor_mag`` are logged per instance when the profile asks.  Old
``sensor_combined`` compass readings are *calibrated* (the driver applied CAL_MAGn offsets and scales,
the sensors module SENS_BOARD_ROT): trical lists them as instance 0 of source ``sensor_combined`` and says
so; :mod:`app.io.flight.context` reads them back to raw.

Each ``multi_id`` of ``sensor_accel`` (and ``sensor_gyro``, ``sensor_mag``) is an instance.  Their
frame is the *board's* FRD frame (x forward, y right, z down): the driver has turned the chip's axes
onto the board's, and from PX4 1.12 on nothing else — no calibration (offsets, scales), no thermal
correction, no ``SENS_BOARD_ROT`` — is applied, which is what a calibration wants; before 1.12 the
drivers applied the CAL_* offsets and scales (:data:`RAW_SENSORS_FROM`), and a note says so.
``sensor_combined`` is what PX4's estimator uses: the selected IMU already calibrated and turned into
the vehicle's FRD body frame; trical reads it (without temperature) when it has more samples than every
``sensor_accel`` instance (PX4's default logging profile logs ``sensor_accel`` at a low rate) and nothing
else is asked, and says so in a note: its calibration is the residual left by PX4's own.  At rest the axis pointing up
reads +g in both (specific force), as trical's convention has it.
"""

from __future__ import annotations

import contextlib
import functools
import io
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import LogFormatError
from ..log import LogData
from .instances import Stream, choose

if TYPE_CHECKING:  # a type only: the readers' package (read_log) imports this module
    from ..readers.table import Sniff

NAME = "ulog"
MAGIC = b"ULog\x01\x12\x35"
"""The first seven bytes of every ULog file (PX4's ULog file format, "File Header")."""
GAUSS_TO_UT = 100.0
"""1 gauss = 100 µT; PX4's sensor_mag is in gauss (msg/SensorMag.msg)."""
TOPICS = ("sensor_accel", "sensor_gyro", "sensor_mag", "sensor_combined", "vehicle_magnetometer")
CONTEXT_TOPICS = (
    "vehicle_attitude",
    "battery_status",
    "actuator_controls_0",
    "vehicle_thrust_setpoint",
    "vehicle_gps_position",
    "sensor_gps",
    "vehicle_global_position",
)
"""A flight's context the compass from the flight reads (app.io.flight.px4): attitude, power, place."""
SENSOR_OF = {"sensor_accel": ("acc", 1.0), "sensor_gyro": ("gyr", 1.0), "sensor_mag": ("mag", GAUSS_TO_UT)}


RAW_SENSORS_FROM = (1, 12)
"""The first PX4 release whose sensor_accel/sensor_gyro/sensor_mag are raw: before it the drivers (PX4Accelerometer,
PX4Magnetometer …) applied the CAL_* offsets and scales; from it src/lib/sensor_calibration in the sensors module
does.  Seen in sample_log_small.ulg (PX4 1.11.2): its external compass's sensor_mag equals vehicle_magnetometer."""


def release(ulog: Any) -> tuple[int, int] | None:
    """PX4's release (major, minor) from the ``ver_sw_release`` information (0xAABBCCTT), None when not logged."""
    v = ulog.msg_info_dict.get("ver_sw_release")
    return ((int(v) >> 24) & 0xFF, (int(v) >> 16) & 0xFF) if v else None


def release_before(ulog: Any, version: tuple[int, int]) -> bool:
    r = release(ulog)
    return r is not None and r < version


def detect(s: Sniff) -> bool:
    """A file that starts with ULog's magic bytes."""
    return s.head.startswith(MAGIC)


RELATIVE_INVALID = 0x7FFFFFFF
"""sensor_combined's RELATIVE_TIMESTAMP_INVALID: no sample of that sensor in the message (msg/SensorCombined.msg)."""


def combined_mag(data: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray] | None:
    """``(time_us, gauss)`` of the compass inside an old ``sensor_combined`` (PX4 ≤ 1.8), or None."""
    names = [f"magnetometer_ga[{k}]" for k in range(3)]
    if not set(names) <= set(data):
        return None
    time = np.asarray(data["timestamp"], dtype=np.int64)
    rel = np.asarray(data.get("magnetometer_timestamp_relative", np.zeros(len(time))), dtype=np.int64)
    xyz = np.column_stack([data[a] for a in names]).astype(float)
    ok = (rel != RELATIVE_INVALID) & np.isfinite(xyz).all(axis=1)
    t, xyz = time[ok] + rel[ok], xyz[ok]
    keep = np.concatenate([[True], np.diff(t) > 0])  # a compass sample repeats in every message until the next
    return t[keep], xyz[keep]


def _streams(ulog: Any) -> list[Stream]:
    streams = []
    for d in ulog.data_list:
        data = d.data
        if d.name in SENSOR_OF:
            sensor, scale = SENSOR_OF[d.name]
            if not {"x", "y", "z"} <= set(data):
                continue
            time = data.get("timestamp_sample", data["timestamp"])
            temperature = data.get("temperature")
            device = data.get("device_id")
            streams.append(
                Stream(
                    sensor=sensor,
                    instance=int(d.multi_id),
                    source=d.name,
                    time_us=np.asarray(time, dtype=np.int64),
                    xyz=np.column_stack([data[a] for a in "xyz"]).astype(float) * scale,
                    temperature_c=None if temperature is None else np.asarray(temperature, dtype=float),
                    device_id=None if device is None or not len(device) else int(device[-1]),
                )
            )
        elif d.name == "sensor_combined":
            time = np.asarray(data["timestamp"], dtype=np.int64)
            acc = [f"accelerometer_m_s2[{k}]" for k in range(3)]
            gyr = [f"gyro_rad[{k}]" for k in range(3)]
            if set(acc) <= set(data):
                # The accelerometer's own time is the message's plus accelerometer_timestamp_relative
                # (msg/SensorCombined.msg); the gyroscope's is the message's.
                rel = np.asarray(data.get("accelerometer_timestamp_relative", np.zeros(len(time))), dtype=np.int64)
                # A relative time of RELATIVE_TIMESTAMP_INVALID (0x7fffffff) marks no accelerometer sample.
                ok = rel != RELATIVE_INVALID
                streams.append(
                    Stream(
                        "acc",
                        int(d.multi_id),
                        d.name,
                        time[ok] + rel[ok],
                        np.column_stack([data[a] for a in acc])[ok].astype(float),
                    )
                )
            if set(gyr) <= set(data):
                streams.append(
                    Stream("gyr", int(d.multi_id), d.name, time, np.column_stack([data[a] for a in gyr]).astype(float))
                )
            mag = combined_mag(data)
            if mag is not None:
                streams.append(Stream("mag", int(d.multi_id), d.name, mag[0], mag[1] * GAUSS_TO_UT))
    if not any(s.sensor == "mag" and s.n_samples for s in streams):
        streams += _vehicle_magnetometer(ulog)
    return [s for s in streams if s.n_samples]


def _vehicle_magnetometer(ulog: Any) -> list[Stream]:
    """The compasses of ``vehicle_magnetometer`` (calibrated, body frame), for a log whose compass is logged
    nowhere else (PX4 1.9 on, with the default profile): each ``multi_id`` an instance."""
    found = []
    for d in ulog.data_list:
        names = [f"magnetometer_ga[{k}]" for k in range(3)]
        if d.name != "vehicle_magnetometer" or not set(names) <= set(d.data):
            continue
        device = d.data.get("device_id")
        found.append(
            Stream(
                "mag",
                int(d.multi_id),
                d.name,
                np.asarray(d.data.get("timestamp_sample", d.data["timestamp"]), dtype=np.int64),
                np.column_stack([d.data[a] for a in names]).astype(float) * GAUSS_TO_UT,
                device_id=None if device is None or not len(device) else int(device[-1]),
            )
        )
    return found


@functools.lru_cache(maxsize=1)
def _parsed(path: str, size: int, mtime_ns: int) -> tuple[Any, str]:
    """pyulog's parse of a file's :data:`TOPICS` and :data:`CONTEXT_TOPICS`, with what it printed; the last file's
    kept, so that an upload's reading, its GPS fix and the compass from the flight parse it once (a 100 MB log
    takes seconds). Keyed by the file's size and modification time besides its path."""
    from pyulog import ULog  # here: only ULog uploads load it

    said = io.StringIO()
    with contextlib.redirect_stdout(said):  # pyulog prints its warnings; the notes carry them
        ulog = ULog(path, message_name_filter_list=list(TOPICS + CONTEXT_TOPICS), disable_str_exceptions=True)
    return ulog, said.getvalue()


def open_ulog(path: Path | str, name: str, remedy: str) -> tuple[Any, str]:
    """``(ulog, printed)``: the file parsed (:func:`_parsed`); a file pyulog cannot parse is refused with ``remedy``.

    Raises
    ------
    LogFormatError
    """
    resolved = Path(path).resolve()
    stat = resolved.stat()
    try:
        return _parsed(str(resolved), stat.st_size, stat.st_mtime_ns)
    except Exception as exc:  # pyulog raises many kinds on a damaged file
        raise LogFormatError(
            f"{name} starts as a PX4 ULog but cannot be read ({type(exc).__name__}: {exc}): the "
            f"file is damaged or cut short in its definitions; {remedy}"
        ) from None


def read(
    path: Path,
    s: Sniff,
    *,
    instance: int | None = None,
    mag_instance: int | None = None,
    clock: str = "imu",
    name: str = "the file",
) -> LogData:
    """Read the IMU instance ``instance`` (and compass ``mag_instance``) of a ULog file.

    Parameters
    ----------
    path : pathlib.Path
        The log.
    s : Sniff
        Its head (its magic: already checked).
    instance : int, optional
        The IMU instance read (default: the source with the most samples).
    mag_instance : int, optional
        The compass instance read (default the first).
    clock : {"imu", "mag"}
        The samples on the IMU's times, or on the compass's with the IMU interpolated onto them
        (:func:`app.io.flight.instances.choose`).
    name : str
        How to call the file in messages.

    Returns
    -------
    LogData
        The chosen sensors on one clock, ``flight`` listing every instance, ``format`` ``ulog``.

    Raises
    ------
    LogFormatError
        A file pyulog cannot parse, one without IMU samples, or an instance the log does not have.
    """
    ulog, said = open_ulog(
        path, name, "download the log again from the vehicle (QGroundControl, Analyze Tools > Log Download)"
    )
    notes = []
    if ulog.file_corruption or "corrupt" in said.lower():
        notes.append(
            f"{name}: pyulog found damaged data in the file and skipped it; the samples read are those it could parse"
        )
    streams = _streams(ulog)
    if not streams:
        raise LogFormatError(
            f"{name} is a PX4 ULog without IMU samples (no sensor_accel, sensor_gyro, sensor_mag or "
            "sensor_combined data; the file may be cut short): log the sensors (SDLOG_PROFILE with "
            "'Sensor comparison' or 'High rate', or the topics in etc/logging/logger_topics.txt)"
        )
    default = None
    if instance is None:  # the source with the most samples: PX4's default profile logs sensor_accel slowly
        accs = [x for x in streams if x.sensor == "acc"]
        default = max(accs, key=lambda x: (x.n_samples, x.source == "sensor_accel", -x.instance)) if accs else None
    if default is not None and default.source == "sensor_combined":
        raw = [x for x in streams if x.source == "sensor_accel"]
        notes.append(
            "read sensor_combined, the IMU PX4's estimator uses, already calibrated by PX4 and turned into "
            "the vehicle's body frame (FRD)"
            + (
                f": it has more samples ({default.n_samples}) than any "
                f"sensor_accel instance ({max(x.n_samples for x in raw)}); give instance for one of those"
                if raw
                else "; the log has no sensor_accel"
            )
            + ". Its calibration is what is left over PX4's own"
        )
    elif release_before(ulog, RAW_SENSORS_FROM):
        notes.append(
            "PX4 sensor_accel/sensor_gyro/sensor_mag of a release before 1.12: the board's FRD frame, after "
            "the driver's own calibration (CAL_ACCn/CAL_GYROn/CAL_MAGn offsets and scales), before "
            "SENS_BOARD_ROT: a calibration from them is what is left over PX4's"
        )
    else:
        notes.append(
            "PX4 sensor_accel/sensor_gyro/sensor_mag: the board's FRD frame (x forward, y right, z down), "
            "before PX4's calibration and SENS_BOARD_ROT"
        )
    if any(x.sensor == "mag" and x.source == "sensor_combined" for x in streams):
        notes.append(
            "the compass of sensor_combined (PX4 1.8 and before) is logged after PX4's calibration (CAL_MAGn "
            "offsets and scales) in the body frame: a calibration from it is what is left over PX4's"
        )
    if any(x.sensor == "mag" and x.source == "vehicle_magnetometer" for x in streams):
        notes.append(
            "the log's only compass readings are vehicle_magnetometer's, logged after PX4's calibration (CAL_MAGn "
            "offsets and scales) in the body frame: a calibration from them is what is left over PX4's; the "
            "compass from this flight reads them back to raw with the stored calibration"
        )
    log = choose(
        streams,
        fmt=NAME,
        imu_sources=("sensor_accel", "sensor_combined"),
        gyr_for={"sensor_accel": "sensor_gyro", "sensor_combined": "sensor_combined"},
        mag_sources=("sensor_mag", "sensor_combined", "vehicle_magnetometer"),
        instance=instance,
        mag_instance=mag_instance,
        clock=clock,
        default_imu=default,
        notes=notes,
        name=name,
    )
    return log
