"""What the two flight controllers' log readers share: sensor streams, the instance chosen, one clock.

A flight controller logs every IMU and compass it has, each as its own *instance* (PX4's ``multi_id``,
ArduPilot's ``I`` field or the ``IMU2``/``MAG2`` names of older logs), each at its own rate and on
its own timestamps.  The readers (:mod:`.ulog`, :mod:`.dataflash`) turn them into :class:`Stream`
objects — a sensor's samples with their times in µs, its temperature and device id — and
:func:`build_log` makes one :class:`~app.io.log.LogData` of the chosen ones:

- ``clock="imu"`` (what an upload reads): the accelerometer of the chosen IMU instance on its own
  timestamps; its gyroscope (the same instance) interpolated linearly onto them when the two are
  logged apart (PX4's ``sensor_gyro``, ArduPilot's ``GYR``); the accelerometer's temperature.  No
  compass: it is slower, and sampled onto the IMU's clock it would repeat or invent readings.
- ``clock="mag"`` (what the compass methods read): the chosen compass's samples on their own
  timestamps, and the IMU's accelerometer and gyroscope interpolated onto them, so that the compass's
  rests (the board still) are found as in any log.

The instances of every sensor (:func:`describe_streams`) go with the log (``LogData.flight``) so that
the overview lists them.  A bad instance number is refused naming those the log has.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, NoReturn

import numpy as np

from ..errors import LogFormatError
from ..log import LogData

CLOCKS = ("imu", "mag")


@dataclass(frozen=True)
class Stream:
    """One sensor instance's samples as the log holds them, in trical's units.

    Attributes
    ----------
    sensor : {"acc", "gyr", "mag"}
    instance : int
        The firmware's instance number.
    source : str
        The message (topic) it came from: ``sensor_accel``, ``IMU``, ``ACC``, ``sensor_combined`` …
    time_us : numpy.ndarray of shape (N,)
        The sample times in µs on the controller's clock.
    xyz : numpy.ndarray of shape (N, 3)
        m/s², rad/s or µT.
    temperature_c : numpy.ndarray of shape (N,), or None
    device_id : int or None
        The firmware's device id (bus type, bus, address, device type packed in 32 bits).
    """

    sensor: str
    instance: int
    source: str
    time_us: np.ndarray
    xyz: np.ndarray
    temperature_c: np.ndarray | None = None
    device_id: int | None = None

    @property
    def n_samples(self) -> int:
        return int(len(self.time_us))

    @property
    def rate_hz(self) -> float | None:
        """(N − 1) over the span, as :mod:`.timing` takes a rate."""
        if len(self.time_us) < 2 or self.time_us[-1] <= self.time_us[0]:
            return None
        return float((len(self.time_us) - 1) / ((self.time_us[-1] - self.time_us[0]) * 1e-6))


@dataclass(frozen=True)
class FlightInfo:
    """What a flight log holds and what was read of it (``LogData.flight``).

    Attributes
    ----------
    instances : tuple of dict
        Every sensor instance of the log (:func:`describe_streams`).
    imu : dict
        The IMU read: ``{"instance", "source", "gyr_source"}``; empty for a log without IMU samples.
    mag : dict or None
        The compass read (clock ``mag``), or the one the compass methods would read.
    clock : str
        ``imu`` or ``mag`` (see the module's docstring).
    """

    instances: tuple[dict[str, Any], ...] = ()
    imu: dict[str, Any] = field(default_factory=dict)
    mag: dict[str, Any] | None = None
    clock: str = "imu"

    def to_dict(self) -> dict[str, Any]:
        return {
            "instances": [dict(i) for i in self.instances],
            "imu": dict(self.imu),
            "mag": None if self.mag is None else dict(self.mag),
            "clock": self.clock,
        }


BUS_TYPES = {0: "unknown", 1: "i2c", 2: "spi", 3: "uavcan", 4: "simulation", 5: "serial", 6: "mavlink"}
"""The bus types of the device id, as PX4's ``device::Device::DeviceBusType`` (src/lib/drivers/device/Device.hpp)
and ArduPilot's ``AP_HAL::Device::BusType`` (libraries/AP_HAL/Device.h) number them."""


def decode_device_id(device_id: int | None) -> dict[str, Any] | None:
    """The fields packed in a device id: bus type (bits 0–2), bus (3–7), address (8–15), device type (16–23).

    The layout of PX4's ``device::Device::DeviceStructure`` (src/lib/drivers/device/Device.hpp) and
    ArduPilot's ``AP_HAL::Device::DeviceStructure`` (libraries/AP_HAL/Device.h), the same in both.
    """
    if not device_id:
        return None
    d = int(device_id)
    bus_type = d & 0x7
    return {
        "bus_type": BUS_TYPES.get(bus_type, str(bus_type)),
        "bus": (d >> 3) & 0x1F,
        "address": (d >> 8) & 0xFF,
        "devtype": (d >> 16) & 0xFF,
    }


def describe_streams(streams: list[Stream]) -> tuple[dict[str, Any], ...]:
    """One line per sensor instance: sensor, instance, source, device id, samples, rate, temperature range."""
    rows = []
    for s in sorted(streams, key=lambda s: (["acc", "gyr", "mag"].index(s.sensor), s.source, s.instance)):
        temp = s.temperature_c[np.isfinite(s.temperature_c)] if s.temperature_c is not None else np.array([])
        rate = s.rate_hz
        rows.append(
            {
                "sensor": s.sensor,
                "instance": s.instance,
                "source": s.source,
                "device_id": s.device_id,
                "device": decode_device_id(s.device_id),
                "n_samples": s.n_samples,
                "sampling_rate_hz": None if rate is None else round(rate, 6),
                "temperature_min_c": float(temp.min()) if temp.size else None,
                "temperature_max_c": float(temp.max()) if temp.size else None,
            }
        )
    return tuple(rows)


def _numbers(streams: list[Stream], sensor: str) -> list[int]:
    return sorted({s.instance for s in streams if s.sensor == sensor})


def _refuse_instance(what: str, wanted: int, have: list[int], option: str, name: str, extra: str = "") -> NoReturn:
    if not have:  # nothing to choose from: the remedy is to leave the choice out
        raise LogFormatError(
            f"{name} holds no {what}{extra}, so there is no {what} {wanted} to read: leave {option} out"
        )
    listed = ", ".join(str(i) for i in have)
    raise LogFormatError(
        f"{name} has no {what} instance {wanted}: its {what} instances are {listed}{extra}; give "
        f"{option} as one of them (or leave it out for the default)"
    )


def pick(streams: list[Stream], sensor: str, instance: int, preferred: tuple[str, ...]) -> Stream | None:
    """The stream of ``sensor`` and ``instance`` from the first source in ``preferred`` that has it."""
    for source in preferred:
        for s in streams:
            if s.sensor == sensor and s.instance == instance and s.source == source and s.n_samples:
                return s
    return None


def _onto(t_target: np.ndarray, s: Stream) -> np.ndarray:
    """``s``'s samples interpolated linearly onto the times ``t_target`` (inside its span)."""
    t = s.time_us.astype(float)
    return np.column_stack([np.interp(t_target, t, s.xyz[:, k]) for k in range(3)])


def _overlap(target: Stream, others: list[Stream]) -> np.ndarray:
    """The indices of ``target``'s samples inside the span of every other stream."""
    keep = np.ones(target.n_samples, dtype=bool)
    for o in others:
        keep &= (target.time_us >= o.time_us[0]) & (target.time_us <= o.time_us[-1])
    return np.flatnonzero(keep)


def build_log(
    streams: list[Stream],
    *,
    fmt: str,
    imu: Stream,
    gyr: Stream | None,
    mag: Stream | None,
    clock: str,
    notes: list[str],
    name: str,
) -> LogData:
    """One :class:`LogData` of the chosen streams on the clock asked (see the module's docstring)."""
    if clock not in CLOCKS:
        raise LogFormatError(f"unknown clock {clock!r}: use one of {', '.join(CLOCKS)}")
    notes = list(notes)
    imu_info = {"instance": imu.instance, "source": imu.source, "gyr_source": None if gyr is None else gyr.source}
    mag_info = None if mag is None else {"instance": mag.instance, "source": mag.source}
    if clock == "mag":
        if mag is None:
            raise LogFormatError(
                f"{name} has no magnetometer samples: the compass methods need a log that "
                "recorded the compass (PX4 sensor_mag, ArduPilot MAG)"
            )
        others = [imu] + ([gyr] if gyr is not None and gyr is not imu else [])
        idx = _overlap(mag, others)
        if len(idx) < 2:
            raise LogFormatError(f"{name}: the compass's samples do not overlap the IMU's in time: record both")
        t = mag.time_us[idx].astype(float)
        acc = _onto(t, imu)
        gyro = None if gyr is None else _onto(t, gyr)
        mags = mag.xyz[idx]
        temperature = None if mag.temperature_c is None else mag.temperature_c[idx]
        notes.append(
            f"the compass {mag.source} instance {mag.instance} on its own clock ({mag.n_samples} samples), "
            f"with the accelerometer ({imu.source} instance {imu.instance}) interpolated onto its times"
        )
        time_us = mag.time_us[idx]
    else:
        acc, mags = imu.xyz, None
        time_us = imu.time_us
        temperature = imu.temperature_c
        gyro = None
        if gyr is not None:
            if gyr is imu or (gyr.n_samples == imu.n_samples and np.array_equal(gyr.time_us, imu.time_us)):
                gyro = gyr.xyz
            else:
                idx = _overlap(imu, [gyr])
                if len(idx) < 2:
                    raise LogFormatError(
                        f"{name}: the gyroscope's samples do not overlap the accelerometer's in time: record both"
                    )
                time_us, acc = imu.time_us[idx], imu.xyz[idx]
                temperature = None if temperature is None else temperature[idx]
                gyro = _onto(time_us.astype(float), gyr)
                notes.append(
                    f"the gyroscope ({gyr.source} instance {gyr.instance}) interpolated onto the "
                    f"accelerometer's times ({imu.source} instance {imu.instance})"
                )
        if mag is not None:
            notes.append(
                f"the compass ({mag.source} instance {mag.instance}, {mag.n_samples} samples) is read on its "
                "own clock by the compass methods (magnetometer, noise of mag)"
            )
    t0 = int(time_us[0])
    time_s = (np.asarray(time_us, dtype=np.int64) - t0) * 1e-6
    units = {"acc": "m/s^2"}
    if gyro is not None:
        units["gyr"] = "rad/s"
    if mags is not None:
        units["mag"] = "uT"
    if temperature is not None and not np.isfinite(temperature).any():
        temperature = None
    return LogData(
        acc=np.asarray(acc, dtype=float),
        gyr=None if gyro is None else np.asarray(gyro, dtype=float),
        mag=None if mags is None else np.asarray(mags, dtype=float),
        time_s=time_s,
        sampling_rate_hz=None,
        units=units,
        format=fmt,
        columns=[],
        notes=tuple(notes),
        temperature_c=None if temperature is None else np.asarray(temperature, float),
        flight=FlightInfo(instances=describe_streams(streams), imu=imu_info, mag=mag_info, clock=clock),
    )


def compass_only_log(streams: list[Stream], mag: Stream, *, fmt: str, notes: list[str]) -> LogData:
    """A flight log without IMU samples as a recording of its compass ``mag`` alone, on the compass's clock:
    what needs no IMU (the compass from the flight, a compass turn, the compass's noise) reads it."""
    notes = list(notes) + [
        f"the log holds no IMU samples: read for what needs none, its compass ({mag.source} instance "
        f"{mag.instance}, {mag.n_samples} samples) on its own clock; the accelerometer's and gyroscope's "
        "calibrations need the IMU logged (PX4 SDLOG_PROFILE, ArduPilot LOG_BITMASK IMU)"
    ]
    t0 = int(mag.time_us[0])
    return LogData(
        acc=None,
        gyr=None,
        mag=np.asarray(mag.xyz, dtype=float),
        time_s=(mag.time_us.astype(np.int64) - t0) * 1e-6,
        sampling_rate_hz=None,
        units={"mag": "uT"},
        format=fmt,
        columns=[],
        notes=tuple(notes),
        temperature_c=None if mag.temperature_c is None else np.asarray(mag.temperature_c, float),
        flight=FlightInfo(
            instances=describe_streams(streams),
            imu={},
            mag={"instance": mag.instance, "source": mag.source},
            clock="mag",
        ),
    )


def choose(
    streams: list[Stream],
    *,
    fmt: str,
    imu_sources: tuple[str, ...],
    gyr_for: dict[str, str],
    mag_sources: tuple[str, ...],
    instance: int | None,
    mag_instance: int | None,
    clock: str,
    default_imu: Stream | None,
    notes: list[str],
    name: str,
) -> LogData:
    """Pick the IMU and compass instances asked (or the defaults) and build the log.

    ``imu_sources`` (and ``mag_sources``) list the messages of each sensor by preference: ArduPilot's
    batch sampler (``ACC``) at full rate before ``IMU``; ``gyr_for`` names the gyroscope's message
    that goes with each accelerometer's (``sensor_accel`` → ``sensor_gyro``, ``ACC`` → ``GYR``), the
    other gyroscope messages of the same instance coming next.  ``default_imu`` is
    the accelerometer read when no instance is given.
    """
    accs = _numbers(streams, "acc")
    mags = _numbers(streams, "mag")
    if not accs and not mags:
        raise LogFormatError(
            f"{name} holds neither accelerometer nor compass samples (PX4 sensor_accel, sensor_combined or "
            "sensor_mag, ArduPilot IMU, ACC or MAG): log the sensors (PX4 SDLOG_PROFILE, ArduPilot LOG_BITMASK "
            "IMU and COMPASS)"
        )
    if not accs:  # a minimal log (attitude, compass, GPS): read for what needs no IMU
        if instance is not None:
            _refuse_instance("IMU", instance, accs, "instance", name)
        wanted = mags[0] if mag_instance is None else mag_instance
        mag = pick(streams, "mag", wanted, mag_sources)
        if mag is None:
            _refuse_instance("magnetometer", wanted, mags, "mag_instance", name)
        assert mag is not None, "the compass asked has a stream"
        return compass_only_log(streams, mag, fmt=fmt, notes=notes)
    if instance is None:
        imu = default_imu or pick(streams, "acc", accs[0], imu_sources)
    else:
        imu = pick(streams, "acc", instance, imu_sources)
        if imu is None:
            _refuse_instance("IMU", instance, accs, "instance", name)
    assert imu is not None, "the first accelerometer instance has a stream"
    gyr = pick(streams, "gyr", imu.instance, (gyr_for[imu.source],) + tuple(v for v in gyr_for.values()))
    if mag_instance is None:
        mag = pick(streams, "mag", mags[0], mag_sources) if mags else None
    else:
        mag = pick(streams, "mag", mag_instance, mag_sources)
        if mag is None:
            _refuse_instance("magnetometer", mag_instance, mags, "mag_instance", name)
    return build_log(streams, fmt=fmt, imu=imu, gyr=gyr, mag=mag, clock=clock, notes=notes, name=name)
