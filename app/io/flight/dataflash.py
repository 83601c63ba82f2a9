"""ArduPilot's DataFlash logs (``.bin``), read through pymavlink's DFReader: IMU and compass instances.

Recognised by the first message: the message header ``0xA3 0x95`` and the type of FMT, ``0x80``
(ArduPilot's DataFlash format: every message starts with those two bytes and its type, and the
log starts by describing its messages with FMT).  pymavlink's ``DFReader_binary`` parses the FMT
messages and indexes where every message is; trical then takes the columns of the few messages it
needs at once with numpy (the formats' struct codes), rather than message by message.

Messages and units, as ArduPilot's message definitions give them
(libraries/AP_InertialSensor/LogStructure.h, libraries/AP_Compass/LogStructure.h, and
libraries/AP_Logger/LogStructure.h for logs before the ``I`` field):

=========================  ===========================  ======================  ==============
message                    fields                       unit                    trical's unit
=========================  ===========================  ======================  ==============
``IMU`` (``IMU2``, …)      I; AccX…Z; GyrX…Z; T/Temp    m/s², rad/s, °C         m/s², rad/s
``ACC``, ``GYR``           I; SampleUS; AccX… / GyrX…   m/s², rad/s             m/s², rad/s
(``ACC1``…, ``GYR1``…)
``MAG`` (``MAG2``, …)      I; MagX, MagY, MagZ          milligauss              µT (× 0.1)
=========================  ===========================  ======================  ==============

``ACC``/``GYR`` are the batch sampler's (``INS_LOG_BAT_MASK``) samples at the sensor's full rate;
when the log has them for the instance they are read in place of ``IMU`` (whose ``T`` is then
interpolated onto their times).  Frame: ArduPilot's body frame (x forward, y right, z down) after
``AHRS_ORIENTATION``; ``IMU`` and ``MAG`` are logged after ArduPilot's own calibration (the
accelerometer's offsets and scales, the compass's offsets ``OfsX…`` and scale factors), so a
calibration from them is what is left over ArduPilot's; a note says so.  At rest the axis pointing up
reads +g (specific force), as trical's convention has it.

Generations (what changes between ArduPilot's releases, and how trical reads each):

==========================  ===========================================  ======================================
what                        older logs (e.g. Copter 3.3, 2015)           newer logs
==========================  ===========================================  ======================================
the clock                   ``TimeMS`` (ms since boot, uint32)           ``TimeUS`` (µs since boot, uint64)
IMU temperature             ``Temp``                                     ``T``
instances                   ``IMU2``, ``IMU3``, ``MAG2``, ``MAG3``       one message with the ``I`` field
                            (instances 1, 2)                             (named by FMTU's ``#`` unit when logged)
units, multipliers          the format letters only (``c`` ×0.01,        the letters, and FMTU/UNIT/MULT naming
                            ``L`` ×1e-7 …)                               each field's unit
==========================  ===========================================  ======================================

pymavlink's DFReader applies the multipliers of the format letters (``c``, ``C``, ``e``, ``E`` ×0.01,
``L`` ×1e-7: ``DFFormat.msg_mults``) and trical takes them as it does; FMTU's multipliers are not applied
by DFReader (``DFFormat.set_mult_ids`` only names the unit), and trical applies none either: the units of
the fields it reads are fixed per message above.  When FMTU marks a field as the instance (unit ``#``),
that field splits the message into instances.  A message trical reads that lacks the field it needs
is refused naming the message and the field (never "damaged": pymavlink read the file).
"""

from __future__ import annotations

import contextlib
import io
import re
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import LogFormatError
from ..log import LogData
from .instances import Stream, choose

if TYPE_CHECKING:  # a type only: the readers' package (read_log) imports this module
    from ..readers.table import Sniff

