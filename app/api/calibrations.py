"""Routes of /api/v1/calibrations: compute and store, read, list, export, apply, check, compare."""

from __future__ import annotations

import base64
import io
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated, Any

import numpy as np
from fastapi import APIRouter, Depends, File, Form, Query, UploadFile
from fastapi.responses import Response, StreamingResponse
from starlette.background import BackgroundTask
from starlette.concurrency import run_in_threadpool

from app import methods
from app.api.deps import OwnerDep, ReaderDep, SettingsDep, StoreDep, not_a_link
from app.api.recordings import copy_limited, save_upload
from app.api.schemas.calibrations import (
    ApplyFileOptions,
    ApplyIn,
    ApplyOut,
    CalibrationList,
    CalibrationOut,
    CheckIn,
    CheckOut,
    CompareOut,
    SnippetsOut,
)
from app.calibration_requests import ImportFirmware, ImportIn
from app.io.exports.snippets import usage_snippets
from app.io.readers.kinds import NAMED_SUFFIXES
from app.io.writers.samples import MEDIA_TYPES
from app.methods import CalibrationIn
from app.store import NotFoundError, Store
from app.verdict import with_verdict
from app.words import render_body
from app.workflows.apply import apply_to_file
from app.workflows.check import check_source, check_turn, compare_calibrations
from app.workflows.recordings import RecordingSource
from app.workflows.results import apply_calibration

router = APIRouter(prefix="/api/v1/calibrations", tags=["calibrations"])


def recording_source(store: Store, recording_id: str | None, owner: str | None) -> RecordingSource | None:
    """The caller's stored recording a request names (404 when it is not theirs)."""
    if recording_id is None:
        return None
    meta, path = store.get_recording(recording_id, owner=owner)
    return RecordingSource(meta=meta, path=path, id=recording_id)


@router.post(
    "",
    status_code=201,
    response_model=CalibrationOut,
    response_model_exclude_unset=True,
    summary="Compute and store a calibration",
)
async def create_calibration(
    request: CalibrationIn, store: StoreDep, owner: OwnerDep, reader: ReaderDep
) -> dict[str, Any]:
    """Compute a calibration by `method` and store it; 201 with the stored resource."""
    # One hop to a worker thread for the fit and the store's commit; FastAPI validates and writes the answer
    # on the event loop (for a plain ``def`` route it would hop once more, for the response's validation).
    return await run_in_threadpool(calibrate_and_store, request, store, owner, reader)


def calibrate_and_store(
    request: CalibrationIn, store: Store, owner: str | None, reader: tuple[str, str | None]
) -> dict[str, Any]:
    """The body of POST /api/v1/calibrations: the calibration computed, stored, and its words for ``reader``."""
    source = recording_source(store, getattr(request, "recording_id", None), owner)
    body = methods.calibrate(request, source).body()
    # A calibration of the same upload, method (and compass) supersedes the earlier ones (none is deleted).
    key = source.supersede_key(body) if source is not None else None
    return render_body(store.add_calibration(body, owner=owner, recording_digest=key), *reader)


@router.post(
    "/import",
    status_code=201,
    response_model=CalibrationOut,
    response_model_exclude_unset=True,
    summary="Import the calibration a device already holds",
)
def import_calibration(
    *,
    file: UploadFile = File(
        ...,
        description="An ArduPilot .param/.parm or DataFlash log (.bin), a PX4 QGroundControl .params or ULog (.ulg), "
        "a Betaflight or INAV CLI `diff all`/`dump`, or trical's JSON export: recognised from its content.",
    ),
    device_id: Annotated[str | None, Form(min_length=1, max_length=200)] = None,
    label: Annotated[str | None, Form(max_length=500)] = None,
    firmware: Annotated[
        ImportFirmware | None,
        Form(description="The file's family, where its content does not say it."),
    ] = None,
    instance: Annotated[int, Form(ge=0, le=3, description="Which IMU and compass of a file holding several.")] = 0,
    settings: SettingsDep,
    store: StoreDep,
    owner: OwnerDep,
    reader: ReaderDep,
) -> dict[str, Any]:
    """Read a device's calibration from its file and store it as the device's calibration (method ``imported``;
    trical's own JSON export as the model it was written from); 201 with the stored resource."""
    data = io.BytesIO()
    copy_limited(file.file, data, 0, settings.max_upload_bytes, settings.max_upload_mb)
    request = ImportIn(
        method="imported",
        file_base64=base64.b64encode(data.getvalue()).decode("ascii"),
        firmware=firmware,
        instance=instance,
        device_id=device_id,
        label=label,
    )
    body = methods.calibrate(request).body()
    return render_body(store.add_calibration(body, owner=owner), *reader)


