"""``trical autocal``: Farago et al.'s pipeline on one long recording, or on a folder of them (local processes
or a Dask cluster)."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from app.calibration import CalibrationError
from app.io.errors import LogFormatError
from app.io.read_options import ReadOptions
from app.workflows.autocal import autocalibrate_file

if TYPE_CHECKING:
    from app.config import Settings

# The printers (app.words imports the method table, ~0.4 s) and the store are imported where they are used:
# `trical autocal FILE --json` needs neither.


def _autocal_options(args) -> dict:
    read = ReadOptions(
        sampling_rate_hz=args.sampling_rate_hz,
        units={"acc": args.unit} if args.unit else {},
        columns=args.columns,
        sign=args.sign,
        chip=args.chip,
        instance=args.instance,
    )
    return dict(
        options=read,
        solver=args.solver,
        gravity=args.gravity,
        latitude_deg=args.latitude_deg,
        detection={"all_axes": True} if args.all_axes else None,
        device_id=args.device_id,
    )


def _autocal_job(path: str, options: dict) -> dict:
    """One file of a folder run (top level, so that worker processes can pickle it)."""
    try:
        return autocalibrate_file(path, **options)
    except (CalibrationError, LogFormatError) as exc:
        return {"label": Path(path).name, "ok": False, "error": str(exc)}
    except Exception as exc:  # a worker must report, never take the run down
        return {"label": Path(path).name, "ok": False, "error": f"{type(exc).__name__}: {exc}"}


def run(args, settings: Settings) -> int:
    """``trical autocal PATH``: one recording (a progress bar on a terminal), or a folder of them."""
    options = _autocal_options(args)
    if args.path.is_dir():
        return _autocal_folder(args, settings, options)
    progress = None
    if sys.stderr.isatty():
        from app.cli.printers import ProgressBar

        progress = ProgressBar(args.path.name)
    body = autocalibrate_file(args.path, progress=progress, **options)
    if args.store:
        from app.store import open_store

        body = open_store(settings.database_url, settings.recordings_dir).add_calibration(body, owner=None)
    if args.json:
        print(json.dumps(body, indent=2))
    else:
        from app.cli.printers import print_autocal

        print_autocal(body)
    return 0 if body["ok"] else 3


def _folder_files(folder: Path) -> list[Path]:
    from app.io.arrays import SUFFIXES

    files = sorted(p for p in folder.iterdir() if p.is_file() and p.suffix.lower() in SUFFIXES)
    if not files:
        raise LogFormatError(f"{folder} holds no .npy, .parquet or .csv recordings")
    return files


def _autocal_folder(args, settings: Settings, options: dict) -> int:
    files = _folder_files(args.path)
    paths = [str(p) for p in files]
    if args.dask_scheduler:
        try:
            from dask.distributed import Client
        except ImportError:
            raise CalibrationError(
                "--dask-scheduler needs dask.distributed, which is not installed: pip install 'dask[distributed]' "
                "(or leave --dask-scheduler out to use local processes)"
            ) from None
        with Client(args.dask_scheduler) as client:
            futures = client.map(_autocal_job, paths, options=options, pure=False)
            bodies = client.gather(futures)
    else:
        from concurrent.futures import ProcessPoolExecutor

        workers = args.workers or min(len(paths), os.cpu_count() or 1)
        if workers <= 1:
            bodies = [_autocal_job(p, options) for p in paths]
        else:
            with ProcessPoolExecutor(max_workers=workers) as pool:
                bodies = list(pool.map(_autocal_job, paths, [options] * len(paths)))
    if args.store:
        from app.store import open_store

        store = open_store(settings.database_url, settings.recordings_dir)
        bodies = [store.add_calibration(b, owner=None) if "error" not in b else b for b in bodies]
    if args.json:
        print(json.dumps(bodies, indent=2))
    else:
        from app.cli.printers import print_folder_table

        print_folder_table(bodies)
    return 0 if all(b.get("ok") for b in bodies) else 3