NAME = "dataflash"
MAGIC = b"\xa3\x95\x80"
"""The message header of DataFlash (0xA3 0x95) and the type of its first message, FMT (0x80)."""
MILLIGAUSS_TO_UT = 0.1
"""MAG's MagX… are in milligauss (libraries/AP_Compass/LogStructure.h: unit G, multiplier C = 1e-3)."""
GATHER_ROWS = 65_536
"""Messages copied out of the file per numpy gather."""
STRUCT_TO_NUMPY = {
    "b": "i1",
    "B": "u1",
    "h": "<i2",
    "H": "<u2",
    "i": "<i4",
    "I": "<u4",
    "q": "<i8",
    "Q": "<u8",
    "f": "<f4",
    "d": "<f8",
    "s": "S",
}
DEVICE_PARAMS = {
    "acc": ("INS_ACC_ID", "INS_ACC2_ID", "INS_ACC3_ID"),
    "gyr": ("INS_GYR_ID", "INS_GYR2_ID", "INS_GYR3_ID"),
    "mag": ("COMPASS_DEV_ID", "COMPASS_DEV_ID2", "COMPASS_DEV_ID3"),
}
INSTANCE_FIELDS = ("I", "Inst")
"""The instance fields of logs without FMTU: ``I`` (IMU, MAG, GPS …), ``Inst`` (BAT)."""
MAG_NAMES = {"MAG": 0, "MAG2": 1, "MAG3": 2}
"""The compass's messages: one with ``I``, or one per instance in older logs."""
"""The parameters naming each instance's device id (bus, address, type packed as in flight_log.decode_device_id)."""


def detect(s: Sniff) -> bool:
    """A file whose first message is DataFlash's FMT."""
    return s.head.startswith(MAGIC)


def _dtype(fmt: Any) -> np.dtype:
    """The numpy record of a message's body, from pymavlink's struct string (``<QffffffIIfBBHH``)."""
    fields = []
    for (count, code), column in zip(re.findall(r"(\d*)([a-zA-Z])", fmt.msg_struct), fmt.columns):
        base = STRUCT_TO_NUMPY[code]
        fields.append((column, f"S{count}" if code == "s" else base, () if code == "s" or not count else int(count)))
    return np.dtype([(n, t) if not shape else (n, t, shape) for n, t, shape in fields])


def time_us(table: dict[str, np.ndarray], message: str, name: str = "the file") -> np.ndarray:
    """A message's time in µs since boot: ``TimeUS``, or ``TimeMS`` × 1000 in logs before ``TimeUS``."""
    if "TimeUS" in table:
        return np.asarray(table["TimeUS"]).astype(np.int64)
    if "TimeMS" in table:
        return np.asarray(table["TimeMS"]).astype(np.int64) * 1000
    raise LogFormatError(
        f"{name}: its {message} messages have no time field (neither TimeUS nor TimeMS; fields "
        f"{', '.join(table)}): trical reads ArduPilot logs that stamp them with either"
    )


def column(table: dict[str, np.ndarray], message: str, names: tuple[str, ...], name: str = "the file") -> np.ndarray:
    """The first of the fields ``names`` the message has, or a refusal naming the message and the fields."""
    for n in names:
        if n in table:
            return table[n]
    raise LogFormatError(
        f"{name}: its {message} messages have no {' or '.join(names)} field (fields "
        f"{', '.join(table)}): this layout of {message} is not one trical reads"
    )


def table(reader: Any, buf: np.ndarray, name: str) -> dict[str, np.ndarray] | None:
    """The columns of every message ``name`` in the log (multipliers applied), or None when it has none."""
    type_id = reader.name_to_id.get(name)
    if type_id is None or not reader.offsets[type_id]:
        return None
    fmt = reader.formats[type_id]
    dtype = _dtype(fmt)
    if dtype.itemsize != fmt.len - 3:
        return None
    offsets = np.asarray(reader.offsets[type_id], dtype=np.int64) + 3
    offsets = offsets[offsets + dtype.itemsize <= len(buf)]  # a last message cut short is left out
    rows = np.empty(len(offsets), dtype=dtype)
    raw = rows.view(np.uint8).reshape(len(offsets), dtype.itemsize)
    span = np.arange(dtype.itemsize)
    for start in range(0, len(offsets), GATHER_ROWS):  # in blocks: the byte indices of all rows at once are large
        block = offsets[start : start + GATHER_ROWS]
        raw[start : start + len(block)] = buf[block[:, None] + span]
    out: dict[str, np.ndarray] = {}
    for i, column in enumerate(fmt.columns):
        values = rows[column]
        mult = fmt.msg_mults[i] if i < len(fmt.msg_mults) else None
        out[column] = values.astype(float) * mult if mult is not None and values.dtype.kind in "iuf" else values
    return out


