"""The end ``trical noise`` and ``trical temperature`` share: the body stored, its plot written, printed; the
store every command that keeps a calibration opens, and the calibration a command names by its id or file."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from app.calibration.shared.errors import CalibrationError
from app.store import open_store

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings
    from app.store import Store


def store_of(settings: Callable[[], Settings]) -> Store:
    """The store of the TRICAL_* environment's settings (``TRICAL_DATABASE_URL``, ``TRICAL_RECORDINGS_DIR``)."""
    config = settings()
    return open_store(config.database_url, config.recordings_dir)


def calibration_body(cal: str, settings: Callable[[], Settings]) -> dict[str, Any]:
    """The calibration a command's ``CAL`` names (``trical apply``, ``check``, ``compare``): a JSON file of one (the
    API's body, or trical's JSON export), else a stored calibration's id."""
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
    return store_of(settings).get_calibration(cal, owner=None)


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
