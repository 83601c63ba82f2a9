"""What the application stores: calibrations, recordings (and their files), wizard sessions.

One class for SQLite and PostgreSQL, in SQLAlchemy Core over app.store.schema; the engine
(app.store.engine) holds what differs between them. Every write commits before the method returns,
so what the API acknowledges is stored.

Objects that belong to someone (calibrations, recordings) are read and written with an explicit
``owner``: ``None`` when API keys are off, ``key:…`` for an API key, ``session:<id>`` for what a
wizard session created (app.api.deps). Another owner's object is not found.
"""

from __future__ import annotations

import json
import secrets
import threading
from collections.abc import Iterator
from contextlib import contextmanager, nullcontext
from datetime import UTC, datetime, timedelta
from pathlib import Path

from sqlalchemy import Connection, Engine, func, select, update
from sqlalchemy.dialects import postgresql, sqlite

from . import migrate
from .engine import WRITE
from .errors import ConflictError, NotFoundError
from .schema import calibrations, links, recording_files, recordings, session_captures, sessions


def new_id(prefix: str) -> str:
    """An unguessable identifier such as ``cal_3f9c…`` (128 random bits)."""
    return f"{prefix}_{secrets.token_hex(16)}"


def utc_now(after_s: float = 0.0) -> str:
    when = datetime.now(UTC) + timedelta(seconds=after_s)
    return when.isoformat(timespec="milliseconds").replace("+00:00", "Z")


LINK_ALPHABET = "23456789ABCDEFGHJKMNPQRSTUVWXYZ"
"""A link's code is typed from a phone's screen: no 0/O, 1/I/L."""
LINK_LENGTH = 10
"""31**10, about 2**49 codes: not guessed within a link's hour under the rate limit."""


INSERT_CALIBRATION = calibrations.insert()
"""Executed with a row's parameters: one statement for every calibration, where ``insert().values(**row)``
built and coerced a new one for each: a tenth of a six-position calibration's server CPU time under cProfile
(bench/load_six.py --profile: add_calibration 2.55 -> 1.50 ms of 11.5)."""


def _json(value) -> str:
    return json.dumps(value, allow_nan=False)


def _owned_by(column, owner: str | None):
    return column.is_(None) if owner is None else column == owner


