"""Persistence of recordings, calibrations and wizard sessions: SQLite on one machine, PostgreSQL for
replicas (SQLAlchemy Core, Alembic migrations).

The errors are imported at once; the rest (SQLAlchemy and Alembic, a third of a second) when first
named, so that a command that opens no database does not pay for it (PEP 562).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from .errors import ConflictError, NotFoundError

if TYPE_CHECKING:
    from .migrate import SchemaError
    from .repository import Store, new_id

_LAZY = {"SchemaError": "migrate", "Store": "repository", "new_id": "repository"}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def open_store(database_url: str, files_dir: Path) -> Store:
    """The store a ``TRICAL_DATABASE_URL`` names (``sqlite:///path`` or ``postgresql://…``), migrated.

    With PostgreSQL the replicas share nothing but the database, so uploaded files are kept in it too.
    """
    from .engine import make_engine
    from .repository import Store

    engine = make_engine(database_url)
    return Store(engine, files_dir, keep_files_in_database=engine.dialect.name == "postgresql")


__all__ = ["ConflictError", "NotFoundError", "SchemaError", "Store", "new_id", "open_store"]
