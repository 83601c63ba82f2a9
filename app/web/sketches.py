"""The sketches a maker flashes so that a board prints what the page reads (static/sketches/<name>/<name>.ino).

Each is described by its board and the libraries it needs; its baud rate is read from its own
``Serial.begin(…)``, so that the page never says another rate than the sketch opens the port at. The files are
served as static files (the Arduino IDE opens a sketch from a folder of its name).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache
from pathlib import Path

SKETCHES_DIR = Path(__file__).resolve().parents[2] / "static" / "sketches"
_BAUD = re.compile(r"Serial\.begin\(\s*(\d+)\s*\)")


@dataclass(frozen=True)
class Sketch:
    """One sketch: its folder's name, the board it is for, the libraries to install, what it prints."""

    name: str
    board: str
    libraries: str
    prints: str

    @property
    def path(self) -> Path:
        return SKETCHES_DIR / self.name / f"{self.name}.ino"

    @property
    def url(self) -> str:
        return f"/static/sketches/{self.name}/{self.name}.ino"

    @property
    def baud(self) -> int:
        """The rate the sketch opens the serial port at (its ``Serial.begin``)."""
        return _baud(self.path)


@cache
def _baud(path: Path) -> int:
    found = _BAUD.search(path.read_text(encoding="utf-8"))
    if found is None:
        raise ValueError(f"{path.name} opens no serial port (no Serial.begin)")
    return int(found.group(1))


SKETCHES = (
    Sketch(
        "mpu6050_uni",
        "an MPU-6050 breakout (no compass)",
        "Adafruit MPU6050, Adafruit Unified Sensor",
        "Uni: lines at about 100 Hz: m/s², rad/s, zeros for the compass it lacks",
    ),
    Sketch(
        "lsm6ds_lis3mdl_uni",
        "an LSM6DSOX + LIS3MDL (Adafruit's 9-DoF boards)",
        "Adafruit LSM6DS, Adafruit LIS3MDL, Adafruit Unified Sensor",
        "Uni: lines at about 100 Hz: m/s², rad/s, µT",
    ),
    Sketch(
        "icm20948_uni",
        "an ICM-20948",
        "Adafruit ICM20X, Adafruit Unified Sensor",
        "Uni: lines at about 100 Hz: m/s², rad/s, µT",
    ),
)
"""The sketches the board page offers, in the order it lists them."""


def sketch_table() -> list[dict]:
    """The page's list of sketches: each one's name, board, libraries, what it prints, its baud rate and URL."""
    return [
        {"name": s.name, "board": s.board, "libraries": s.libraries, "prints": s.prints, "baud": s.baud, "url": s.url}
        for s in SKETCHES
    ]
