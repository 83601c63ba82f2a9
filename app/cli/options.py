"""Value checks of the ``trical`` command's options, run by argparse while it parses.

Each factory returns a ``type=`` function that refuses a bad value with a one-line reason
(argparse then exits with status 2) and lists in ``refuses`` a few values it refuses, so that
tests can feed every option of the parser a bad value without a hand-kept list.
"""

from __future__ import annotations

import argparse
import datetime
import math
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Protocol, TypeVar, cast

T = TypeVar("T")
T_co = TypeVar("T_co", covariant=True)


class OptionType(Protocol[T_co]):
    """A ``type=`` function: what it reads (its ``__name__``, in argparse's messages) and a few values it refuses."""

    __name__: str
    refuses: tuple[str, ...]

    def __call__(self, value: str, /) -> T_co: ...


def _option(parse: Callable[[str], T], what: str, refuses: Iterable[str]) -> OptionType[T]:
    option = cast("OptionType[T]", parse)
    option.refuses = tuple(refuses)
    option.__name__ = what
    return option


def number(
    what: str, *, low: float | None = None, high: float | None = None, low_open: bool = False, integer: bool = False
):
    """A finite number (an integer with ``integer``) within ``[low, high]`` (``(low, high]`` with ``low_open``).

    Parameters
    ----------
    what : str
        How the message names the value, e.g. ``"a latitude in degrees"``.
    low, high : float, optional
        The bounds; None for none.
    low_open : bool
        Exclude ``low`` itself (e.g. ``> 0``).
    integer : bool
        Accept integers only.
    """
    if low is not None and high is not None:
        bounds = f"{'above' if low_open else 'from'} {low:g} {'up to' if low_open else 'to'} {high:g}"
    elif low is not None:
        bounds = f"{'above' if low_open else 'at least'} {low:g}"
    else:
        bounds = f"at most {high:g}" if high is not None else "finite"

    def parse(text: str):
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{text!r} is not {'an integer' if integer else 'a number'}: give {what}, {bounds}"
            ) from None
        if (
            not math.isfinite(value)
            or (low is not None and (value < low or (low_open and value == low)))
            or (high is not None and value > high)
        ):
            raise argparse.ArgumentTypeError(f"{text} is out of range: give {what}, {bounds}")
        return value

    refused = ["abc", "nan"] + (["1.5"] if integer else [])
    if low is not None:
        refused.append(f"{low:g}" if low_open else f"{low - 1:g}")
    if high is not None:
        refused.append(f"{high + 1:g}")
    return _option(parse, what, tuple(refused))


def text(what: str):
    """A non-blank string."""

    def parse(value: str) -> str:
        if not value.strip():
            raise argparse.ArgumentTypeError(f"an empty value: give {what}")
        return value

    return _option(parse, what, ("", "  "))


def output_file(what: str):
    """A file to write, in a directory that exists."""

    def parse(value: str) -> Path:
        path = Path(value)
        if not value.strip() or path.is_dir() or not path.parent.is_dir():
            raise argparse.ArgumentTypeError(f"cannot write {value!r}: give {what} in a directory that exists")
        return path

    return _option(parse, what, ("/nonexistent-dir/calibration.json", "", "/"))


def input_path(what: str):
    """A file or folder to read; a missing one is reported when the command runs, before anything
    starts ("trical: error: no such file: ...")."""

    def parse(value: str) -> Path:
        if not value.strip():
            raise argparse.ArgumentTypeError(f"an empty path: give {what}")
        return Path(value)

    return _option(parse, what, ("/nonexistent/trical-input", ""))


def day(what: str):
    """A calendar day, ISO 8601 (``2026-12-02``)."""

    def parse(value: str) -> datetime.date:
        try:
            return datetime.date.fromisoformat(value.strip())
        except ValueError:
            raise argparse.ArgumentTypeError(f"{value!r} is not a day: give {what} as YYYY-MM-DD") from None

    return _option(parse, what, ("2026-13-01", "yesterday", ""))


def chips(what: str):
    """One or more part names separated by commas, each one trical knows (app.io.readers.chips)."""

    def parse(value: str) -> str:
        from app.io.errors import LogFormatError
        from app.io.readers.chips import parse_chips
        from app.words import render

        if not value.strip():
            raise argparse.ArgumentTypeError(f"an empty value: give {what}")
        try:
            parse_chips(value)
        except LogFormatError as exc:
            raise argparse.ArgumentTypeError(render(str(exc), "cli")) from None
        return value

    return _option(parse, what, ("", "mpu9999", "mpu6050-2g,mpu6050-4g"))


PORT = number("a TCP port", low=1, high=65535, integer=True)
LATITUDE = number("a latitude in degrees", low=-90, high=90)
LONGITUDE = number("a longitude in degrees, east positive", low=-180, high=180)
DAY = day("the day of the recording")
HEIGHT = number("a height above the ellipsoid in m", low=-12000, high=100000)
GRAVITY = number("a gravity in m/s^2", low=0.1, high=100)
SAMPLING_RATE = number("a sampling rate in Hz", low=0, high=100000, low_open=True)
LSB_PER_G = number("counts per g", low=0, low_open=True)
FIELD_UT = number("a magnetic field magnitude in µT", low=0, high=1000, low_open=True)
INCLINATION = number("an inclination in degrees", low=-90, high=90)
SECONDS = number("a time in seconds from the log's start", low=0, high=604800)
CHIP = chips("the parts of the log's sensors, e.g. mpu6050-4g,ak8963-16bit")
WORKERS = number("a number of worker processes", low=1, integer=True)
BAUD = number("a baud rate", low=50, high=4_000_000, integer=True)
MINUTES = number("a length in minutes", low=0, high=1440, low_open=True)
INSTANCE = number("an instance number of the flight log's sensor", low=0, high=255, integer=True)
CAPTURE_S = number("seconds captured per pose", low=0, low_open=True)


NOTES_SHOWN = 5
"""The notes a command's summary prints by default (``--verbose``: all): the first are the reader's decisions
(units, columns, clock), then the calibration's own (app.cli.printers.print_notes)."""
