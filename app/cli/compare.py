"""``trical compare``: two calibrations of a device, parameter by parameter, with their intervals."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING

from app.cli.finish import calibration_body
from app.workflows.check import compare_calibrations

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical compare A B``: the differences B − A, which are real, and their effect in degrees."""
    a = calibration_body(args.id, settings)
    b = calibration_body(args.other, settings)
    out = compare_calibrations(a, b, field_ut=args.field_ut, inclination_deg=args.inclination_deg)
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        from app.cli.printers import print_comparison

        print_comparison(out)
    return 0
