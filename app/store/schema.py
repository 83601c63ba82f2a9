"""The database schema, once, in SQLAlchemy Core: what the repository (app.store.repository) reads
and writes. The Alembic migrations (app/store/migrations/versions) build exactly these tables.

Bodies are JSON text; ``created_at`` is an ISO 8601 UTC string, so it sorts as text.
"""

from __future__ import annotations

from sqlalchemy import (
    REAL,
    Column,
    ForeignKey,
    Index,
    Integer,
    LargeBinary,
    MetaData,
    PrimaryKeyConstraint,
    Table,
    Text,
)

metadata = MetaData()

calibrations = Table(
    "calibrations",
    metadata,
    Column("id", Text, primary_key=True),
    Column("method", Text, nullable=False),
    Column("device_id", Text),
    Column("label", Text),
    Column("owner", Text),
    Column("created_at", Text, nullable=False),
    Column("ok", Integer, nullable=False),
    Column("body", Text, nullable=False),
    # The SHA-256 of the recording's upload (a calibration of one): with the method, what "the same reading" is.
    Column("recording_digest", Text),
    Column("superseded_by", Text),  # the later calibration of the same recording and method, if any
    Index("calibrations_device", "device_id", "created_at"),
    Index("calibrations_recording", "recording_digest", "method"),
    Index("calibrations_superseded", "superseded_by"),
)

recordings = Table(
    "recordings",
    metadata,
    Column("id", Text, primary_key=True),
    Column("owner", Text),
    Column("created_at", Text, nullable=False),
    Column("format", Text, nullable=False),
    Column("n_samples", Integer, nullable=False),
    Column("sampling_rate_hz", REAL, nullable=False),  # informative: the body holds the exact rate (0: none)
    Column("path", Text, nullable=False),  # the file's name inside the store's files_dir
    Column("body", Text, nullable=False),
)

recording_files = Table(
    "recording_files",
    metadata,
    Column("id", Text, primary_key=True),  # the recording's id
    Column("content", LargeBinary, nullable=False),
)
"""Uploaded files kept in the database itself, so that replicas share nothing else."""

sessions = Table(
    "sessions",
    metadata,
    Column("id", Text, primary_key=True),
    Column("token_hash", Text, nullable=False, unique=True),
    Column("owner", Text),
    Column("protocol", Text, nullable=False),
    Column("created_at", Text, nullable=False),
    Column("calibration_id", Text),
    Column("body", Text, nullable=False),
)

session_captures = Table(
    "session_captures",
    metadata,
    Column("session_id", Text, ForeignKey("sessions.id"), nullable=False),
    Column("position", Text, nullable=False),
    Column("created_at", Text, nullable=False),
    Column("summary", Text, nullable=False),
    Column("samples", Text, nullable=False),  # the raw samples of the pose (and of the move to it), JSON
    PrimaryKeyConstraint("session_id", "position"),
)

links = Table(
    "links",
    metadata,
    Column("code", Text, primary_key=True),  # short and random: what the link carries
    Column("calibration_id", Text, nullable=False),
    Column("owner", Text),  # the calibration's owner: the link reads as it, that one calibration only
    Column("created_at", Text, nullable=False),
    Column("expires_at", Text, nullable=False),
)
"""Short links that let another device read one calibration until they expire."""