@router.get("", response_model=CalibrationList, response_model_exclude_unset=True, summary="List calibrations")
def list_calibrations(
    *,
    device_id: str | None = Query(None, max_length=200),
    superseded_by: str | None = Query(
        None,
        max_length=200,
        description=("List the earlier calibrations of the same recording and method this one superseded."),
    ),
    limit: int = Query(100, ge=1, le=1000),
    store: StoreDep,
    owner: OwnerDep,
    reader: ReaderDep,
) -> dict[str, Any]:
    """Calibrations, newest first, optionally of one device: one per recording and method (the latest; each
    says how many ``earlier`` it superseded), or with ``superseded_by`` those earlier ones."""
    return render_body(
        {
            "items": [
                with_verdict(body)
                for body in store.list_calibrations(
                    owner=owner, device_id=device_id, limit=limit, superseded_by=superseded_by
                )
            ]
        },
        *reader,
    )


@router.get(
    "/{calibration_id}", response_model=CalibrationOut, response_model_exclude_unset=True, summary="Read a calibration"
)
async def get_calibration(calibration_id: str, store: StoreDep, owner: OwnerDep, reader: ReaderDep) -> dict[str, Any]:
    """One stored calibration."""
    return await run_in_threadpool(read_calibration, calibration_id, store, owner, reader)


def read_calibration(
    calibration_id: str, store: Store, owner: str | None, reader: tuple[str, str | None]
) -> dict[str, Any]:
    """The body of GET /api/v1/calibrations/{id}: the stored calibration with its verdict, in ``reader``'s words."""
    return render_body(with_verdict(store.get_calibration(calibration_id, owner=owner)), *reader)


@router.get(
    "/{calibration_id}/export",
    summary="Export a calibration",
    responses={
        200: {
            "content": {
                "application/json": {},
                "text/x-c": {},
                "text/plain": {},
                "application/yaml": {},
                "text/csv": {},
                "image/svg+xml": {},
            }
        }
    },
)
def export(
    *,
    calibration_id: str,
    format: str = Query("json", description=f"By the calibration's method: {methods.formats_in_words()}"),
    store: StoreDep,
    owner: OwnerDep,
) -> Response:
    """The calibration as a file for firmware or analysis code.

    ``json`` (versioned schema), ``c`` (C99 header), ``yaml`` and ``csv`` carry the full correction
    ``a = M (m - o)``; ``ardupilot`` (``INS_ACCOFFS_*``, ``INS_ACCSCAL_*``) and ``px4``
    (``CAL_ACC0_*OFF``, ``CAL_ACC0_*SCALE``) carry offsets and per-axis scales only, fitted on the
    calibration's still readings; their comment header states the norm error the firmware reaches with them
    beside trical's full model's, and the rotation and non-orthogonality they cannot hold; ArduPilot's ranges
    are enforced.
    ``allan_svg`` draws a noise characterisation's Allan deviation (an SVG image). A temperature calibration
    exports its own ``px4`` (QGroundControl ``.params``, ``TC_A*``/``TC_G*``), ``ardupilot`` (``INS_TCAL1_*``),
    ``json`` and ``temperature_svg`` (offset against temperature).
    """
    out = methods.export(store.get_calibration(calibration_id, owner=owner), format)
    return Response(
        out.content,
        media_type=out.media_type,
        headers={"Content-Disposition": f'attachment; filename="{out.filename}"'},
    )


@router.get(
    "/{calibration_id}/use",
    response_model=SnippetsOut,
    summary="How to apply it: the corrections and paste-ready lines",
)
def snippets(calibration_id: str, store: StoreDep, owner: OwnerDep) -> dict[str, Any]:
    """Paste-ready lines that apply the calibration: C over its header, Python and JavaScript over its JSON;
    a board's counts scaled into the calibration's unit by the part its recording was read with."""
    body = store.get_calibration(calibration_id, owner=owner)
    recording: dict[str, Any] = {}
    if body.get("recording_id"):
        try:
            recording = store.get_recording(body["recording_id"], owner=owner)[0]
        except NotFoundError:
            recording = {}  # a recording deleted since: the examples name a common part's figure instead
    return usage_snippets(body, recording.get("read_with"), recording.get("scales"))


