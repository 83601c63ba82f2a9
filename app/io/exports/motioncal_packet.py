"""MotionCal's 68-byte calibration packet, which a board running Adafruit's Sensor Calibration library
(or PJRC's Prop Shield sketches) receives over its serial port and stores.

The layout, as PJRC's MotionCal sends it and Adafruit_Sensor_Calibration stores and loads it
(facts of their public sources; every line here is trical's own):

- bytes 0–1: the signature 117, 84;
- bytes 2–65: sixteen little-endian IEEE-754 float32: the accelerometer's zero-g offsets x, y, z
  (m/s²), the gyroscope's zero-rate offsets x, y, z (rad/s), the magnetometer's hard iron x, y, z
  (µT), the field's magnitude (µT), and the symmetric soft-iron matrix's entries [0][0], [1][1],
  [2][2], [0][1], [0][2], [1][2];
- bytes 66–67: the CRC-16 of bytes 0–65 (reflected polynomial 0xA001, initial value 0xFFFF), low
  byte first, so that the same CRC run over all 68 bytes ends at 0 — the receiver's check.

The receiver corrects a = m − accel_zerog, w = m − gyro_zerorate and h = M (m − hard iron): the
magnetometer's whole model ``h = M (m − b)`` with M symmetric (trical's compass, Särkkä et al., IEEE
Sensors Journal 17(11) 2017, eq. (6) with S = M⁻¹) fits it exactly, but of the accelerometer only
the offsets: its scales and cross terms, and the gyroscope's scales, are not carried. The C header
export applies the whole model.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from app.calibration.shared.headlines import SENSOR_WORDS

from ..board.formats import DEFAULT_FIELD_UT, MOTIONCAL_CRC, MOTIONCAL_PACKET_BYTES, MOTIONCAL_SIGNATURE
from ..errors import ExportError
from ..log import TO_SI
from ..plural import counted
from .common import sensor_corrections

CRC_POLYNOMIAL = MOTIONCAL_CRC["polynomial"]
CRC_START = MOTIONCAL_CRC["start"]
SOFT_IRON_ORDER = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))
"""The packet's six soft-iron entries, in order."""
# Adafruit's Unified Sensor units are m/s² (a g is STANDARD_GRAVITY of them), rad/s and µT.
SYMMETRY_TOLERANCE = 1e-6
"""A soft-iron matrix whose antisymmetric part exceeds this fraction of its norm is not symmetric."""

_FLOATS = struct.Struct("<16f")


class PacketError(ValueError):
    """A packet the receiver refuses: wrong length, signature or CRC."""


def crc16(data: bytes, crc: int = CRC_START) -> int:
    """The CRC-16 the packet carries: reflected polynomial 0xA001 (CRC-16/MODBUS), from 0xFFFF."""
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ CRC_POLYNOMIAL if crc & 1 else crc >> 1
    return crc


@dataclass(frozen=True)
class MotionCalCalibration:
    """What the packet holds, in the receiver's units.

    Attributes
    ----------
    accel_zerog : numpy.ndarray, shape (3,)
        m/s², subtracted from the accelerometer.
    gyro_zerorate : numpy.ndarray, shape (3,)
        rad/s, subtracted from the gyroscope.
    mag_hardiron : numpy.ndarray, shape (3,)
        µT, subtracted from the magnetometer before the soft iron.
    mag_field : float
        µT.
    mag_softiron : numpy.ndarray, shape (3, 3)
        Symmetric.
    notes : tuple of str
        What the packet does not carry of the calibration it was made from.
    """

    accel_zerog: np.ndarray = field(default_factory=lambda: np.zeros(3))
    gyro_zerorate: np.ndarray = field(default_factory=lambda: np.zeros(3))
    mag_hardiron: np.ndarray = field(default_factory=lambda: np.zeros(3))
    mag_field: float = DEFAULT_FIELD_UT
    mag_softiron: np.ndarray = field(default_factory=lambda: np.eye(3))
    notes: tuple = ()

    def floats(self) -> list[float]:
        M = np.asarray(self.mag_softiron, dtype=float)
        return [
            *map(float, self.accel_zerog),
            *map(float, self.gyro_zerorate),
            *map(float, self.mag_hardiron),
            float(self.mag_field),
            *(float(M[i, j]) for i, j in SOFT_IRON_ORDER),
        ]


def encode(cal: MotionCalCalibration) -> bytes:
    """The 68 bytes of ``cal``.

    Raises
    ------
    ExportError
        A value that is not finite or beyond float32.
    """
    values = cal.floats()
    if not all(np.isfinite(values)) or max(abs(v) for v in values) > 3.4e38:
        raise ExportError(
            "the calibration holds a value that is not finite or beyond a float32: it cannot be "
            "written to MotionCal's packet"
        )
    body = bytes(MOTIONCAL_SIGNATURE) + _FLOATS.pack(*values)
    crc = crc16(body)
    packet = body + bytes((crc & 0xFF, crc >> 8))
    assert len(packet) == MOTIONCAL_PACKET_BYTES
    return packet


def decode(packet: bytes) -> MotionCalCalibration:
    """The calibration a receiver recovers from ``packet`` (for tests and for reading a board's echo).

    Raises
    ------
    PacketError
        Not 68 bytes, a wrong signature, or a CRC that does not check.
    """
    if len(packet) != MOTIONCAL_PACKET_BYTES:
        raise PacketError(f"a MotionCal packet has {MOTIONCAL_PACKET_BYTES} bytes, not {len(packet)}")
    if tuple(packet[:2]) != MOTIONCAL_SIGNATURE:
        raise PacketError(f"the packet does not start with the signature {MOTIONCAL_SIGNATURE}")
    if crc16(packet) != 0:
        raise PacketError("the packet's CRC does not check: a byte was changed on the way")
    v = _FLOATS.unpack(packet[2:66])
    M = np.empty((3, 3))
    for value, (i, j) in zip(v[10:16], SOFT_IRON_ORDER):
        M[i, j] = M[j, i] = value
    return MotionCalCalibration(np.array(v[0:3]), np.array(v[3:6]), np.array(v[6:9]), float(v[9]), M)


