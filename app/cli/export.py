"""``trical export``: a stored calibration in one of its method's formats."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

from app import methods
from app.cli.finish import store_of
from app.words import render

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical export ID``: the stored calibration in ``--format``, to ``--output`` or stdout."""
    body = store_of(settings).get_calibration(args.id, owner=None)
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