def params(reader: Any, buf: np.ndarray) -> dict[str, float]:
    """The log's parameters (PARM Name, Value), the last value of each name."""
    t = table(reader, buf, "PARM")
    if t is None or "Name" not in t or "Value" not in t:
        return {}
    return {n.split(b"\0")[0].decode("ascii", "replace"): float(v) for n, v in zip(t["Name"], t["Value"])}


def instance_field(reader: Any, name: str) -> str | None:
    """The field that numbers a message's instances: FMTU's ``#`` unit when logged, else ``I`` (``Inst`` of BAT)."""
    type_id = reader.name_to_id.get(name)
    fmt = None if type_id is None else reader.formats[type_id]
    if fmt is not None and fmt.instance_field:
        field: str = fmt.instance_field  # pymavlink's column name
        return field
    return next((c for c in INSTANCE_FIELDS if fmt is not None and c in fmt.columns), None)


def instances(reader: Any, buf: np.ndarray, names: dict[str, int]) -> list[tuple[int, str, dict[str, np.ndarray]]]:
    """``(instance, columns)`` of a message with an ``I`` field, or of its numbered names (``IMU2`` is
    instance 1 in logs before the field): ``names`` maps each name to its instance when it has no ``I``.
    Returns ``(instance, message name, columns)``."""
    out = []
    for name, number in names.items():
        t = table(reader, buf, name)
        if t is None:
            continue
        field = instance_field(reader, name)
        if field is not None and field in t:
            for i in np.unique(t[field]):
                out.append((int(i), name, {c: v[t[field] == i] for c, v in t.items()}))
        else:
            out.append((number, name, t))
    return out


def _streams(reader: Any, buf: np.ndarray, name: str = "the file") -> list[Stream]:
    values = params(reader, buf)

    def device(sensor: str, instance: int) -> int | None:
        names = DEVICE_PARAMS[sensor]
        value = values.get(names[instance]) if instance < len(names) else None
        return int(value) if value else None

    def xyz(t: dict[str, np.ndarray], prefix: str, msg: str) -> np.ndarray:
        return np.column_stack([column(t, msg, (f"{prefix}{a}",), name) for a in "XYZ"]).astype(float)

    streams: list[Stream] = []
    imu_temps = {}
    for instance, msg, t in instances(reader, buf, {"IMU": 0, "IMU2": 1, "IMU3": 2}):
        time = time_us(t, msg, name)
        temp = t.get("T", t.get("Temp"))  # Temp in logs before T
        temperature = None if temp is None else np.asarray(temp, dtype=float)
        imu_temps[instance] = (time, temperature)
        streams.append(Stream("acc", instance, "IMU", time, xyz(t, "Acc", msg), temperature, device("acc", instance)))
        streams.append(Stream("gyr", instance, "IMU", time, xyz(t, "Gyr", msg), temperature, device("gyr", instance)))
    for sensor, source, prefix in (("acc", "ACC", "Acc"), ("gyr", "GYR", "Gyr")):
        # Older logs name the batch sampler's instances ACC1, ACC2, ACC3 (instances 0, 1, 2).
        for instance, msg, t in instances(reader, buf, {source: 0, f"{source}1": 0, f"{source}2": 1, f"{source}3": 2}):
            time = np.asarray(t["SampleUS"]).astype(np.int64) if "SampleUS" in t else time_us(t, msg, name)
            temperature = None
            it, temp = imu_temps.get(instance, (None, None))
            if it is not None and temp is not None and len(it) >= 2:  # the IMU's T (logged slower) at the batch's times
                temperature = np.interp(time.astype(float), it.astype(float), temp)
            streams.append(
                Stream(sensor, instance, source, time, xyz(t, prefix, msg), temperature, device(sensor, instance))
            )
    for instance, msg, t in instances(reader, buf, MAG_NAMES):
        streams.append(
            Stream(
                "mag",
                instance,
                "MAG",
                time_us(t, msg, name),
                xyz(t, "Mag", msg) * MILLIGAUSS_TO_UT,
                None,
                device("mag", instance),
            )
        )
    return [s for s in streams if s.n_samples]


