"""Betaflight's and INAV's CLI ``diff all`` / ``dump``: the version line and the ``set`` lines.

The accelerometer's zero and gain are read in the units trical's exports write them in
(app.io.exports.cli_sets, which cites both firmwares' source): counts of ``acc_1G`` = 2048 per g, a gain of
4096 = 1.0.
"""

from __future__ import annotations

import re

import numpy as np

from app.calibration.imported import ImportedCalibration, offset_scale_sensor
from app.calibration.shared.gravity import STANDARD_GRAVITY

from ..exports.cli_sets import ACC_1G, INAV_GAIN_ONE, INAV_GAIN_RANGE, INT16

VERSION = re.compile(r"^#\s*(Betaflight|INAV)\s*/\s*(.*?)\s(\d+\.\d+(?:\.\d+)?)\b", re.MULTILINE | re.IGNORECASE)
"""``# Betaflight / STM32F405 (S405) 4.4.2 …``, ``# INAV/MATEKF405TE_SD 7.1.0 …``."""
SET = re.compile(r"^\s*set\s+(\w+)\s*=\s*(.*?)\s*$", re.MULTILINE)

ACC_1G_WORDS = (
    f"counts at {ACC_1G} per g (acc_1G of the parts run at ±16 g; another part's numbers need scaling by "
    f"its acc_1G / {ACC_1G})"
)
MAG_NOTE = (
    "the compass's zero ({names}) is in the magnetometer's raw counts, whose scale the file does not state: not "
    "imported"
)


def sets(text: str) -> dict[str, str]:
    """The ``set name = value`` lines, the last of each name."""
    return {m.group(1).lower(): m.group(2) for m in SET.finditer(text)}


def firmware_of(text: str) -> tuple[str, str | None, str | None] | None:
    """``(firmware, board, version)`` of the version line, or None."""
    m = VERSION.search(text)
    if m is None:
        return None
    name = "INAV" if m.group(1).upper() == "INAV" else "Betaflight"
    return name, m.group(2).strip(), m.group(3)


class NotANumber(ValueError):
    """A ``set`` line of the calibration whose value is not a number (the message names the line)."""


def _number(name: str, value: str) -> float:
    """A value of a ``set`` line as a number.

    Raises
    ------
    NotANumber
        A value that is not a number, named with its line.
    """
    try:
        return float(value)
    except ValueError:
        raise NotANumber(f"`set {name} = {value}` is not a number") from None


def _ints(name: str, value: str) -> list[float]:
    return [_number(name, v) for v in value.replace(" ", "").split(",") if v]


def _to_mps2(counts) -> np.ndarray:
    return np.asarray(counts, dtype=float) * STANDARD_GRAVITY / ACC_1G


def betaflight(values: dict[str, str], version: str | None, file_kind: str) -> ImportedCalibration:
    """Betaflight's ``acc_calibration = x,y,z`` (4.0 and later; 4.3 adds a fourth value, 1 once calibrated) or
    ``acc_zero_x/y/z`` (3.x): ``M = I``, ``o`` the zero in m/s² (Betaflight holds no scale).

    Raises
    ------
    LookupError
        When the dump sets neither.
    """
    warnings: list[str] = []
    if "acc_calibration" in values:
        numbers = _ints("acc_calibration", values["acc_calibration"])
        zero = (numbers + [0.0, 0.0, 0.0])[:3]
        params = {"acc_calibration": values["acc_calibration"]}
        if len(numbers) >= 4 and numbers[3] == 0:
            warnings.append("acc_calibration's last value is 0: Betaflight counts the accelerometer as not calibrated")
    elif any(f"acc_zero_{a}" in values for a in "xyz"):
        zero = [_number(f"acc_zero_{a}", values.get(f"acc_zero_{a}", "0")) for a in "xyz"]
        params = {f"acc_zero_{a}": values[f"acc_zero_{a}"] for a in "xyz" if f"acc_zero_{a}" in values}
    else:
        raise LookupError("no accelerometer calibration: neither acc_calibration nor acc_zero_x/y/z is set")
    reasons = _int16(params, zero)
    warnings += _version_warning("Betaflight", version)
    mag = [n for n in ("mag_calibration", "mag_zero_x") if n in values]
    if mag:
        warnings.append(MAG_NOTE.format(names=", ".join(mag)))
    sensor = offset_scale_sensor("acc", _to_mps2(zero), np.ones(3), ACC_1G_WORDS, params)
    return ImportedCalibration(
        (sensor,),
        "Betaflight",
        version,
        file_kind,
        "the sensor's frame (before align_board_*)",
        warnings=tuple(reasons + warnings),
        reasons=tuple(reasons),
    )


def inav(values: dict[str, str], version: str | None, file_kind: str) -> ImportedCalibration:
    """INAV's ``acczero_x/y/z`` and ``accgain_x/y/z`` (2.0 and later): ``M = diag(accgain / 4096)``, ``o`` the zero
    in m/s²; a value the diff leaves out is INAV's default (zero 0, gain 4096).

    Raises
    ------
    LookupError
        When the dump sets none of them.
    """
    names = [f"acczero_{a}" for a in "xyz"] + [f"accgain_{a}" for a in "xyz"]
    if not any(n in values for n in names):
        raise LookupError("no accelerometer calibration: none of acczero_x/y/z, accgain_x/y/z is set")
    zero = [_number(f"acczero_{a}", values.get(f"acczero_{a}", "0")) for a in "xyz"]
    gain = np.array([_number(f"accgain_{a}", values.get(f"accgain_{a}", str(INAV_GAIN_ONE))) for a in "xyz"])
    params = {n: values[n] for n in names if n in values}
    reasons = _int16(params, zero)
    lo, hi = INAV_GAIN_RANGE
    reasons += [f"accgain_{a} = {v:g} is outside INAV's {lo}…{hi}" for a, v in zip("xyz", gain) if not lo <= v <= hi]
    warnings = _version_warning("INAV", version)
    mag = [n for n in ("magzero_x", "maggain_x") if n in values]
    if mag:
        warnings.append(MAG_NOTE.format(names=", ".join(mag)))
    sensor = offset_scale_sensor("acc", _to_mps2(zero), gain / INAV_GAIN_ONE, ACC_1G_WORDS, params)
    return ImportedCalibration(
        (sensor,),
        "INAV",
        version,
        file_kind,
        "the sensor's frame (before align_acc and the board's alignment)",
        warnings=tuple(reasons + warnings),
        reasons=tuple(reasons),
    )


SUPPORTED_FROM = {"Betaflight": (3, 0), "INAV": (2, 0)}
"""The first release whose calibration trical reads as described (Betaflight's acc_zero_* from 3.x, acc_calibration
from 4.0; INAV's acczero_*/accgain_* from 2.0)."""


def _version_warning(firmware: str, version: str | None) -> list[str]:
    """A warning for a release older than :data:`SUPPORTED_FROM`, or for a dump without a version line."""
    if version is None:
        return [f"the dump has no version line: read as {firmware} from {'.'.join(map(str, SUPPORTED_FROM[firmware]))}"]
    parts = tuple(int(v) for v in version.split(".")[:2])
    if parts < SUPPORTED_FROM[firmware]:
        first = ".".join(map(str, SUPPORTED_FROM[firmware]))
        return [
            f"{firmware} {version} is older than {first}, the first release whose calibration trical reads: check it"
        ]
    return []


def _int16(params: dict[str, str], zero) -> list[str]:
    lo, hi = INT16
    return [f"an accelerometer zero of {v:g} is outside {lo}…{hi}" for v in zero if not lo <= v <= hi] if params else []
