"""``trical export``: a stored calibration in one of its method's formats."""

from __future__ import annotations

import sys

from app import methods
from app.config import Settings
from app.store import open_store
from app.words import render


def run(args, settings: Settings) -> int:
    """``trical export ID``: the stored calibration in ``--format``, to ``--output`` or stdout."""
    body = open_store(settings.database_url, settings.recordings_dir).get_calibration(args.id, owner=None)
    out = methods.export(body, args.format)
    binary = isinstance(out.content, bytes)
    if args.output:
        if binary:
            args.output.write_bytes(out.content)
        else:
            args.output.write_text(out.content)
        print(f"wrote {args.output}", file=sys.stderr)
    elif binary:
        sys.stdout.flush()
        sys.stdout.buffer.write(out.content)
    else:
        sys.stdout.write(out.content)
    for note in out.notes:  # what the format does not carry (motioncal: the accelerometer's scales)
        print(f"note: {render(note, 'cli')}", file=sys.stderr)
    return 0
