"""The lines boards print over a serial port or a Bluetooth UART, as trical reads them live.

One place for the constants of the board connection, read by the terminal (``trical capture``) and,
through :func:`app.web.tables.page_tables`, by the page (the Web Serial and Web Bluetooth sources):

- MotionCal's and Adafruit SensorLab's ``Raw:`` lines: nine int16 counts, accelerometer, gyroscope,
  magnetometer x, y, z, at MotionCal's fixed scales (1/8192 g, 1/16 °/s and 0.1 µT a count: the
  constants ``G_PER_COUNT``, ``DEG_PER_SEC_PER_COUNT`` and ``UT_PER_COUNT`` of MotionCal's
  ``imuread.h``, PJRC's MotionCal, and the scaling Adafruit's calibration sketches print with);
- their ``Uni:`` lines: nine numbers in m/s², rad/s and µT (Adafruit's Unified Sensor units);
- CSV with a header line (the column names trical's log readers know), and bare numbers in 3, 6 or 9
  columns, optionally after a leading time.

Nothing here talks to a port: the browser uses the Web Serial API, the terminal pyserial.
"""

from __future__ import annotations

from typing import TypedDict


class RawLine(TypedDict):
    prefix: str
    fields: int
    acc_g_per_count: float
    gyr_dps_per_count: float
    mag_ut_per_count: float


class UniLine(TypedDict):
    prefix: str
    fields: int
    units: dict[str, str]


MOTIONCAL_RAW: RawLine = {
    "prefix": "Raw:",
    "fields": 9,
    "acc_g_per_count": 1.0 / 8192.0,
    "gyr_dps_per_count": 1.0 / 16.0,
    "mag_ut_per_count": 0.1,
}
"""MotionCal's ``Raw:`` line: ax, ay, az, gx, gy, gz, mx, my, mz as integers, and their scales."""

ADAFRUIT_UNI: UniLine = {"prefix": "Uni:", "fields": 9, "units": {"acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}}
"""Adafruit SensorLab's ``Uni:`` line: the same nine values in the Unified Sensor units."""

BAUD_RATES = (9600, 19200, 38400, 57600, 115200, 230400, 250000, 460800, 500000, 921600, 1000000)
"""The rates a board's serial port is commonly opened at (the Arduino IDE's monitor offers these)."""

DEFAULT_BAUD = 115200

SILENCE_S = 3.0
"""Nothing for this long after the port opened: the rate or the sketch is wrong, and the page says so."""

RATE_MIN_S = 1.0
RATE_STEPS = 2.0
RATE_WINDOW_S = 8.0
RATE_AGREE = 0.05
"""Live lines: the board's rate is the readings counted between two ends of bursts (moments when every line
printed so far has arrived) over the time between them, decided once such ends span ``RATE_MIN_S`` and
``RATE_STEPS`` times the longest step between arrivals in the last ``RATE_WINDOW_S``, and the rates over the
two halves of that span agree within ``RATE_AGREE`` (one end read late by a loaded reader shows as halves that
disagree: 0.15 s late at the end of 2 s made 93 Hz of a board at 100 Hz), else once the arrivals fill the
window. When the window's arrivals do not decide, those after its longest pause may alone (by the same
rule, halves agreeing, their ends spanning ``RATE_MIN_S`` and ``RATE_STEPS`` times that pause): a page
whose thread was held 0.4 s as the board connected (a steady stream after it) is decided a second after
the pause, not once the pause has left the window. A bridge's buffer
or a loaded host delivering 1–2 s of lines at once is decided after 3–4 bursts, a reader that lags now and
then by the window's 8 s at the latest. Never the step of one burst's
arrival (app.io.board.lines.StreamRate, static/js/board_lines.js StreamRate)."""

STALL_S = 20.0
"""A capture that makes no progress for this long says what it waits for and what to do."""

NORDIC_UART = {
    "service": "6e400001-b5a3-f393-e0a9-e50e24dcca9e",
    "rx": "6e400002-b5a3-f393-e0a9-e50e24dcca9e",  # the board receives: trical writes here
    "tx": "6e400003-b5a3-f393-e0a9-e50e24dcca9e",  # the board sends: trical is notified here
}
"""The Nordic UART Service's UUIDs (nRF52 and ESP32 BLE UART examples use them)."""

MOTIONCAL_PACKET_BYTES = 68
MOTIONCAL_SIGNATURE = (117, 84)
MOTIONCAL_CRC = {"polynomial": 0xA001, "start": 0xFFFF}
"""The packet's CRC-16 (reflected polynomial 0xA001, CRC-16/MODBUS, from 0xFFFF), low byte first after byte 65."""
MOTIONCAL_MAG_FLOATS = (6, 16)
"""The packet's floats [6, 16) are the magnetometer's (hard iron, field, soft iron); [0, 6) the accelerometer's
and gyroscope's offsets (app.io.exports.motioncal_packet)."""
DEFAULT_FIELD_UT = 50.0
"""The field Adafruit_Sensor_Calibration starts with (µT), sent when the calibration has no magnetometer."""


def board_tables() -> dict:
    """The board connection's constants as plain JSON-ready data (for the page)."""
    return {
        "raw": dict(MOTIONCAL_RAW),
        "uni": {**ADAFRUIT_UNI, "units": dict(ADAFRUIT_UNI["units"])},
        "baudRates": list(BAUD_RATES),
        "defaultBaud": DEFAULT_BAUD,
        "silenceS": SILENCE_S,
        "rateMinS": RATE_MIN_S,
        "rateSteps": RATE_STEPS,
        "rateWindowS": RATE_WINDOW_S,
        "rateAgree": RATE_AGREE,
        "stallS": STALL_S,
        "nordicUart": dict(NORDIC_UART),
        "packet": {
            "bytes": MOTIONCAL_PACKET_BYTES,
            "signature": list(MOTIONCAL_SIGNATURE),
            "crc": dict(MOTIONCAL_CRC),
            "magFloats": list(MOTIONCAL_MAG_FLOATS),
            "defaultFieldUt": DEFAULT_FIELD_UT,
        },
    }
