"""``trical autocal``: Farago et al.'s pipeline on one long recording, or on a folder of them (local processes
or a Dask cluster)."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from app.calibration import CalibrationError
from app.calibration.shared.cores import usable_cores
from app.calibration.shared.result import NormErrors
from app.cli.reading import read_options
from app.io.errors import LogFormatError
from app.workflows.autocal import autocalibrate_file

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings

# The printers (app.words imports the method table, ~0.4 s) and the store are imported where they are used:
# `trical autocal FILE --json` needs neither.


def _autocal_options(args) -> dict:
    read = read_options(args, units={"acc": args.unit} if args.unit else {})
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
        return autocalibrate_file(path, **options).body()
    except (CalibrationError, LogFormatError) as exc:
        return {"label": Path(path).name, "ok": False, "error": str(exc)}
    except Exception as exc:  # a worker must report, never take the run down
        return {"label": Path(path).name, "ok": False, "error": f"{type(exc).__name__}: {exc}"}


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical autocal PATH``: one recording (a progress bar on a terminal), or a folder of them."""
    options = _autocal_options(args)
    if args.path.is_dir():
        return _autocal_folder(args, settings, options)
    progress = None
    if sys.stderr.isatty():
        from app.cli.printers import ProgressBar

        progress = ProgressBar(args.path.name)
    body = autocalibrate_file(args.path, progress=progress, **options).body()
    if args.store:
        from app.cli.finish import store_of

        body = store_of(settings).add_calibration(body, owner=None)
    if args.json:
        print(json.dumps(body, indent=2))
    else:
        summary(body, verbose=args.verbose)
    return 0 if body["ok"] else 3


def _folder_files(folder: Path) -> list[Path]:
    from app.io.readers.arrays import SUFFIXES

    files = sorted(p for p in folder.iterdir() if p.is_file() and p.suffix.lower() in SUFFIXES)
    if not files:
        raise LogFormatError(f"{folder} holds no .npy, .parquet or .csv recordings")
    return files


def _progress_line(done: int, total: int, path: str, body: dict, seconds: float) -> str:
    """One line per finished file, in the order they finish: ``[3/8] rec_002.npy: ok, 0.11 mg after (4.2 s)``."""
    if "error" in body:
        what = f"error: {body['error'].splitlines()[0] if body['error'] else 'no message'}"
    else:
        after = NormErrors.of(body.get("metrics") or {}).after  # on the control points, held out of the fit
        what = ("ok" if body.get("ok") else "not ok") + ("" if after is None else f", {after:.3g} mg after")
        if not body.get("ok") and body.get("reasons"):
            what += f": {body['reasons'][0][:80]}"
    return f"[{done}/{total}] {Path(path).name}: {what} ({seconds:.1f} s)"


def _finished_jobs(args, paths: list[str], options: dict):
    """(index, body) of each file as it finishes: on the Dask cluster given, else on a process per core (or
    ``--workers``); each file's rest detection on one thread, the files being the parallel work."""
    if args.dask_scheduler:
        try:
            from dask.distributed import Client, as_completed
        except ImportError:
            raise CalibrationError(
                "--dask-scheduler needs dask.distributed, which is not installed: pip install 'dask[distributed]' "
                "(or leave --dask-scheduler out to use local processes)"
            ) from None
        with Client(args.dask_scheduler) as client:
            futures = [client.submit(_autocal_job, p, {**options, "threads": 1}, pure=False) for p in paths]
            index = {f.key: i for i, f in enumerate(futures)}
            for future in as_completed(futures):
                yield index[future.key], future.result()
        return
    workers = min(len(paths), args.workers or usable_cores())
    if workers <= 1:
        for i, p in enumerate(paths):
            yield i, _autocal_job(p, options)  # one process: its detection may use every core
        return
    from concurrent.futures import ProcessPoolExecutor
    from concurrent.futures import as_completed as finished

    with ProcessPoolExecutor(max_workers=workers) as pool:
        index = {pool.submit(_autocal_job, p, {**options, "threads": 1}): i for i, p in enumerate(paths)}
        for future in finished(index):
            yield index[future], future.result()


def _autocal_folder(args, settings: Callable[[], Settings], options: dict) -> int:
    """Every recording of a folder, in parallel; a line on stderr as each finishes, the bodies (or the table) in
    the files' order once all have."""
    import time

    files = _folder_files(args.path)
    paths = [str(p) for p in files]
    bodies: list[dict] = [{} for _ in paths]
    start = time.perf_counter()
    for done, (i, body) in enumerate(_finished_jobs(args, paths, options), start=1):
        bodies[i] = body
        print(
            _progress_line(done, len(paths), paths[i], body, time.perf_counter() - start), file=sys.stderr, flush=True
        )
    if args.store:
        from app.cli.finish import store_of

        store = store_of(settings)
        bodies = [store.add_calibration(b, owner=None) if "error" not in b else b for b in bodies]
    if args.json:
        print(json.dumps(bodies, indent=2))
    else:
        from app.cli.printers import print_folder_table

        print_folder_table(bodies)
    return 0 if all(b.get("ok") for b in bodies) else 3


def summary(body: dict, verbose: bool = False) -> None:
    """The command's summary of one file's auto-calibration (``--verbose``: every note)."""
    from app.cli.printers import print_autocal

    print_autocal(body, verbose)
