"""``trical check``: a stored calibration checked on a new recording of the device (keep it, calibrate again,
move the compass, cannot tell)."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING

from app.cli.finish import calibration_body
from app.cli.reading import read_options
from app.io.readers import read_log, starts_like_flight_log
from app.io.readers.read_options import units_named
from app.workflows.check import check_recording, clock_for

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical check CAL LOG``: the verdict and each sensor's figures; status 0 to keep it, 3 otherwise."""
    body = calibration_body(args.id, settings)
    units = units_named(args.unit, args.gyr_unit, args.mag_unit)
    clock = (clock_for(body) or "imu") if starts_like_flight_log(args.log) else "imu"
    log = read_log(args.log, read_options(args, units=units, clock=clock), name=str(args.log))
    out = check_recording(body, log, field_ut=args.field_ut, inclination_deg=args.inclination_deg)
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        from app.cli.printers import print_check

        print_check(out)
    return 0 if out["verdict"] == "keep" else 3
