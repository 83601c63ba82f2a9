"""SQLite persistence: one file, WAL journal, versioned migrations, durable commits.

Every write commits before the API acknowledges it, with ``synchronous=FULL`` so that an
acknowledged calibration survives a crash or power loss.
"""

from __future__ import annotations

import functools
import inspect
import json
import secrets
import sqlite3
import threading
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path

MIGRATIONS: tuple[str, ...] = (
    # 1: calibrations and recordings
    """
    CREATE TABLE calibrations (
        id TEXT PRIMARY KEY,
        method TEXT NOT NULL,
        device_id TEXT,
        label TEXT,
        owner TEXT,
        created_at TEXT NOT NULL,
        ok INTEGER NOT NULL,
        body TEXT NOT NULL
    );
    CREATE INDEX calibrations_device ON calibrations (device_id, created_at);
    CREATE TABLE recordings (
        id TEXT PRIMARY KEY,
        owner TEXT,
        created_at TEXT NOT NULL,
        format TEXT NOT NULL,
        n_samples INTEGER NOT NULL,
        sampling_rate_hz REAL NOT NULL,
        path TEXT NOT NULL,
        body TEXT NOT NULL
    );
    """,
)


class NotFoundError(LookupError):
    """No stored object has that id (or it belongs to someone else)."""


def new_id(prefix: str) -> str:
    """An unguessable identifier such as ``cal_3f9c…`` (128 random bits)."""
    return f"{prefix}_{secrets.token_hex(16)}"


def utc_now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="milliseconds").replace("+00:00", "Z")


class SQLiteStore:
    """Recordings and calibrations in one SQLite file.

    Parameters
    ----------
    path : pathlib.Path
        The database file; its directory is created if needed and the schema migrated.
    """

    def __init__(self, path: Path):
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._local = threading.local()
        # Write-ahead log: readers never block the writer; set outside any transaction.
        self._connect().execute("PRAGMA journal_mode=WAL")
        self._migrate()

    def _connect(self) -> sqlite3.Connection:
        db = getattr(self._local, "db", None)
        if db is None:
            db = sqlite3.connect(self.path, timeout=30.0, isolation_level=None)
            db.row_factory = sqlite3.Row
            db.execute("PRAGMA synchronous=FULL")
            db.execute("PRAGMA foreign_keys=ON")
            self._local.db = db
        return db

    @contextmanager
    def _tx(self):
        db = self._connect()
        db.execute("BEGIN IMMEDIATE")
        try:
            yield db
        except BaseException:
            db.execute("ROLLBACK")
            raise
        else:
            db.execute("COMMIT")

    def _migrate(self) -> None:
        with self._tx() as db:
            db.execute("CREATE TABLE IF NOT EXISTS schema_version (version INTEGER NOT NULL)")
            row = db.execute("SELECT version FROM schema_version").fetchone()
            version = row[0] if row else 0
            if row is None:
                db.execute("INSERT INTO schema_version (version) VALUES (0)")
            for number, script in enumerate(MIGRATIONS[version:], start=version + 1):
                for statement in filter(str.strip, script.split(";")):
                    db.execute(statement)
                db.execute("UPDATE schema_version SET version = ?", (number,))

    @property
    def schema_version(self) -> int:
        return self._connect().execute("SELECT version FROM schema_version").fetchone()[0]

    # -- calibrations ---------------------------------------------------------------------

    def add_calibration(self, body: dict, *, owner: str | None = None) -> dict:
        """Store a calibration; ``id`` and ``created_at`` are assigned here and returned in it."""
        body = dict(body, id=new_id("cal"), created_at=utc_now())
        with self._tx() as db:
            db.execute(
                "INSERT INTO calibrations (id, method, device_id, label, owner, created_at, ok, body)"
                " VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (
                    body["id"], body["method"], body.get("device_id"), body.get("label"), owner,
                    body["created_at"], int(bool(body.get("ok"))), json.dumps(body, allow_nan=False),
                ),
            )
        return body

    def get_calibration(self, calibration_id: str, *, owner: str | None = None) -> dict:
        row = self._connect().execute(
            "SELECT body FROM calibrations WHERE id = ? AND owner IS ?", (calibration_id, owner)
        ).fetchone()
        if row is None:
            raise NotFoundError(f"no calibration with id {calibration_id!r}")
        return json.loads(row[0])

    def list_calibrations(self, *, device_id: str | None = None, owner: str | None = None,
                          limit: int = 100) -> list[dict]:
        sql = "SELECT body FROM calibrations WHERE owner IS ?"
        args: list = [owner]
        if device_id is not None:
            sql += " AND device_id = ?"
            args.append(device_id)
        sql += " ORDER BY created_at DESC, id LIMIT ?"
        args.append(limit)
        return [json.loads(r[0]) for r in self._connect().execute(sql, args)]

    # -- recordings -----------------------------------------------------------------------

    def add_recording(self, recording_id: str, body: dict, path: Path, *, owner: str | None = None) -> dict:
        """Store a recording's metadata; its samples are already at ``path``."""
        body = dict(body, id=recording_id, created_at=utc_now())
        with self._tx() as db:
            db.execute(
                "INSERT INTO recordings (id, owner, created_at, format, n_samples, sampling_rate_hz, path, body)"
                " VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (
                    recording_id, owner, body["created_at"], body["format"], body["n_samples"],
                    body["sampling_rate_hz"], str(path), json.dumps(body, allow_nan=False),
                ),
            )
        return body

    def get_recording(self, recording_id: str, *, owner: str | None = None) -> tuple[dict, Path]:
        row = self._connect().execute(
            "SELECT body, path FROM recordings WHERE id = ? AND owner IS ?", (recording_id, owner)
        ).fetchone()
        if row is None:
            raise NotFoundError(f"no recording with id {recording_id!r}; upload it with POST /api/v1/recordings")
        return json.loads(row[0]), Path(row[1])


class OwnedStore:
    """A store seen by one owner: every method that takes ``owner`` gets this one.

    Routes use it without naming the owner, so no call can forget to confine itself.
    """

    def __init__(self, store: SQLiteStore, owner: str | None):
        self._store = store
        self.owner = owner

    def __getattr__(self, name: str):
        attr = getattr(self._store, name)
        if callable(attr) and "owner" in inspect.signature(attr).parameters:
            return functools.partial(attr, owner=self.owner)
        return attr