UNIFIED_SCALES = {sensor: {unit: f for unit, f in table.items() if unit != "raw"} for sensor, table in TO_SI.items()}
"""The factors into Adafruit's Unified Sensor units (m/s², rad/s, µT) of the units the packet can take: the
log's unit tables (app.io.log) without counts, whose scale is unknown."""


def _refuse_counts(sensor: str, unit: str | None) -> float:
    table = UNIFIED_SCALES[sensor]
    if unit not in table:
        raise ExportError(
            f"the {SENSOR_WORDS[sensor]} of this calibration is in {'counts' if unit == 'raw' else unit}, "
            "but MotionCal's packet "
            f"holds {', '.join(table)} only (Adafruit's Unified Sensor units): calibrate readings in those units "
            "(give chip for counts), or use the C header export"
        )
    return table[unit]


def from_calibration(body: dict) -> MotionCalCalibration:
    """The packet's values from a stored calibration, and notes on what it cannot carry.

    The accelerometer's and gyroscope's offsets where the calibration has them (a wizard session's
    gyroscope bias at rest, the cube's gyroscope), else zeros; the compass's hard iron, field and
    soft-iron matrix, else Adafruit_Sensor_Calibration's defaults (none, 50 µT, the identity).

    Raises
    ------
    ExportError
        A calibration in counts, or a magnetometer matrix that is not symmetric (the packet holds six
        entries): the message names the C header export, which carries the whole model.
    """
    notes: list[str] = []
    cal: dict[str, Any] = {  # MotionCalCalibration's fields
        "accel_zerog": np.zeros(3),
        "gyro_zerorate": np.zeros(3),
        "mag_hardiron": np.zeros(3),
        "mag_field": DEFAULT_FIELD_UT,
        "mag_softiron": np.eye(3),
    }
    corrections = {c.sensor: c for c in sensor_corrections(body)}
    if "acc" in corrections:
        c = corrections["acc"]
        scale = _refuse_counts("acc", c.input_unit)
        cal["accel_zerog"] = scale * np.asarray(c.o, dtype=float)
        M = np.asarray(c.M, dtype=float)
        off = float(np.abs(M - np.eye(3)).max())
        notes.append(
            f"accelerometer: only the offsets are carried; its scales and cross terms (the matrix M, "
            f"up to {100 * off:.2f} % from the identity) are not: apply the C header export for the "
            "whole model"
        )
    else:
        notes.append("accelerometer: no model in this calibration, zero offsets sent")
    gyro = body.get("gyroscope_bias")
    if "gyr" in corrections:
        c = corrections["gyr"]
        cal["gyro_zerorate"] = _refuse_counts("gyr", c.input_unit) * np.asarray(c.o, dtype=float)
        notes.append("gyroscope: only the offsets are carried, not its scales and cross terms")
    elif gyro:
        cal["gyro_zerorate"] = np.asarray(gyro["rad_s"], dtype=float)
        notes.append(f"gyroscope: the bias at rest over {counted(gyro['count'], 'still capture')}")
    else:
        notes.append("gyroscope: no bias in this calibration, zero offsets sent")
    if "mag" in corrections:
        c = corrections["mag"]
        if c.output_unit == "raw":
            _refuse_counts("mag", "raw")
        scale = _refuse_counts("mag", c.input_unit)
        M = np.asarray(c.M, dtype=float)
        if float(np.abs(M - M.T).max()) > SYMMETRY_TOLERANCE * float(np.abs(M).max()):
            raise ExportError(
                "the magnetometer's correction matrix is not symmetric, and MotionCal's packet holds "
                "a symmetric soft-iron matrix only: use the C header export, which carries it whole"
            )
        cal["mag_hardiron"] = scale * np.asarray(c.o, dtype=float)
        cal["mag_softiron"] = (M + M.T) / 2.0
        field_ut = (body.get("metrics") or {}).get("field_ut")
        cal["mag_field"] = float(field_ut) * scale if field_ut else DEFAULT_FIELD_UT
        notes.append("magnetometer: hard iron, field and soft-iron matrix carried whole")
    else:
        notes.append(
            "magnetometer: no model in this calibration, the library's defaults sent (no hard iron, "
            "identity soft iron, 50 uT): the board's magnetometer calibration is replaced"
        )
    return MotionCalCalibration(**cal, notes=tuple(notes))


def packet_of(body: dict, compass: dict | None = None) -> tuple[bytes, tuple[str, ...]]:
    """The 68 bytes for a stored calibration, and the notes on what they do not carry; with ``compass`` (a stored
    compass calibration of the same board, for a calibration that has none), its hard iron, field and soft iron in
    place of the library's defaults, so that the board keeps its compass calibration."""
    cal = from_calibration(body)
    if compass is not None:
        mag = from_calibration(compass)
        kept = [n for n in cal.notes if not n.startswith("magnetometer:")]
        cal = replace(
            cal,
            mag_hardiron=mag.mag_hardiron,
            mag_field=mag.mag_field,
            mag_softiron=mag.mag_softiron,
            notes=(*kept, f"magnetometer: from the compass calibration {compass['id']}, carried whole"),
        )
    return encode(cal), cal.notes
