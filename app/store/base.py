"""What every store does, whatever the database: versioned migrations, calibrations, recordings,
wizard sessions.

The SQL here is written once, with ``?`` parameters and ``owner IS ?``; each backend's connection
runs it in its own dialect (app.store.sqlite, app.store.postgres). Every write commits before the
API acknowledges it.
"""

from __future__ import annotations

import functools
import inspect
import json
import secrets
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
    # 2: uploaded files kept in the database itself, so that replicas share nothing else
    """
    CREATE TABLE recording_files (
        id TEXT PRIMARY KEY,
        content BLOB NOT NULL
    );
    """,
    # 3: wizard sessions and the raw samples of each capture (issue 6)
    """
    CREATE TABLE sessions (
        id TEXT PRIMARY KEY,
        token_hash TEXT NOT NULL UNIQUE,
        owner TEXT,
        protocol TEXT NOT NULL,
        created_at TEXT NOT NULL,
        calibration_id TEXT,
        body TEXT NOT NULL
    );
    CREATE TABLE session_captures (
        session_id TEXT NOT NULL REFERENCES sessions (id),
        position TEXT NOT NULL,
        created_at TEXT NOT NULL,
        summary TEXT NOT NULL,
        samples TEXT NOT NULL,
        PRIMARY KEY (session_id, position)
    );
    """,
)


class NotFoundError(LookupError):
    """No stored object has that id (or it belongs to someone else)."""


class ConflictError(Exception):
    """The write would replace something that exists (a pose already captured)."""


def new_id(prefix: str) -> str:
    """An unguessable identifier such as ``cal_3f9c…`` (128 random bits)."""
    return f"{prefix}_{secrets.token_hex(16)}"


def utc_now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="milliseconds").replace("+00:00", "Z")


