"""Persistence of recordings, calibrations and wizard sessions: SQLite on one machine, PostgreSQL for replicas."""

from __future__ import annotations

from pathlib import Path

from .base import ConflictError, NotFoundError, OwnedStore, Store
from .sqlite import SQLiteStore


def open_store(database_url: str, files_dir: Path) -> Store:
    """The store a ``TRICAL_DATABASE_URL`` names (``sqlite:///path`` or ``postgresql://…``)."""
    if database_url.startswith(("postgresql://", "postgres://")):
        from .postgres import PostgresStore

        return PostgresStore(database_url, files_dir)
    prefix = "sqlite:///"
    if not database_url.startswith(prefix):
        raise ValueError(
            f"TRICAL_DATABASE_URL must be sqlite:///path/to/trical.db or postgresql://user@host/db; got {database_url!r}"
        )
    return SQLiteStore(Path(database_url[len(prefix):]), files_dir)


__all__ = ["ConflictError", "NotFoundError", "OwnedStore", "SQLiteStore", "Store", "open_store"]
