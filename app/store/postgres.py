"""PostgreSQL, for replicated deployments: the replicas share nothing but this database.

The shared SQL of app.store.base is run through a thin connection that speaks PostgreSQL's
dialect (``%s`` parameters, ``IS NOT DISTINCT FROM``, ``BYTEA``); commits are synchronous, so an
acknowledged write is on the server's disk. Uploaded files are kept in the database too.
"""

from __future__ import annotations

import re
from pathlib import Path

from .base import Store

_IS_PARAM = re.compile(r"\bIS \?")


def translate(sql: str) -> str:
    """The shared SQL in PostgreSQL's dialect."""
    sql = _IS_PARAM.sub("IS NOT DISTINCT FROM ?", sql)
    sql = re.sub(r"\bBLOB\b", "BYTEA", sql)
    return sql.replace("?", "%s")


class _Row(tuple):
    """A row addressable by position and by column name, like sqlite3.Row."""

    names: tuple = ()

    def __getitem__(self, key):
        if isinstance(key, str):
            return tuple.__getitem__(self, self.names.index(key))
        return tuple.__getitem__(self, key)

    def keys(self):
        return list(self.names)


def _row_factory(cursor):
    names = tuple(d.name for d in cursor.description or ())
    row_type = type("Row", (_Row,), {"names": names})
    return lambda values: row_type(values)


class _Connection:
    """Runs the shared SQL on a psycopg connection in autocommit mode (explicit BEGIN/COMMIT)."""

    def __init__(self, url: str):
        import psycopg

        self._db = psycopg.connect(url, autocommit=True, row_factory=_row_factory)

    def execute(self, sql: str, args=()):
        return self._db.execute(translate(sql), tuple(args))


class PostgresStore(Store):
    """Recordings and calibrations in a PostgreSQL database.

    Parameters
    ----------
    url : str
        ``postgresql://user:password@host:port/database``.
    files_dir : pathlib.Path
        This replica's cache of uploaded files (the database holds the originals).
    """

    def __init__(self, url: str, files_dir: Path):
        self.url = url
        super().__init__(files_dir, keep_files_in_database=True)
        self._migrate()

    def _open(self) -> _Connection:
        return _Connection(self.url)

    def _lock_schema(self, db) -> None:
        # Replicas starting together migrate one after the other.
        db.execute("SELECT pg_advisory_xact_lock(7357001)")
