"""``trical apply``: a calibration (stored, or a JSON file of one) applied to every sample of a recording, the rows
written as CSV, Parquet or .npy a chunk at a time (app.workflows.apply)."""

from __future__ import annotations

import json
import os
import sys
from typing import TYPE_CHECKING

from app.cli.finish import calibration_body
from app.cli.reading import read_options
from app.io.readers.read_options import units_named
from app.io.writers.samples import output_format
from app.workflows.apply import apply_to_file

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical apply CAL FILE -o OUT``: the calibrated samples written to OUT; a summary on stderr (``--json``:
    what was written, on stdout)."""
    body = calibration_body(args.calibration, settings)
    fmt = output_format(args.output, args.format)
    options = read_options(args, units=units_named(args.unit, args.gyr_unit, args.mag_unit))
    if not args.file.exists():
        raise FileNotFoundError(2, "No such file", str(args.file))
    # Written beside the output and renamed at the end: a refused or stopped run leaves no half-written file.
    part = args.output.with_name(f".{args.output.name}.part")
    try:
        with open(part, "wb") as out:
            applied = apply_to_file(body, args.file, out, fmt=fmt, options=options, name=args.file.name)
        os.replace(part, args.output)
    finally:
        part.unlink(missing_ok=True)
    if args.json:
        print(json.dumps({"output": str(args.output), **applied.body()}, indent=2))
        return 0
    from app.words import render

    units = ", ".join(f"{s} {'corrected' if s in applied.corrected else 'as read'} ({u})" for s, u in _units(applied))
    print(f"wrote {args.output}: {applied.rows} rows ({fmt}); {units}", file=sys.stderr)
    for note in applied.notes[:5]:
        print(f"note: {render(note, 'cli')}", file=sys.stderr)
    return 0


def _units(applied) -> list[tuple[str, str]]:
    seen: dict[str, str] = {}
    for c in applied.columns:
        if c.sensor in ("acc", "gyr", "mag"):
            seen.setdefault(c.sensor, c.unit)
    return list(seen.items())
