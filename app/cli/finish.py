"""The end ``trical noise`` and ``trical temperature`` share: the body stored, its plot written, printed."""

from __future__ import annotations

import json
import sys

from app.config import Settings
from app.store import open_store


def finish(args, settings: Settings, body: dict, *, plot, summary) -> int:
    """The end of ``trical noise`` and ``trical temperature``: the body stored (``--store``), its plot written
    (``--plot``, by ``plot(body)``), the JSON or the summary printed; status 0, or 3 when ``ok`` is false."""
    if args.store:
        body = open_store(settings.database_url, settings.recordings_dir).add_calibration(body, owner=None)
    if args.plot:
        args.plot.write_text(plot(body), encoding="utf-8")
        print(f"wrote {args.plot}", file=sys.stderr)
    if args.json:
        print(json.dumps(body, indent=2))
    else:
        summary(body)
    return 0 if body["ok"] else 3
