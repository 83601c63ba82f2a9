"""Routes of /api/v1/calibrations: compute and store, read, list, export, apply."""

from __future__ import annotations

import numpy as np
from fastapi import APIRouter, Depends, Query
from fastapi.responses import Response

from app import workflow
from app.api.deps import get_owner, get_store
from app.api.schemas import (
    ApplyIn,
    ApplyOut,
    AutocalIn,
    CalibrationIn,
    CalibrationList,
    CalibrationOut,
    CubeIn,
    KnownOrientationIn,
    UnknownOrientationIn,
)
from app.io.exporters import EXPORTERS, export_calibration
from app.store import Store

router = APIRouter(prefix="/api/v1/calibrations", tags=["calibrations"])


def _source(request, store: Store, owner: str | None) -> tuple[dict | None, str, float, list[str]]:
    """The recording (if any), the unit, the reference magnitude and notes for a request."""
    recording = None
    unit = request.unit
    notes: list[str] = []
    if request.recording_id is not None:
        recording, _ = store.get_recording(request.recording_id, owner=owner)
        if request.unit != recording["units"]["acc"]:
            notes.append(
                f"the recording's accelerometer unit is {recording['units']['acc']}; the request's unit "
                f"{request.unit} was replaced by it"
            )
        unit = recording["units"]["acc"]
        if recording.get("quantization_step"):
            notes.append(
                f"the recording's values are rounded to {recording['quantization_step']} m/s² (as browsers "
                "round motion sensor data): each reading's mean is still precise when averaged over many samples"
            )
    gravity, more = workflow.reference_gravity(unit, request.gravity, request.latitude_deg, request.height_m)
    return recording, unit, gravity, notes + more


def _known_orientation_body(request: KnownOrientationIn, store: Store, owner: str | None) -> dict:
    recording, unit, gravity, notes = _source(request, store, owner)
    source: dict = {}
    if recording is not None:
        readings, used = workflow.readings_from_segments(recording, request.method, request.segments)
        source = {"recording_id": request.recording_id, "segments_used": used}
    else:
        readings = [workflow.Reading(mean=tuple(r.mean), up=r.up,
                                     expected=None if r.expected is None else tuple(r.expected),
                                     std=None if r.std is None else tuple(r.std), count=r.count)
                    for r in request.readings]
    result, extra = workflow.calibrate_known(request.method, readings, unit=unit, gravity=gravity,
                                             holdout=request.holdout)
    return workflow.calibration_body(result, extra, unit=unit, notes=notes, device_id=request.device_id,
                                     label=request.label, **source)


def _unknown_orientation_body(request: UnknownOrientationIn, store: Store, owner: str | None) -> dict:
    recording, unit, gravity, notes = _source(request, store, owner)
    source: dict = {}
    means = request.means
    if recording is not None:
        means, used = workflow.means_from_segments(recording, request.segments)
        source = {"recording_id": request.recording_id, "segments_used": used}
    result, extra = workflow.calibrate_unknown(request.method, means, unit=unit, gravity=gravity,
                                               solver=getattr(request, "solver", "lm"), holdout=request.holdout)
    return workflow.calibration_body(result, extra, unit=unit, notes=notes, device_id=request.device_id,
                                     label=request.label, **source)


def _cube_body(request: CubeIn, store: Store, owner: str | None) -> dict:
    recording, path = store.get_recording(request.recording_id, owner=owner)
    log = workflow.load_log(path, sampling_rate_hz=recording["sampling_rate_hz"], units=recording["units"],
                            name=recording.get("filename") or "the recording")
    unit = log.units["acc"]
    gravity, notes = workflow.reference_gravity(unit, request.gravity, request.latitude_deg, request.height_m)
    result = workflow.calibrate_cube_log(log, protocol=request.protocol, gravity=gravity, field_ut=request.field_ut)
    return workflow.calibration_body(result, {}, unit=unit, notes=notes, device_id=request.device_id,
                                     label=request.label, recording_id=request.recording_id, units=log.units)


@router.post("", status_code=201, response_model=CalibrationOut, summary="Compute and store a calibration")
def create_calibration(request: CalibrationIn, store: Store = Depends(get_store),
                       owner: str | None = Depends(get_owner)):
    """Compute a calibration by `method` and store it; 201 with the stored resource."""
    if isinstance(request, KnownOrientationIn):
        body = _known_orientation_body(request, store, owner)
    elif isinstance(request, CubeIn):
        body = _cube_body(request, store, owner)
    elif isinstance(request, AutocalIn):
        body = _autocal_body(request, store, owner)
    else:
        body = _unknown_orientation_body(request, store, owner)
    return store.add_calibration(body, owner=owner)


def _autocal_body(request: AutocalIn, store: Store, owner: str | None) -> dict:
    recording, path = store.get_recording(request.recording_id, owner=owner)
    return workflow.autocalibrate_file(
        path, sampling_rate_hz=recording["sampling_rate_hz"], unit=request.unit or recording["units"]["acc"],
        solver=request.solver, gravity=request.gravity, latitude_deg=request.latitude_deg,
        height_m=request.height_m, detection={"all_axes": True} if request.all_axes else None,
        device_id=request.device_id, label=request.label or recording.get("filename"),
        recording_id=request.recording_id)


@router.get("", response_model=CalibrationList, summary="List calibrations")
def list_calibrations(device_id: str | None = Query(None, max_length=200),
                      limit: int = Query(100, ge=1, le=1000), store: Store = Depends(get_store),
                      owner: str | None = Depends(get_owner)):
    """Calibrations, newest first, optionally of one device."""
    return {"items": store.list_calibrations(owner=owner, device_id=device_id, limit=limit)}


@router.get("/{calibration_id}", response_model=CalibrationOut, summary="Read a calibration")
def get_calibration(calibration_id: str, store: Store = Depends(get_store),
                    owner: str | None = Depends(get_owner)):
    """One stored calibration."""
    return store.get_calibration(calibration_id, owner=owner)


@router.get("/{calibration_id}/export", summary="Export a calibration",
            responses={200: {"content": {"application/json": {}, "text/x-c": {}, "text/plain": {},
                                         "application/yaml": {}, "text/csv": {}}}})
def export(calibration_id: str, format: str = Query("json", description=f"One of {', '.join(EXPORTERS)}"),
           store: Store = Depends(get_store), owner: str | None = Depends(get_owner)):
    """The calibration as a file for firmware or analysis code.

    ``json`` (versioned schema), ``c`` (C99 header), ``yaml`` and ``csv`` carry the full correction
    ``a = M (m - o)``; ``ardupilot`` (``INS_ACCOFFS_*``, ``INS_ACCSCAL_*``) and ``px4``
    (``CAL_ACC0_*OFF``, ``CAL_ACC0_*SCALE``) carry offsets and per-axis scales only, their comment
    header reporting the residual of the dropped cross-axis terms; ArduPilot's ranges are enforced.
    """
    out = export_calibration(store.get_calibration(calibration_id, owner=owner), format)
    return Response(out.content, media_type=out.media_type,
                    headers={"Content-Disposition": f'attachment; filename="{out.filename}"'})


@router.post("/{calibration_id}/apply", response_model=ApplyOut, summary="Calibrate samples")
def apply(calibration_id: str, request: ApplyIn, store: Store = Depends(get_store),
          owner: str | None = Depends(get_owner)):
    """Samples calibrated with a stored calibration."""
    body = store.get_calibration(calibration_id, owner=owner)
    calibrated = workflow.apply_calibration(body, request.samples, request.sensor)
    return {"samples": np.asarray(calibrated).tolist(), "unit": body.get("output_unit")}