@router.post("/{calibration_id}/apply", response_model=ApplyOut, summary="Calibrate samples")
def apply(calibration_id: str, request: ApplyIn, store: StoreDep, owner: OwnerDep) -> dict[str, Any]:
    """Samples calibrated with a stored calibration."""
    body = store.get_calibration(calibration_id, owner=owner)
    calibrated = apply_calibration(body, request.samples, request.sensor)
    return {"samples": np.asarray(calibrated).tolist(), "unit": body.get("output_unit")}


@router.post(
    "/{calibration_id}/check",
    dependencies=[Depends(not_a_link)],
    response_model=CheckOut,
    summary="Check a calibration on a new recording",
)
def check_calibration(calibration_id: str, request: CheckIn, store: StoreDep, owner: OwnerDep) -> dict[str, Any]:
    """The calibration applied to a new recording of the device, or to a turn's readings: keep it, calibrate again
    (naming what drifted), move the compass, or cannot tell (saying what to record)."""
    body = store.get_calibration(calibration_id, owner=owner)
    place = {"field_ut": request.field_ut, "inclination_deg": request.inclination_deg}
    if request.recording_id is None:  # a turn's readings sent as read (the page's live turn)
        return check_turn(body, request.mag, **place)
    meta, path = store.get_recording(request.recording_id, owner=owner)
    return check_source(body, RecordingSource(meta=meta, path=path, id=request.recording_id), **place)


@router.get(
    "/{calibration_id}/compare",
    dependencies=[Depends(not_a_link)],
    response_model=CompareOut,
    response_model_by_alias=True,
    summary="Compare two calibrations of a device",
)
def compare_with(
    *,
    calibration_id: str,
    other: str = Query(..., alias="with", max_length=200, description="The other calibration's id (B; this is A)."),
    field_ut: float | None = Query(None, gt=0, le=1000, description="The place's field F in µT, for the heading."),
    inclination_deg: float | None = Query(None, ge=-90, le=90, description="The place's inclination (60° assumed)."),
    store: StoreDep,
    owner: OwnerDep,
) -> dict[str, Any]:
    """The differences B − A per parameter, with their intervals (which are real) and their effect in degrees."""
    a = store.get_calibration(calibration_id, owner=owner)
    b = store.get_calibration(other, owner=owner)
    return compare_calibrations(a, b, field_ut=field_ut, inclination_deg=inclination_deg)


STREAM_BYTES = 1 << 20
"""Bytes of the written file sent at a time by the apply-file answer."""


def _file_chunks(path: Path) -> Iterator[bytes]:
    with open(path, "rb") as f:
        while block := f.read(STREAM_BYTES):
            yield block


@router.post(
    "/{calibration_id}/apply-file",
    response_class=StreamingResponse,
    summary="Calibrate a recording: its samples, streamed as CSV, Parquet or .npy",
    responses={
        200: {
            "content": {media: {} for media in MEDIA_TYPES.values()},
            "description": "The calibrated samples, each column named with its unit (docs/rest.md).",
        }
    },
)
def apply_file(
    calibration_id: str,
    *,
    file: UploadFile = File(
        ..., description="The recording: any log the upload reads; CSV, .npy and Parquet in chunks."
    ),
    form: Annotated[ApplyFileOptions, Form()],
    settings: SettingsDep,
    store: StoreDep,
    owner: OwnerDep,
) -> StreamingResponse:
    """A stored calibration applied to every sample of an uploaded recording; the rows streamed back."""
    body = store.get_calibration(calibration_id, owner=owner)
    work = Path(tempfile.mkdtemp(prefix="trical-apply-"))
    try:
        suffix = Path(file.filename or "").suffix.lower()
        source = work / f"recording{suffix if suffix in NAMED_SUFFIXES else '.csv'}"
        save_upload(file.file, source, settings.max_upload_bytes, settings.max_upload_mb)
        fmt = form.output_format
        with open(work / f"calibrated.{fmt}", "wb") as out:
            applied = apply_to_file(
                body, source, out, fmt=fmt, options=form.read_options(), name=Path(file.filename or "the file").name
            )
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise
    return StreamingResponse(
        _file_chunks(work / f"calibrated.{fmt}"),
        media_type=MEDIA_TYPES[fmt],
        headers={
            "Content-Disposition": f'attachment; filename="{calibration_id}-calibrated.{fmt}"',
            "X-Trical-Rows": str(applied.rows),
            "X-Trical-Corrected": ",".join(applied.corrected),
            "X-Trical-Passed-Through": ",".join(applied.passed),
            "X-Trical-Streamed": "true" if applied.streamed else "false",
        },
        background=BackgroundTask(shutil.rmtree, work, ignore_errors=True),
    )
