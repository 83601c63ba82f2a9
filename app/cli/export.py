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
    content = out.content
    if args.output:
        if isinstance(content, bytes):
            args.output.write_bytes(content)
        else:
            args.output.write_text(content)
        print(f"wrote {args.output}", file=sys.stderr)
    elif isinstance(content, bytes):
        sys.stdout.flush()
        sys.stdout.buffer.write(content)
    else:
        sys.stdout.write(content)
    for note in out.notes:  # what the format does not carry (motioncal: the accelerometer's scales)
        print(f"note: {render(note, 'cli')}", file=sys.stderr)
    return 0
