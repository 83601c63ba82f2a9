"""``trical noise``: a still recording's Allan deviation (noise density, random walk, bias instability)."""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from app.calibration import CalibrationError
from app.cli.finish import finish
from app.cli.reading import read_options
from app.io.log import GYR_TO_RAD_S, MAG_TO_UT, UNITS
from app.io.readers import read_log, starts_like_flight_log
from app.io.readers.read_options import units_named
from app.workflows.noise import characterise_log

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical noise PATH…``: the files as one still recording, characterised."""
    if len(args.path) == 1:
        return _noise_of(args, settings, args.path[0], args.path[0].name)
    from app.cli.calibrate import one_recording  # several files joined as one recording (a zip of them)

    with tempfile.TemporaryDirectory(prefix="trical-") as tmp:
        return _noise_of(args, settings, one_recording(args.path, Path(tmp)), ", ".join(p.name for p in args.path))


def _noise_of(args, settings: Callable[[], Settings], path: Path, label: str) -> int:
    array = path.suffix.lower() in (".npy", ".parquet", ".pq")
    sensor = args.sensor or "acc"
    units = {}
    if args.unit:
        if args.unit not in UNITS[sensor]:
            raise CalibrationError(f"--unit {args.unit} is not a {sensor} unit: use one of {', '.join(UNITS[sensor])}")
        units = {sensor: args.unit}
    read_units = {"acc": units[sensor]} if array and units and sensor == "acc" else ({} if array else units)
    if not array:  # a log's gyroscope and magnetometer, as trical calibrate and the upload name them
        read_units = {**units_named(None, args.gyr_unit, args.mag_unit), **read_units}
    # A flight controller's compass is on its own clock (app.io.flight.instances): --sensor mag reads it there.
    clock = "mag" if args.sensor == "mag" and not array and starts_like_flight_log(path) else "imu"
    name = str(args.path[0]) if len(args.path) == 1 else label
    log = read_log(
        path,
        read_options(args, units=read_units, clock=clock),
        name=name,
    )
    if array and sensor != "acc" and units:
        log = _relabel_units(log, units[sensor])
    body = characterise_log(
        log,
        sensors=None if array or not args.sensor else [args.sensor],
        array_sensor=sensor if array else None,
        device_id=args.device_id,
        label=label,
    ).body()
    return finish(args, settings, body, plot=_plot, summary=lambda b: summary(b, verbose=args.verbose))


def _plot(body: dict) -> str:
    from app.io.exports.allan_plot import allan_svg

    return allan_svg(body)


def summary(body: dict, verbose: bool = False) -> None:
    """The command's summary of a noise characterisation (``--verbose``: every note)."""
    # The printers' words are the method table's (app.words): loaded for a summary, not for --json.
    from app.cli.printers import print_noise

    print_noise(body, verbose)


def _relabel_units(log, unit: str):
    """An array of gyroscope or magnetometer samples in deg/s or nT: read as acc, converted by the workflow."""
    import dataclasses

    factor = {"deg/s": GYR_TO_RAD_S["deg/s"], "nT": MAG_TO_UT["nT"]}.get(unit)
    if factor is None:
        return log
    return dataclasses.replace(log, acc=np.asarray(log.acc, dtype=float) * factor)
