"""SQLite: one file, WAL journal, ``synchronous=FULL`` so that an acknowledged write survives a
crash or power loss. The single-machine default."""

from __future__ import annotations

import sqlite3
from pathlib import Path

from .base import Store


class SQLiteStore(Store):
    """Recordings and calibrations in one SQLite file.

    Parameters
    ----------
    path : pathlib.Path
        The database file; its directory is created if needed and the schema migrated.
    files_dir : pathlib.Path, optional
        Where uploaded files are kept; ``recordings/`` beside the database by default.
    """

    def __init__(self, path: Path, files_dir: Path | None = None):
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        super().__init__(files_dir if files_dir is not None else self.path.parent / "recordings")
        # Write-ahead log: readers never block the writer; set outside any transaction.
        self._connect().execute("PRAGMA journal_mode=WAL")
        self._migrate()

    def _open(self) -> sqlite3.Connection:
        db = sqlite3.connect(self.path, timeout=30.0, isolation_level=None)
        db.row_factory = sqlite3.Row
        db.execute("PRAGMA synchronous=FULL")
        db.execute("PRAGMA foreign_keys=ON")
        return db

    def _begin(self, db) -> None:
        db.execute("BEGIN IMMEDIATE")  # take the write lock now: no upgrade deadlocks
