"""The end ``trical noise`` and ``trical temperature`` share: the body stored, its plot written, printed; and the
store every command that keeps a calibration opens."""

from __future__ import annotations

import json
import sys
from typing import TYPE_CHECKING

from app.store import open_store

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings
    from app.store import Store


def store_of(settings: Callable[[], Settings]) -> Store:
    """The store of the TRICAL_* environment's settings (``TRICAL_DATABASE_URL``, ``TRICAL_RECORDINGS_DIR``)."""
    config = settings()
    return open_store(config.database_url, config.recordings_dir)


def finish(args, settings: Callable[[], Settings], body: dict, *, plot, summary) -> int:
    """The end of ``trical noise`` and ``trical temperature``: the body stored (``--store``), its plot written
    (``--plot``, by ``plot(body)``), the JSON or the summary printed; status 0, or 3 when ``ok`` is false."""
    if args.store:
        body = store_of(settings).add_calibration(body, owner=None)
    if args.plot:
        args.plot.write_text(plot(body), encoding="utf-8")
        print(f"wrote {args.plot}", file=sys.stderr)
    if args.json:
        print(json.dumps(body, indent=2))
    else:
        summary(body)
    return 0 if body["ok"] else 3
