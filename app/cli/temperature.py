"""``trical temperature``: each axis's offset as a polynomial of temperature, from a still recording."""

from __future__ import annotations

from typing import TYPE_CHECKING

from app.cli.finish import finish
from app.cli.printers import print_temperature
from app.cli.reading import read_options
from app.io.readers import read_log
from app.io.readers.read_options import units_named
from app.workflows.temperature import temperature_log

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical temperature PATH``: the offsets' drift with temperature, fitted."""
    log = read_log(
        args.path,
        read_options(args, units=units_named(args.unit, args.gyr_unit, args.mag_unit)),
        name=str(args.path),
    )
    body = temperature_log(
        log, sensors=[args.sensor] if args.sensor else None, device_id=args.device_id, label=args.path.name
    ).body()
    from app.io.exports.temperature import temperature_svg

    return finish(args, settings, body, plot=temperature_svg, summary=lambda b: summary(b, verbose=args.verbose))


def summary(body: dict, verbose: bool = False) -> None:
    """The command's summary of a temperature calibration (``--verbose``: every note)."""
    print_temperature(body, verbose)