class Store:
    """Recordings, calibrations and sessions; a backend defines ``_open()`` and ``_begin(db)``.

    Parameters
    ----------
    files_dir : pathlib.Path
        Where uploaded files are kept on this machine (created if needed).
    keep_files_in_database : bool
        Also store each uploaded file in the database, for replicas that share nothing else.
    """

    def __init__(self, files_dir: Path, *, keep_files_in_database: bool = False):
        self.files_dir = Path(files_dir)
        self.files_dir.mkdir(parents=True, exist_ok=True)
        self.keep_files_in_database = keep_files_in_database
        self._local = threading.local()

    def _open(self):  # pragma: no cover - every backend defines it
        raise NotImplementedError

    def _begin(self, db) -> None:
        db.execute("BEGIN")

    def _lock_schema(self, db) -> None:
        """Serialise migrations between processes that start together (a no-op where BEGIN does)."""

    def _connect(self):
        db = getattr(self._local, "db", None)
        if db is None:
            db = self._local.db = self._open()
        return db

    @contextmanager
    def _tx(self):
        db = self._connect()
        self._begin(db)
        try:
            yield db
        except BaseException:
            db.execute("ROLLBACK")
            raise
        else:
            db.execute("COMMIT")

    def _migrate(self) -> None:
        with self._tx() as db:
            self._lock_schema(db)
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
        """Store a recording's metadata; its file is already at ``path``, inside ``files_dir``."""
        body = dict(body, id=recording_id, created_at=utc_now())
        with self._tx() as db:
            if self.keep_files_in_database:
                db.execute("INSERT INTO recording_files (id, content) VALUES (?, ?)",
                           (recording_id, Path(path).read_bytes()))
            db.execute(
                "INSERT INTO recordings (id, owner, created_at, format, n_samples, sampling_rate_hz, path, body)"
                " VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (
                    recording_id, owner, body["created_at"], body["format"], body["n_samples"],
                    body["sampling_rate_hz"], Path(path).name, json.dumps(body, allow_nan=False),
                ),
            )
        return body

    def get_recording(self, recording_id: str, *, owner: str | None = None) -> tuple[dict, Path]:
        row = self._connect().execute(
            "SELECT body, path FROM recordings WHERE id = ? AND owner IS ?", (recording_id, owner)
        ).fetchone()
        if row is None:
            raise NotFoundError(f"no recording with id {recording_id!r}; upload it with POST /api/v1/recordings")
        path = self.files_dir / row[1]
        if not path.exists() and self.keep_files_in_database:
            # Uploaded through another replica: bring the file from the database.
            content = self._connect().execute("SELECT content FROM recording_files WHERE id = ?",
                                              (recording_id,)).fetchone()
            if content is not None:
                tmp = path.with_suffix(path.suffix + ".part")
                tmp.write_bytes(bytes(content[0]))
                tmp.replace(path)
        return json.loads(row[0]), path


    # -- wizard sessions ----------------------------------------------------------------------
    # A session is reached by its token alone (the owner column records who created it, for the
    # API-key case); its calibrations are owned by ``session:<id>`` (app.api.deps).

    def add_session(self, body: dict, token_hash: str, *, owner: str | None = None) -> dict:
        """Store a new session; ``id`` and ``created_at`` are assigned here."""
        body = dict(body, id=new_id("ses"), created_at=utc_now())
        with self._tx() as db:
            db.execute(
                "INSERT INTO sessions (id, token_hash, owner, protocol, created_at, calibration_id, body)"
                " VALUES (?, ?, ?, ?, ?, NULL, ?)",
                (body["id"], token_hash, owner, body["protocol"], body["created_at"], json.dumps(body, allow_nan=False)),
            )
        return body

    def session_id_for_token(self, token_hash: str) -> str | None:
        row = self._connect().execute("SELECT id FROM sessions WHERE token_hash = ?", (token_hash,)).fetchone()
        return None if row is None else row[0]

    def get_session(self, session_id: str) -> dict:
        """The session with its captures' summaries (in the order they were taken) and calibration id."""
        db = self._connect()
        row = db.execute("SELECT body, calibration_id FROM sessions WHERE id = ?", (session_id,)).fetchone()
        if row is None:
            raise NotFoundError(f"no session with id {session_id!r}; start one with POST /api/v1/sessions")
        captures = db.execute(
            "SELECT summary FROM session_captures WHERE session_id = ? ORDER BY created_at, position", (session_id,)
        ).fetchall()
        return dict(json.loads(row[0]), calibration_id=row[1], captures=[json.loads(c[0]) for c in captures])

    def add_capture(self, session_id: str, summary: dict, samples: dict, *, replace: bool = False) -> dict:
        """Store one capture of a pose; a second one of the same pose needs ``replace``.

        Raises
        ------
        ConflictError
            The pose is captured already and ``replace`` is false.
        """
        summary = dict(summary, created_at=utc_now())
        args = (session_id, summary["position"], summary["created_at"], json.dumps(summary, allow_nan=False),
                json.dumps(samples, allow_nan=False))
        sql = ("INSERT INTO session_captures (session_id, position, created_at, summary, samples)"
               " VALUES (?, ?, ?, ?, ?) ON CONFLICT (session_id, position) DO ")
        with self._tx() as db:
            if replace:
                db.execute(sql + "UPDATE SET created_at = excluded.created_at, summary = excluded.summary,"
                                 " samples = excluded.samples", args)
            elif db.execute(sql + "NOTHING", args).rowcount == 0:
                raise ConflictError(summary["position"])
        return summary

    def get_capture_samples(self, session_id: str, position: str) -> dict:
        row = self._connect().execute(
            "SELECT samples FROM session_captures WHERE session_id = ? AND position = ?", (session_id, position)
        ).fetchone()
        if row is None:
            raise NotFoundError(f"session {session_id!r} has no capture of {position}")
        return json.loads(row[0])

    def set_session_calibration(self, session_id: str, calibration_id: str) -> None:
        with self._tx() as db:
            db.execute("UPDATE sessions SET calibration_id = ? WHERE id = ?", (calibration_id, session_id))


class OwnedStore:
    """A store seen by one owner: every method that takes ``owner`` gets this one.

    Routes use it without naming the owner, so no call can forget to confine itself.
    """

    def __init__(self, store: Store, owner: str | None):
        self._store = store
        self.owner = owner

    def __getattr__(self, name: str):
        attr = getattr(self._store, name)
        if callable(attr) and "owner" in inspect.signature(attr).parameters:
            return functools.partial(attr, owner=self.owner)
        return attr
