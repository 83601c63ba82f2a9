"""``trical apply``: a calibration (stored, or a JSON file of one) applied to every sample of a recording, the rows
written as CSV, Parquet or .npy a chunk at a time (app.workflows.apply)."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from app.calibration import CalibrationError
from app.cli.reading import read_options
from app.io.readers.read_options import units_named
from app.io.writers.samples import output_format
from app.workflows.apply import apply_to_file

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings


def calibration_body(cal: str, settings: Callable[[], Settings]) -> dict[str, Any]:
    """The calibration ``CAL`` names: a JSON file of one (the API's body, or trical's JSON export), else a stored
    calibration's id."""
    path = Path(cal)
    if path.is_file():
        try:
            body = json.loads(path.read_text(encoding="utf-8"))
        except (UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise CalibrationError(
                f"{path.name} is not a calibration's JSON ({exc}): give CAL as a calibration "
                "id (cal_...) or a file trical calibrate --json wrote"
            ) from None
        if not isinstance(body, dict) or "model" not in body or "method" not in body:
            raise CalibrationError(
                f"{path.name} holds no calibration (no method and model): give CAL as a calibration id (cal_...) or "
                "a file trical calibrate --json or trical export --format json wrote"
            )
        # trical's JSON export names the input unit input_unit; the API's body names it unit.
        return {**body, "unit": body.get("unit") or body.get("input_unit")}
    if not cal.startswith("cal_"):
        raise CalibrationError(f"{cal} is neither a file nor a calibration id (cal_...): give CAL as one of them")
    from app.cli.finish import store_of

    return store_of(settings).get_calibration(cal, owner=None)


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
