"""The one dialect-specific part of the store: the engine a ``TRICAL_DATABASE_URL`` names.

SQLite (one machine): WAL journal (readers never block the writer), ``synchronous=FULL`` (an
acknowledged write survives a crash or power loss), foreign keys on, and writes that take the write
lock at ``BEGIN IMMEDIATE`` (no lock-upgrade deadlocks between two writers). PostgreSQL (replicas):
psycopg 3; commits are synchronous, so an acknowledged write is on the server's disk.
"""

from __future__ import annotations

from pathlib import Path

from sqlalchemy import Engine, create_engine, event
from sqlalchemy.engine import make_url

from app.config import database_url_problem, sqlite_path

WRITE = "trical_write"
"""Execution option of the connections that write (``BEGIN IMMEDIATE`` on SQLite)."""
POOL = {"pool_size": 5, "max_overflow": 35}
"""Up to 40 connections: one for each thread of the server's pool (AnyIO's default), so that no
request waits for a connection."""


SQLITE_PRAGMAS = {"journal_mode": "WAL", "synchronous": "FULL", "foreign_keys": "ON"}
"""Set on each SQLite connection. In WAL mode ``synchronous=FULL`` syncs the log at every commit, so a
commit that returned survives power loss; ``NORMAL`` would sync only at checkpoints (sqlite.org/pragma.html)."""


def make_engine(database_url: str) -> Engine:
    """The engine of ``sqlite:///path`` or ``postgresql://…`` (also ``postgres://``), pooled."""
    problem = database_url_problem(database_url)
    if problem is not None:
        raise ValueError(f"TRICAL_DATABASE_URL {problem}; got {database_url!r}")
    path = sqlite_path(database_url)
    if path is not None:
        return _sqlite_engine(path)
    url = make_url(database_url).set(drivername="postgresql+psycopg")
    return create_engine(url, pool_pre_ping=True, **POOL)


def _sqlite_engine(path: Path) -> Engine:
    path.parent.mkdir(parents=True, exist_ok=True)
    engine = create_engine(f"sqlite:///{path}", connect_args={"timeout": 30.0, "check_same_thread": False}, **POOL)

    @event.listens_for(engine, "connect")
    def _configure(dbapi_connection, _record):
        # Transactions are begun by the "begin" listener below, not by the sqlite3 module.
        dbapi_connection.isolation_level = None
        cursor = dbapi_connection.cursor()
        for name, value in SQLITE_PRAGMAS.items():
            cursor.execute(f"PRAGMA {name}={value}")
        cursor.close()

    @event.listens_for(engine, "begin")
    def _begin(connection):
        # A writer takes the write lock now; a reader reads a snapshot without blocking anyone.
        connection.exec_driver_sql("BEGIN IMMEDIATE" if connection.get_execution_options().get(WRITE) else "BEGIN")

    return engine
