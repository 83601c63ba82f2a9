"""``trical import``: the calibration a device already holds, read from its firmware's file and stored."""

from __future__ import annotations

import base64
import json
from typing import TYPE_CHECKING

from app import methods
from app.calibration_requests import ImportIn
from app.cli.finish import store_of
from app.cli.printers import print_model, print_notes, print_verdict
from app.words import render

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical import FILE``: the file's calibration (recognised from its content, ``--firmware`` to force the
    family) stored as ``--device-id``'s, unless ``--no-store``; status 0, or 3 when ``ok`` is false."""
    request = ImportIn(
        method="imported",
        file_base64=base64.b64encode(args.path.read_bytes()).decode("ascii"),
        firmware=args.firmware,
        instance=args.instance,
        device_id=args.device_id,
        label=args.label or args.path.name,
    )
    body = methods.calibrate(request).body()
    if not args.no_store:
        body = store_of(settings).add_calibration(body, owner=None)
    if args.json:
        print(json.dumps(body, indent=2))
        return 0 if body["ok"] else 3
    print_verdict(body)
    if body.get("headline"):
        print(render(body["headline"], "cli"))
    if body.get("id"):
        print(f"stored as {body['id']}" + (f" (device {body['device_id']})" if body.get("device_id") else ""))
    print_model({k: v for k, v in body["model"].items() if k != "type"})
    for reason in body.get("reasons") or []:
        print(f"reason: {render(reason, 'cli')}")
    print_notes(body.get("warnings") or [], args.verbose)
    return 0 if body["ok"] else 3
