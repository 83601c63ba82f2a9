"""``trical calibrate``: one recording (a log, or the pose files joined) calibrated by the method table's
request, with imucal's section list for the cube (``--sections``)."""

from __future__ import annotations

import importlib
import json
import tempfile
import zipfile
from pathlib import Path
from typing import TYPE_CHECKING

from app import methods
from app.calibration import CalibrationError
from app.cli.finish import store_of
from app.cli.printers import print_summary
from app.cli.reading import read_options
from app.io.readers import read_log
from app.io.readers.parts import refuse_repeated_names
from app.io.readers.read_options import units_named
from app.workflows.recordings import RecordingSource, describe_log
from app.workflows.supports import first_ready

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings
    from app.workflows.calibration import Calibration


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical calibrate LOG…``: the files as one recording, calibrated, printed; status 3 when not ok."""
    with tempfile.TemporaryDirectory(prefix="trical-") as tmp:
        return _calibrate_files(args, settings, one_recording(args.log, Path(tmp)))


def one_recording(paths: list[Path], tmp: Path) -> Path:
    """The log to read: the one path, or the pose files put together, each under its name, in a zip that
    is read as one recording in parts (app.io.readers.parts), as the API stores several uploaded files."""
    if len(paths) == 1:
        return paths[0]
    refuse_repeated_names([p.name for p in paths])
    joined = tmp / "poses.zip"
    with zipfile.ZipFile(joined, "w", compression=zipfile.ZIP_STORED) as zf:
        for p in paths:
            if not p.is_file():
                raise FileNotFoundError(2, "No such file", str(p))
            zf.write(p, p.name)
    return joined


def _calibrate_files(args, settings: Callable[[], Settings], path: Path) -> int:
    calibration, body, recording = calibrated(args, settings, path)
    if args.json:
        print(json.dumps(body, indent=2))
    else:
        if recording.get("chosen"):
            from app.words import render  # the method table's words: loaded for a summary, not for --json

            print(render(recording["chosen"], "cli"))
        command = methods.BY_NAME[body["method"]].command
        if command == "calibrate":
            print_summary(calibration, body, recording, verbose=args.verbose)
        else:  # a method of another command, chosen by the recording (app.workflows.supports): printed as it prints
            importlib.import_module(f"app.cli.{command}").summary(body, verbose=args.verbose)
    return 0 if body["ok"] else 3


def calibrated(
    args, settings: Callable[[], Settings], path: Path, captures: list | None = None
) -> tuple[Calibration, dict, dict]:
    """The calibration of the log at ``path`` as ``trical calibrate``'s options ask, typed and as its plain form
    (stored unless ``--no-store``), and the recording's description; ``captures`` (``trical capture``'s rows of each
    capture) stand for the still segments the log's detector would find."""
    units = units_named(args.unit, args.gyr_unit, args.mag_unit)
    options = read_options(args, units=units)
    name = ", ".join(str(p) for p in args.log)
    log = read_log(path, options, name=name)
    recording = describe_log(log, options, path=path)
    if captures and log.acc is not None:
        from app.cli.board import capture_segments

        recording["segments"] = capture_segments(log.acc, captures)
        recording["notes"].append(
            f"the still segments are the {len(captures)} captures, rows "
            + ", ".join(f"{a}–{b - 1}" for _, a, b in captures)
        )
    chosen = None if args.method else chosen_support(recording)
    method = args.method or (chosen or {})["method"]
    request = methods.parse_calibration_request(
        calibration_request(args, unit=log.units.get("acc", "m/s^2"), method=method)
    )
    if chosen is not None:  # the summary's first line (the JSON has the recording's supports through the API)
        others = [s["method"] for s in recording["supports"] if s is not chosen]
        also = f" (it also supports {', '.join(others)}: --method)" if others else ""
        recording["chosen"] = f"method {method}, chosen from the recording: {chosen['why']}{also}"
    calibration = methods.calibrate(request, RecordingSource(meta=recording, path=path, log=log))
    if captures:  # each capture's rows of the log and its reading, as a wizard session's body lists its captures
        calibration = calibration.with_fields(
            captures=[
                {
                    "position": seg["capture"],
                    "rows": [seg["start"], seg["end"]],
                    "up": seg["up"],
                    "mean": seg["acc_mean"],
                    "std": seg["acc_std"],
                    "count": seg["count"],
                }
                for seg in recording["segments"]
            ]
        )
    body = calibration.body()
    if not args.no_store:
        body = store_of(settings).add_calibration(body, owner=None)
    return calibration, body, recording


def chosen_support(recording: dict) -> dict:
    """What the page runs on this recording when the person chose nothing (app.workflows.supports): the first
    calibration it supports that is ready; a refusal listing what it supports and what each lacks when none is."""
    found = recording["supports"]
    first = first_ready(found)
    if first is None:
        lacks = "; ".join(f"{s['method']}: {s['why']}" for s in found) or "no sensor trical calibrates"
        raise CalibrationError(f"this recording is ready for no calibration ({lacks}); or give --method to try one")
    return first


def calibration_request(args, *, unit: str, method: str) -> dict:
    """The request of POST /api/v1/calibrations that ``trical calibrate`` makes of its options: each field the
    method's request model takes (app.methods) from the option of its name (``--field-ut``: ``field_ut``); the
    log file stands in for the stored recording, and ``unit`` is the log's accelerometer unit."""
    # Read whatever the method: a section list that cannot be read is an error, not an option ignored.
    sections = None if args.sections is None else _read_sections(args.sections)
    given = {
        **vars(args),
        "recording_id": ", ".join(str(p) for p in args.log),
        "label": ", ".join(p.name for p in args.log),
        "unit": unit,
        "sections": sections,
    }
    return {
        "method": method,
        **{name: given[name] for name in methods.BY_NAME[method].options if given.get(name) is not None},
    }


def _read_sections(path) -> object:
    """The JSON of ``--sections``; the request model validates its keys and regions."""
    try:
        return json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise CalibrationError(
            f"--sections {path}: not a readable JSON section list ({exc}); write it as imucal "
            'does: {"x_p": {"start": 540, "end": 1271}, …}'
        ) from None