class Store:
    """Recordings, calibrations and sessions in one database, migrated when opened.

    Parameters
    ----------
    engine : sqlalchemy.Engine
        The database (app.store.engine.make_engine).
    files_dir : pathlib.Path
        Where uploaded files are kept on this machine (created if needed).
    keep_files_in_database : bool
        Also store each uploaded file in the database, for replicas that share nothing else.
    """

    def __init__(self, engine: Engine, files_dir: Path, *, keep_files_in_database: bool = False):
        self.engine = engine
        self._writer = engine.execution_options(**{WRITE: True})
        # SQLite has one writer at a time. Without this lock, the threads of one server that wait for it
        # poll in SQLite's busy handler, which sleeps up to 100 ms between tries: a waiter could sleep past
        # many later writers, and under load a few calibrations waited seconds (bench/load_six.py p99).
        # Queued on a lock, the next writer starts as the last one commits. Other processes on the same
        # file still meet BEGIN IMMEDIATE's busy timeout (app.store.engine).
        self._write_lock = threading.Lock() if engine.dialect.name == "sqlite" else None
        self.files_dir = Path(files_dir)
        self.files_dir.mkdir(parents=True, exist_ok=True)
        self.keep_files_in_database = keep_files_in_database
        migrate.upgrade(engine)

    @property
    def schema_revision(self) -> str | None:
        """The Alembic revision the database is at."""
        with self.engine.connect() as connection:
            return migrate.current_revision(connection)

    @contextmanager
    def _write(self) -> Iterator[Connection]:
        """A write transaction, committed (for SQLite: synced) when the block ends without an error."""
        with self._write_lock or nullcontext(), self._writer.begin() as connection:
            yield connection

    def _read(self, statement):
        with self.engine.connect() as connection:
            return connection.execute(statement).all()

    def _insert(self, table):
        """The dialect's INSERT, which knows ON CONFLICT."""
        return (postgresql if self.engine.dialect.name == "postgresql" else sqlite).insert(table)

    # -- calibrations ---------------------------------------------------------------------

    def add_calibration(
        self, body: dict, *, owner: str | None, session_id: str | None = None, recording_digest: str | None = None
    ) -> dict:
        """Store a calibration; ``id`` and ``created_at`` are assigned here and returned in it. With
        ``session_id``, the session names it as its calibration in the same transaction: a solved session
        and its calibration are stored together or not at all. With ``recording_digest`` (the SHA-256 of the
        recording's upload, with the compass for a flight log's: RecordingSource.supersede_key), it supersedes the
        owner's earlier calibrations of the same recording, method and device name (read again with other
        options): they stay, each naming it in ``superseded_by``."""
        body = dict(body, id=new_id("cal"), created_at=utc_now())
        row = {
            "id": body["id"],
            "method": body["method"],
            "device_id": body.get("device_id"),
            "label": body.get("label"),
            "owner": owner,
            "created_at": body["created_at"],
            "ok": int(bool(body.get("ok"))),
            "body": _json(body),
            "recording_digest": recording_digest,
        }
        with self._write() as db:  # the row is made before the write lock is taken
            db.execute(INSERT_CALIBRATION, row)
            if recording_digest is not None:
                db.execute(
                    update(calibrations)
                    .where(
                        _owned_by(calibrations.c.owner, owner),
                        calibrations.c.recording_digest == recording_digest,
                        calibrations.c.method == body["method"],
                        calibrations.c.id != body["id"],
                        calibrations.c.device_id.is_not_distinct_from(body.get("device_id")),
                    )
                    .values(superseded_by=body["id"])
                )
            if session_id is not None:
                db.execute(update(sessions).where(sessions.c.id == session_id).values(calibration_id=body["id"]))
        return body

    def get_calibration(self, calibration_id: str, *, owner: str | None) -> dict:
        """One calibration, with ``superseded_by`` when a later one of the same recording and method
        superseded it and ``earlier`` (how many it superseded) when it did."""
        rows = self._read(
            select(calibrations.c.body, calibrations.c.superseded_by).where(
                calibrations.c.id == calibration_id, _owned_by(calibrations.c.owner, owner)
            )
        )
        if not rows:
            raise NotFoundError(f"no calibration with id {calibration_id!r}")
        return self._with_lineage(rows)[0]

    def list_calibrations(
        self, *, owner: str | None, device_id: str | None = None, limit: int = 100, superseded_by: str | None = None
    ) -> list[dict]:
        """The owner's calibrations that no later one superseded, newest first, optionally of one device;
        with ``superseded_by``, the earlier ones that calibration superseded instead."""
        query = select(calibrations.c.body, calibrations.c.superseded_by).where(
            _owned_by(calibrations.c.owner, owner),
            calibrations.c.superseded_by.is_(None)
            if superseded_by is None
            else calibrations.c.superseded_by == superseded_by,
        )
        if device_id is not None:
            query = query.where(calibrations.c.device_id == device_id)
        query = query.order_by(calibrations.c.created_at.desc(), calibrations.c.id).limit(limit)
        return self._with_lineage(self._read(query))

    def _with_lineage(self, rows) -> list[dict]:
        """The bodies of ``rows`` (body, superseded_by), each with ``superseded_by`` and ``earlier`` where they hold."""
        bodies = [json.loads(row.body) for row in rows]
        ids = [b["id"] for b in bodies]
        counts = (
            dict(
                self._read(
                    select(calibrations.c.superseded_by, func.count())
                    .where(calibrations.c.superseded_by.in_(ids))
                    .group_by(calibrations.c.superseded_by)
                )
            )
            if ids
            else {}
        )
        for body, row in zip(bodies, rows):
            if row.superseded_by:
                body["superseded_by"] = row.superseded_by
            if counts.get(body["id"]):
                body["earlier"] = counts[body["id"]]
        return bodies

    # -- links ----------------------------------------------------------------------------

    def add_link(self, calibration_id: str, *, owner: str | None, ttl_s: float) -> dict:
        """A short link to the owner's calibration that reads it for ``ttl_s`` seconds: ``code``,
        ``calibration_id``, ``created_at``, ``expires_at``. Another owner's calibration is not found."""
        self.get_calibration(calibration_id, owner=owner)
        row = {
            "code": "".join(secrets.choice(LINK_ALPHABET) for _ in range(LINK_LENGTH)),
            "calibration_id": calibration_id,
            "owner": owner,
            "created_at": utc_now(),
            "expires_at": utc_now(ttl_s),
        }
        with self._write() as db:
            db.execute(links.insert().values(**row))
        return {k: v for k, v in row.items() if k != "owner"}

    def open_link(self, code: str) -> dict:
        """The link ``code`` while it holds: ``calibration_id``, ``owner``, ``expires_at``. An unknown
        code, or one past its time, is not found, with a message saying to send it again."""
        rows = self._read(select(links).where(links.c.code == code.upper()))
        if not rows:
            raise NotFoundError(
                f"no link {code!r}: check the address, or send it again from the device that made the calibration"
            )
        row = rows[0]._asdict()
        if row["expires_at"] <= utc_now():
            raise NotFoundError(
                f"the link {code!r} expired at {row['expires_at']}: send it again from the device "
                "that made the calibration"
            )
        return row

    # -- recordings -----------------------------------------------------------------------

    def add_recording(self, recording_id: str, body: dict, path: Path, *, owner: str | None) -> dict:
        """Store a recording's metadata; its file is already at ``path``, inside ``files_dir``."""
        body = dict(body, id=recording_id, created_at=utc_now())
        with self._write() as db:
            if self.keep_files_in_database:
                db.execute(recording_files.insert().values(id=recording_id, content=Path(path).read_bytes()))
            db.execute(
                recordings.insert().values(
                    id=recording_id,
                    owner=owner,
                    created_at=body["created_at"],
                    format=body["format"],
                    n_samples=body["n_samples"],
                    path=Path(path).name,
                    # The column is informative (the body holds the rate): 0 for a log without one.
                    sampling_rate_hz=body["sampling_rate_hz"] or 0.0,
                    body=_json(body),
                )
            )
        return body

    def get_recording(self, recording_id: str, *, owner: str | None) -> tuple[dict, Path]:
        """A recording's metadata and its file on this machine (fetched from the database if needed)."""
        rows = self._read(
            select(recordings.c.body, recordings.c.path).where(
                recordings.c.id == recording_id, _owned_by(recordings.c.owner, owner)
            )
        )
        if not rows:
            raise NotFoundError(f"no recording with id {recording_id!r}; upload it with POST /api/v1/recordings")
        path = self.files_dir / rows[0].path
        if not path.exists() and self.keep_files_in_database:
            # Uploaded through another replica: bring the file from the database.
            content = self._read(select(recording_files.c.content).where(recording_files.c.id == recording_id))
            if content:
                tmp = path.with_suffix(path.suffix + ".part")
                tmp.write_bytes(bytes(content[0].content))
                tmp.replace(path)
        return json.loads(rows[0].body), path

    # -- wizard sessions ----------------------------------------------------------------------
    # A session is reached by its token alone (the owner column records who created it, for the
    # API-key case); its calibrations are owned by ``session:<id>`` (app.api.deps).

    def add_session(self, body: dict, token_hash: str, *, owner: str | None) -> dict:
        """Store a new session; ``id`` and ``created_at`` are assigned here."""
        body = dict(body, id=new_id("ses"), created_at=utc_now())
        with self._write() as db:
            db.execute(
                sessions.insert().values(
                    id=body["id"],
                    token_hash=token_hash,
                    owner=owner,
                    protocol=body["protocol"],
                    created_at=body["created_at"],
                    calibration_id=None,
                    body=_json(body),
                )
            )
        return body

    def session_id_for_token(self, token_hash: str) -> str | None:
        rows = self._read(select(sessions.c.id).where(sessions.c.token_hash == token_hash))
        return rows[0].id if rows else None

    def get_session(self, session_id: str) -> dict:
        """The session with its captures' summaries (in the order they were taken) and calibration id."""
        with self.engine.connect() as db:
            row = db.execute(
                select(sessions.c.body, sessions.c.calibration_id).where(sessions.c.id == session_id)
            ).first()
            if row is None:
                raise NotFoundError(f"no session with id {session_id!r}; start one with POST /api/v1/sessions")
            captures = db.execute(
                select(session_captures.c.summary)
                .where(session_captures.c.session_id == session_id)
                .order_by(session_captures.c.created_at, session_captures.c.position)
            ).all()
        return dict(
            json.loads(row.body), calibration_id=row.calibration_id, captures=[json.loads(c.summary) for c in captures]
        )

    def add_capture(self, session_id: str, summary: dict, samples: dict, *, replace: bool = False) -> dict:
        """Store one capture of a pose; a second one of the same pose needs ``replace``.

        Raises
        ------
        ConflictError
            The pose is captured already and ``replace`` is false.
        """
        summary = dict(summary, created_at=utc_now())
        insert = self._insert(session_captures).values(
            session_id=session_id,
            position=summary["position"],
            created_at=summary["created_at"],
            summary=_json(summary),
            samples=_json(samples),
        )
        key = ["session_id", "position"]
        with self._write() as db:
            if replace:
                db.execute(
                    insert.on_conflict_do_update(
                        index_elements=key,
                        set_={name: insert.excluded[name] for name in ("created_at", "summary", "samples")},
                    )
                )
            elif (
                db.execute(
                    insert.on_conflict_do_nothing(index_elements=key).returning(session_captures.c.position)
                ).first()
                is None
            ):
                raise ConflictError(summary["position"])
        return summary

    def get_capture_samples(self, session_id: str, position: str) -> dict:
        rows = self._read(
            select(session_captures.c.samples).where(
                session_captures.c.session_id == session_id, session_captures.c.position == position
            )
        )
        if not rows:
            raise NotFoundError(f"session {session_id!r} has no capture of {position}")
        return json.loads(rows[0].samples)
