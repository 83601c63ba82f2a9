"""Routes of /api/v1/recordings: upload a log, read its segments."""

from __future__ import annotations

import zipfile
from pathlib import Path, PurePath
from typing import IO, Annotated, Any, BinaryIO

from fastapi import APIRouter, File, Form, UploadFile

from app.api.deps import OwnerDep, ReaderDep, SettingsDep, StoreDep
from app.api.errors import PayloadTooLarge
from app.api.schemas.recordings import RecordingOut, UploadOptions
from app.io.readers.kinds import NAMED_SUFFIXES
from app.io.readers.parts import refuse_repeated_names
from app.store import new_id
from app.words import render_body
from app.workflows.recordings import add_recording

router = APIRouter(prefix="/api/v1/recordings", tags=["recordings"])
CHUNK = 1 << 20


def copy_limited(source: BinaryIO, out: IO[bytes], size: int, limit_bytes: int, limit_mb: float) -> int:
    """Copy ``source`` into ``out`` in chunks; ``size`` counts what came before. Refuses past the limit."""
    while chunk := source.read(CHUNK):
        size += len(chunk)
        if size > limit_bytes:
            raise PayloadTooLarge(limit_mb)
        out.write(chunk)
    return size


def save_upload(source: BinaryIO, dest: Path, limit_bytes: int, limit_mb: float) -> int:
    """Copy an upload to ``dest`` in chunks, refusing it past the size limit; returns its size."""
    dest.parent.mkdir(parents=True, exist_ok=True)
    try:
        with open(dest, "wb") as out:
            return copy_limited(source, out, 0, limit_bytes, limit_mb)
    except BaseException:
        dest.unlink(missing_ok=True)
        raise


def save_uploads_as_zip(uploads: list[tuple[str, BinaryIO]], dest: Path, limit_bytes: int, limit_mb: float) -> None:
    """Store several uploaded files as one zip, each under its own name, refusing them past the size limit
    (counted over all of them)."""
    refuse_repeated_names([name for name, _ in uploads])
    dest.parent.mkdir(parents=True, exist_ok=True)
    size = 0
    try:
        with zipfile.ZipFile(dest, "w", compression=zipfile.ZIP_DEFLATED) as zf:
            for name, source in uploads:
                with zf.open(name, "w", force_zip64=True) as out:
                    size = copy_limited(source, out, size, limit_bytes, limit_mb)
    except BaseException:
        dest.unlink(missing_ok=True)
        raise


def _part_name(upload: UploadFile, i: int) -> str:
    return PurePath((upload.filename or "").replace("\\", "/")).name or f"file{i + 1}.csv"


@router.post("", status_code=201, response_model=RecordingOut, summary="Upload a log, or one file per pose")
def upload_recording(
    *,
    file: list[UploadFile] = File(
        ...,
        description=(
            "A log: CSV with or without a header row, a JSON array of samples, a phyphox / Sensor Logger zip, .npy / "
            ".parquet samples, a PX4 ULog (.ulg) or ArduPilot DataFlash (.bin) flight log, or a zip of log files. "
            "Several `file` parts (one file per pose) are one recording in parts, in the order given; files named one "
            "per sensor (accelerometer.csv, gyroscope.csv, magnetometer.csv) whose times overlap are merged onto one "
            "clock (app.io.readers.sensor_files)."
        ),
    ),
    form: Annotated[UploadOptions, Form()],
    settings: SettingsDep,
    store: StoreDep,
    owner: OwnerDep,
    reader: ReaderDep,
) -> dict[str, Any]:
    """Store a log (or one file per pose, as one recording) and return its static segments with their orientation."""
    recording_id = new_id("rec")
    if len(file) == 1:
        filename = file[0].filename
        suffix = Path(filename or "").suffix.lower()
        dest = settings.recordings_dir / f"{recording_id}{suffix if suffix in NAMED_SUFFIXES else '.csv'}"
        save_upload(file[0].file, dest, settings.max_upload_bytes, settings.max_upload_mb)
    else:  # one file per pose: kept together, each under its name, and read as a zip of them (app.io.readers.parts)
        names = [_part_name(f, i) for i, f in enumerate(file)]
        filename = ", ".join(names)
        dest = settings.recordings_dir / f"{recording_id}.zip"
        save_uploads_as_zip(
            [(n, f.file) for n, f in zip(names, file)], dest, settings.max_upload_bytes, settings.max_upload_mb
        )
    options = form.read_options()
    return render_body(
        add_recording(store, recording_id, dest, filename=filename, options=options, owner=owner), *reader
    )


@router.get("/{recording_id}", response_model=RecordingOut, summary="Read a recording's metadata")
def get_recording(recording_id: str, store: StoreDep, owner: OwnerDep, reader: ReaderDep) -> dict[str, Any]:
    """A recording's metadata and static segments."""
    body, _ = store.get_recording(recording_id, owner=owner)
    return render_body(body, *reader)
