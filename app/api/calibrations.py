"""Routes of /api/v1/calibrations: compute and store, read, list, export, apply."""

from __future__ import annotations

import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated, Any

import numpy as np
from fastapi import APIRouter, File, Form, Query, UploadFile
from fastapi.responses import Response, StreamingResponse
from starlette.background import BackgroundTask
from starlette.concurrency import run_in_threadpool

from app import methods
from app.api.deps import OwnerDep, ReaderDep, SettingsDep, StoreDep
from app.api.recordings import save_upload
from app.api.schemas.calibrations import (
    ApplyFileOptions,
    ApplyIn,
    ApplyOut,
    CalibrationList,
    CalibrationOut,
    SnippetsOut,
)
from app.io.exports.snippets import usage_snippets
from app.io.readers.kinds import NAMED_SUFFIXES
from app.io.writers.samples import MEDIA_TYPES
from app.methods import CalibrationIn
from app.store import NotFoundError, Store
from app.verdict import with_verdict
from app.words import render_body
from app.workflows.apply import apply_to_file
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
