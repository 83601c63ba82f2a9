"""``trical temperature``: each axis's offset as a polynomial of temperature, from a still recording."""

from __future__ import annotations

from app import workflow
from app.cli.finish import finish
from app.cli.printers import print_temperature
from app.config import Settings


def run(args, settings: Settings) -> int:
    """``trical temperature PATH``: the offsets' drift with temperature, fitted."""
    log = workflow.load_log(args.path, sampling_rate_hz=args.sampling_rate_hz, units={}, name=str(args.path),
                            columns=args.columns, sign=args.sign, chip=args.chip, instance=args.instance)
    body = workflow.temperature_log(log, sensors=[args.sensor] if args.sensor else None, device_id=args.device_id,
                                    label=args.path.name)
    from app.io.export_temperature import temperature_svg

    return finish(args, settings, body, plot=temperature_svg, summary=print_temperature)