def _indexed_reader(DFReader: Any) -> Any:
    """pymavlink's binary reader for its FMT parsing and its index of where every message is, without working
    out the log's wall clock: that parses every message of a log without GPS time (a bench log), and trical
    reads each message's own TimeUS. (Made with ``type``: pymavlink ships no types, so its class is Any.)"""

    def init_clock(self: Any) -> None:
        self._rewind(keep_messages=True)
        self.init_clock_usec()

    return type("IndexedReader", (DFReader.DFReader_binary,), {"init_clock": init_clock})


@contextlib.contextmanager
def unknown_layout(name: str, what: str = "an ArduPilot DataFlash log") -> Iterator[None]:
    """Taking apart a log the library read: what goes wrong is a layout trical does not know, not a damaged file."""
    try:
        yield
    except LogFormatError:
        raise
    except (KeyError, ValueError, IndexError, TypeError) as exc:
        raise LogFormatError(
            f"{name} is {what} its library reads, but trical cannot take its messages apart "
            f"({type(exc).__name__}: {exc}): a layout trical does not know yet; the file itself "
            "is fine"
        ) from None


def open_log(path: Path, name: str = "the file") -> tuple[Any, np.ndarray, io.StringIO]:
    """pymavlink's index of the log, its bytes, and what DFReader printed: ``(reader, buf, said)``.

    Raises
    ------
    LogFormatError
        A file DFReader cannot index (then it is damaged or cut short in its formats).
    """
    from pymavlink import DFReader  # here: only DataFlash uploads load it

    said = io.StringIO()
    try:
        with contextlib.redirect_stdout(said):  # DFReader prints what it skips; the note carries it
            reader = _indexed_reader(DFReader)(str(path), zero_time_base=True)
    except Exception as exc:  # DFReader raises many kinds on a damaged file
        raise LogFormatError(
            f"{name} starts as an ArduPilot DataFlash log but cannot be read ({type(exc).__name__}: "
            f"{exc}): the file is damaged; download the log again (Mission Planner, DataFlash "
            "Logs > Download)"
        ) from None
    return reader, np.frombuffer(reader.data_map, dtype=np.uint8), said


def read(
    path: Path,
    s: Sniff,
    *,
    instance: int | None = None,
    mag_instance: int | None = None,
    clock: str = "imu",
    name: str = "the file",
) -> LogData:
    """Read the IMU instance ``instance`` (and compass ``mag_instance``) of an ArduPilot DataFlash log.

    Parameters
    ----------
    path : pathlib.Path
        The log.
    s : Sniff
        Its head (its magic: already checked).
    instance : int, optional
        The IMU instance read (default: the first).
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
        The chosen sensors on one clock, ``flight`` listing every instance, ``format`` ``dataflash``.

    Raises
    ------
    LogFormatError
        A file DFReader cannot index, one without IMU samples, or an instance the log does not have.
    """
    reader, buf, said = open_log(path, name)
    with unknown_layout(name):
        streams = _streams(reader, buf, name)
    if not streams:
        raise LogFormatError(
            f"{name} is an ArduPilot DataFlash log without IMU samples (no IMU, ACC, GYR or MAG "
            "messages; the file may be cut short): log the IMU (LOG_BITMASK with IMU, or "
            "INS_LOG_BAT_MASK for the batch sampler)"
        )
    notes = [
        "ArduPilot IMU/ACC/GYR/MAG: the body frame (x forward, y right, z down) after AHRS_ORIENTATION and after "
        "ArduPilot's own calibration (accelerometer offsets and scales, compass offsets OfsX… and scales): a "
        "calibration from them is what is left over ArduPilot's"
    ]
    if said.getvalue().strip():
        notes.append(f"{name}: pymavlink reported: {said.getvalue().strip()[:200]}")
    return choose(
        streams,
        fmt=NAME,
        imu_sources=("ACC", "IMU"),
        gyr_for={"ACC": "GYR", "IMU": "IMU"},
        mag_sources=("MAG",),
        instance=instance,
        mag_instance=mag_instance,
        clock=clock,
        default_imu=None,
        notes=notes,
        name=name,
    )
