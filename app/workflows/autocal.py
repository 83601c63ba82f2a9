"""Auto-calibration of a long recording by the pipeline of Farago et al. (IEEE Access)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from app.calibration import CalibrationError
from app.io.log import ACC_PHYSICAL_UNITS
from app.io.readers import read_log
from app.io.readers.read_options import ReadOptions
from app.workflows.calibration import Calibration
from app.workflows.gravity import reference_gravity
from app.workflows.recordings import RecordingSource, require_accelerometer, require_rate
from app.workflows.requests import AutocalRequest


def autocal(request: AutocalRequest, recording: RecordingSource) -> Calibration:
    """Method ``autocal``: an uploaded long recording, read as it was uploaded (:func:`autocalibrate_file`)."""
    require_accelerometer(recording.meta["units"], "autocal")
    # Read as the upload was (its chip or sensitivity turns counts into g), or as the stored units say.
    read_with = recording.meta.get("read_with") or {"units": recording.meta["units"]}
    unit = request.unit or (read_with.get("units") or {}).get("acc")
    options = ReadOptions(
        sampling_rate_hz=recording.meta["sampling_rate_hz"],
        units={"acc": unit} if unit else {},
        chip=read_with.get("chip"),
        instance=read_with.get("instance"),
        lsb_per_g=read_with.get("lsb_per_g"),
    )
    return autocalibrate_file(
        recording.path,
        options,
        solver=request.solver,
        gravity=request.gravity,
        latitude_deg=request.latitude_deg,
        height_m=request.height_m,
        detection={"all_axes": True} if request.all_axes else None,
        device_id=request.device_id,
        label=request.label or recording.meta.get("filename"),
        **recording.source_fields,
    )


AUTOCAL_UNITS = ACC_PHYSICAL_UNITS


def autocalibrate_file(
    path: str | Path,
    options: ReadOptions = ReadOptions(),
    *,
    progress: Callable[[int, int], object] | None = None,
    solver: str = "lm",
    gravity: float | None = None,
    latitude_deg: float | None = None,
    height_m: float | None = None,
    detection: dict[str, Any] | None = None,
    selection: dict[str, Any] | None = None,
    threads: int | None = None,
    **fields: Any,
) -> Calibration:
    """Auto-calibrate a long recording by the pipeline of Farago et al. and return the calibration.

    Parameters
    ----------
    path : str or pathlib.Path
        ``.npy`` (N×3, or N×4 with time first; memory-mapped), Parquet or CSV.
    options : app.io.readers.read_options.ReadOptions
        How to read it (:func:`app.io.readers.read_log`): the rate, needed when the file has no time column;
        the accelerometer's unit (``units["acc"]``: g or m/s²; the file's (header) unit, else m/s², when
        omitted); a CSV's columns and sign; the part and range (``chip``) or the counts per g of a CSV in
        counts; the IMU instance of a flight controller's log (PX4 ULog, ArduPilot DataFlash).
    progress : callable, optional
        ``progress(done_samples, total_samples)``.
    solver : str
        Solver of the 9-parameter fit (``lm``, ``gradient``, ``fixed16``, ``fixed32``).
    gravity, latitude_deg, height_m : float, optional
        Reference gravity for m/s² input (see :func:`reference_gravity`).
    detection, selection : dict, optional
        Options of :class:`app.calibration.segments.stationary_002.RestAccumulator` and
        :func:`app.calibration.autocal.autocalibrate`.
    threads : int, optional
        Threads of the rest detection (default: the cores,
        :func:`app.calibration.segments.stationary_002.detection_threads`); 1 where the files of a folder are the
        parallel work.
    **fields
        Added to the body (``device_id``, ``label``...).

    Returns
    -------
    Calibration
        Its plain form (:meth:`Calibration.body`) holds ``method: "autocal"``, ``model`` (triangular K, o),
        ``metrics`` (``error_before_mg``, ``error_after_mg``, ``improvement_pct`` on the control set),
        ``comparison``, ``selection``, ``detection``, ``ok``, ``warnings``, ``reasons``.
    """
    from app.calibration.segments.stationary_002 import detect_rest_segments

    path = Path(path)
    log = read_log(path, options, name=str(path))
    require_accelerometer(log.channels, "autocal")
    unit = log.units["acc"]
    if unit not in AUTOCAL_UNITS:
        raise CalibrationError(
            f"auto-calibration needs samples in g or m/s^2 (its thresholds are fractions of g); {path.name} is in "
            f"counts whose scale is unknown: give chip (e.g. chip=mpu6050-2g) for a CSV, or convert the counts "
            f"to g first"
        )
    g, notes = reference_gravity(unit, gravity, latitude_deg, height_m)
    rate = require_rate(log.sampling_rate_hz, "autocal")
    # The detection on every core, then the fit's modules (scipy.optimize, ~0.4 s to import).  Not side by side:
    # the import holds the GIL, which the detection's threads need back after each numpy call; with the default
    # 5 ms switch interval they waited for the import to end, and with 0.1 ms the switches cost about what the
    # overlap saves (by estimate under 0.1 s for a week); one after the other uses the least CPU.
    rest = detect_rest_segments(log.acc, rate, gravity=g, progress=progress, workers=threads, **(detection or {}))
    from app.calibration.autocal import autocalibrate

    result = autocalibrate(rest, solver=solver, **(selection or {}))
    fields.setdefault("label", path.name)
    return Calibration.of(
        result,
        {},
        unit=unit,
        notes=notes,
        recording={
            "format": log.format,
            "n_samples": log.n_samples,
            "sampling_rate_hz": log.sampling_rate_hz,
            "duration_s": log.n_samples / rate,
        },
        **fields,
    )
