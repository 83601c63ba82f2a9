"""Persistence of recordings, calibrations and wizard sessions: SQLite on one machine, PostgreSQL for
replicas (SQLAlchemy Core, Alembic migrations)."""

from __future__ import annotations

from pathlib import Path

from .engine import make_engine
from .migrate import SchemaError
from .repository import ConflictError, NotFoundError, Store, new_id


def open_store(database_url: str, files_dir: Path) -> Store:
    """The store a ``TRICAL_DATABASE_URL`` names (``sqlite:///path`` or ``postgresql://…``), migrated.

    With PostgreSQL the replicas share nothing but the database, so uploaded files are kept in it too.
    """
    engine = make_engine(database_url)
    return Store(engine, files_dir, keep_files_in_database=engine.dialect.name == "postgresql")


__all__ = ["ConflictError", "NotFoundError", "SchemaError", "Store", "new_id", "open_store"]
