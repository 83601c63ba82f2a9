"""A database made by trical before Alembic (the hand-written ``schema_version`` table) is adopted in
place: stamped with its revision, upgraded, and every row, body and file it held still reads."""

from __future__ import annotations

import json
import sqlite3
from contextlib import closing

import psycopg
import pytest
from sqlalchemy import inspect

from app.store import ConflictError, NotFoundError, SchemaError, Store, open_store
from app.store.engine import make_engine, sqlite_path
from app.store.migrate import head_revision

# The hand-written migrations 1, 2 and 3 as trical ran them (BLOB is BYTEA on PostgreSQL).
LEGACY_MIGRATIONS = (
    """
    CREATE TABLE calibrations (
        id TEXT PRIMARY KEY, method TEXT NOT NULL, device_id TEXT, label TEXT, owner TEXT,
        created_at TEXT NOT NULL, ok INTEGER NOT NULL, body TEXT NOT NULL
    );
    CREATE INDEX calibrations_device ON calibrations (device_id, created_at);
    CREATE TABLE recordings (
        id TEXT PRIMARY KEY, owner TEXT, created_at TEXT NOT NULL, format TEXT NOT NULL,
        n_samples INTEGER NOT NULL, sampling_rate_hz REAL NOT NULL, path TEXT NOT NULL, body TEXT NOT NULL
    );
    """,
    """
    CREATE TABLE recording_files (id TEXT PRIMARY KEY, content BLOB NOT NULL);
    """,
    """
    CREATE TABLE sessions (
        id TEXT PRIMARY KEY, token_hash TEXT NOT NULL UNIQUE, owner TEXT, protocol TEXT NOT NULL,
        created_at TEXT NOT NULL, calibration_id TEXT, body TEXT NOT NULL
    );
    CREATE TABLE session_captures (
        session_id TEXT NOT NULL REFERENCES sessions (id), position TEXT NOT NULL, created_at TEXT NOT NULL,
        summary TEXT NOT NULL, samples TEXT NOT NULL, PRIMARY KEY (session_id, position)
    );
    """,
)

CALIBRATIONS = [
    {
        "id": "cal_keyless",
        "method": "six_position",
        "ok": True,
        "device_id": "d1",
        "label": "bench",
        "created_at": "2026-01-01T10:00:00.000Z",
        "model": {"type": "affine", "X": [[1.01, 0, 0]], "o": [0.1, 0, 0]},
    },
    {
        "id": "cal_key_a",
        "method": "nonorthogonal",
        "ok": False,
        "device_id": "d1",
        "label": None,
        "created_at": "2026-01-02T10:00:00.000Z",
        "model": {"type": "nonorthogonal"},
        "warnings": ["ü ° ²"],
    },
    {
        "id": "cal_session",
        "method": "six_position",
        "ok": True,
        "device_id": None,
        "label": None,
        "created_at": "2026-01-03T10:00:00.000Z",
        "model": {"type": "affine"},
        "session_id": "ses_legacy",
    },
]
OWNERS = {"cal_keyless": None, "cal_key_a": "key:a", "cal_session": "session:ses_legacy"}
RECORDING = {
    "id": "rec_legacy",
    "created_at": "2026-01-01T09:00:00.000Z",
    "format": "csv",
    "n_samples": 3,
    "sampling_rate_hz": 150.0,
    "units": {"acc": "m/s^2"},
    "segments": [],
    "filename": "log.csv",
}
FILE = b"t,ax,ay,az\n0,0,0,9.81\n" + bytes(range(256))  # every byte value survives
SESSION = {
    "id": "ses_legacy",
    "created_at": "2026-01-03T09:00:00.000Z",
    "protocol": "six",
    "positions": ["+x", "-x", "+y", "-y", "+z", "-z"],
    "capture_s": 3,
    "unit": "m/s^2",
    "gravity": 9.81,
    "notes": [],
    "device_id": None,
    "label": None,
}
CAPTURES = [
    (
        {"position": "+z", "mean": [0.0, 0.0, 9.81], "created_at": "2026-01-03T09:01:00.000Z"},
        {"t_ms": [0.0, 10.0], "acc": [[0, 0, 9.8], [0, 0, 9.82]], "gyr": None, "gyr_unit": None, "motion": None},
    ),
    (
        {"position": "-z", "mean": [0.0, 0.0, -9.81], "created_at": "2026-01-03T09:02:00.000Z"},
        {"t_ms": [20.0], "acc": [[0, 0, -9.81]], "gyr": [[0.1, 0, 0]], "gyr_unit": "deg/s", "motion": None},
    ),
]


def legacy_database(database_url: str, version: int) -> None:
    """Make the database as trical did before Alembic, at ``version``, with rows in every table."""
    path = sqlite_path(database_url)
    db = sqlite3.connect(path, isolation_level=None) if path else psycopg.connect(database_url, autocommit=True)
    with closing(db):

        def run(sql, args=()):
            db.execute(sql if path else sql.replace("?", "%s").replace("BLOB", "BYTEA"), args)

        run("BEGIN")
        run("CREATE TABLE schema_version (version INTEGER NOT NULL)")
        run("INSERT INTO schema_version (version) VALUES (?)", (version,))
        for script in LEGACY_MIGRATIONS[:version]:
            for statement in filter(str.strip, script.split(";")):
                run(statement)
        for body in CALIBRATIONS:
            run(
                "INSERT INTO calibrations (id, method, device_id, label, owner, created_at, ok, body)"
                " VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (
                    body["id"],
                    body["method"],
                    body["device_id"],
                    body["label"],
                    OWNERS[body["id"]],
                    body["created_at"],
                    int(body["ok"]),
                    json.dumps(body),
                ),
            )
        run(
            "INSERT INTO recordings (id, owner, created_at, format, n_samples, sampling_rate_hz, path, body)"
            " VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
            (
                RECORDING["id"],
                "key:a",
                RECORDING["created_at"],
                "csv",
                3,
                150.0,
                "rec_legacy.csv",
                json.dumps(RECORDING),
            ),
        )
        if version >= 2:
            run("INSERT INTO recording_files (id, content) VALUES (?, ?)", (RECORDING["id"], FILE))
        if version >= 3:
            run(
                "INSERT INTO sessions (id, token_hash, owner, protocol, created_at, calibration_id, body)"
                " VALUES (?, ?, ?, ?, ?, ?, ?)",
                (SESSION["id"], "hash-legacy", None, "six", SESSION["created_at"], "cal_session", json.dumps(SESSION)),
            )
            for summary, samples in CAPTURES:
                run(
                    "INSERT INTO session_captures (session_id, position, created_at, summary, samples)"
                    " VALUES (?, ?, ?, ?, ?)",
                    (
                        SESSION["id"],
                        summary["position"],
                        summary["created_at"],
                        json.dumps(summary),
                        json.dumps(samples),
                    ),
                )
        run("COMMIT")


def tables(store: Store) -> set[str]:
    return set(inspect(store.engine).get_table_names())


def test_a_version_3_database_is_adopted_without_loss(database_url, tmp_path):
    legacy_database(database_url, 3)
    store = open_store(database_url, tmp_path / "files")
    assert store.schema_revision == head_revision()
    assert "schema_version" not in tables(store) and "alembic_version" in tables(store)

    for body in CALIBRATIONS:
        assert store.get_calibration(body["id"], owner=OWNERS[body["id"]]) == body
        with pytest.raises(NotFoundError):
            store.get_calibration(body["id"], owner="key:someone-else")
    assert [b["id"] for b in store.list_calibrations(owner="key:a", device_id="d1")] == ["cal_key_a"]
    assert [b["id"] for b in store.list_calibrations(owner=None)] == ["cal_keyless"]

    # The file comes back from the database's BLOB (as on a replica that never saw the upload).
    replica = Store(make_engine(database_url), tmp_path / "replica", keep_files_in_database=True)
    body, path = replica.get_recording(RECORDING["id"], owner="key:a")
    assert body == RECORDING and path.read_bytes() == FILE
    with pytest.raises(NotFoundError):
        replica.get_recording(RECORDING["id"], owner=None)

    assert store.session_id_for_token("hash-legacy") == SESSION["id"]
    session = store.get_session(SESSION["id"])
    assert session == dict(SESSION, calibration_id="cal_session", captures=[c for c, _ in CAPTURES])
    for summary, samples in CAPTURES:
        assert store.get_capture_samples(SESSION["id"], summary["position"]) == samples

    # And the adopted database takes new writes under the old constraints.
    with pytest.raises(ConflictError):
        store.add_capture(SESSION["id"], {"position": "+z"}, {"acc": []})
    store.add_capture(SESSION["id"], {"position": "+x", "mean": [9.81, 0, 0]}, {"acc": [[9.81, 0, 0]]})
    assert [c["position"] for c in store.get_session(SESSION["id"])["captures"]] == ["+z", "-z", "+x"]
    new = store.add_calibration(dict(CALIBRATIONS[0], id=None), owner=None)
    assert [b["id"] for b in store.list_calibrations(owner=None)] == [new["id"], "cal_keyless"]
    again = open_store(database_url, tmp_path / "files")  # a restart migrates nothing more
    assert again.schema_revision == head_revision() and again.get_calibration(new["id"], owner=None) == new


def test_an_older_legacy_database_is_stamped_then_upgraded(database_url, tmp_path):
    legacy_database(database_url, 2)
    store = open_store(database_url, tmp_path / "files")
    assert store.schema_revision == head_revision()
    assert {"sessions", "session_captures"} <= tables(store) and "schema_version" not in tables(store)
    assert store.get_calibration("cal_key_a", owner="key:a") == CALIBRATIONS[1]
    replica = Store(make_engine(database_url), tmp_path / "replica", keep_files_in_database=True)
    assert replica.get_recording(RECORDING["id"], owner="key:a")[1].read_bytes() == FILE
    s = store.add_session({"protocol": "six", "positions": ["+z"]}, "hash-new", owner=None)
    assert store.get_session(s["id"])["captures"] == []


def test_a_newer_legacy_database_is_refused_untouched(database_url, tmp_path):
    legacy_database(database_url, 3)
    engine = make_engine(database_url)
    with engine.begin() as db:
        db.exec_driver_sql("UPDATE schema_version SET version = 4")
    with pytest.raises(SchemaError, match="schema_version 4"):
        open_store(database_url, tmp_path / "files")
    assert "alembic_version" not in set(inspect(engine).get_table_names())
    with engine.connect() as db:
        assert db.exec_driver_sql("SELECT version FROM schema_version").scalar() == 4


def test_the_package_carries_every_migration():
    """A wheel install has the migrations: pyproject's package data covers every file of them."""
    import tomllib
    from pathlib import Path

    import app.store

    package = Path(app.store.__file__).parent
    patterns = tomllib.loads((package.parents[1] / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"][
        "app.store"
    ]
    shipped = {p for pattern in patterns for p in package.glob(pattern)}
    files = {p for p in (package / "migrations").rglob("*") if p.is_file() and "__pycache__" not in p.parts}
    assert files and files <= shipped, sorted(map(str, files - shipped))
    assert {p.name for p in (package / "migrations" / "versions").glob("*.py")} >= {
        "0001_calibrations_and_recordings.py",
        "0002_recording_files.py",
        "0003_sessions.py",
        "0004_links.py",
        "0005_superseded_calibrations.py",
    }


def test_a_revision_0004_database_gains_superseding_and_keeps_its_calibrations(database_url, tmp_path):
    """A database file of the trical before 0005 (calibrations with no recording digest): upgraded in place,
    its calibrations all list and read as before, and new ones of one upload supersede each other only."""
    from alembic import command

    from app.store.migrate import adopt_legacy_schema, alembic_config

    legacy_database(database_url, 3)
    engine = make_engine(database_url)
    with engine.begin() as connection:  # adopted and brought to 0004, as the trical before 0005 left it
        config = alembic_config(connection)
        adopt_legacy_schema(connection, config)
        command.upgrade(config, "0004")
    engine.dispose()
    store = open_store(database_url, tmp_path / "files")
    assert store.schema_revision == head_revision() == "0005"
    for body in CALIBRATIONS:
        assert store.get_calibration(body["id"], owner=OWNERS[body["id"]]) == body
    assert [b["id"] for b in store.list_calibrations(owner="key:a", device_id="d1")] == ["cal_key_a"]
    first = store.add_calibration(dict(CALIBRATIONS[0], id=None), owner=None, recording_digest="ab" * 32)
    second = store.add_calibration(dict(CALIBRATIONS[0], id=None), owner=None, recording_digest="ab" * 32)
    other_owner = store.add_calibration(dict(CALIBRATIONS[0], id=None), owner="key:a", recording_digest="ab" * 32)
    assert [b["id"] for b in store.list_calibrations(owner=None)] == [second["id"], "cal_keyless"]
    assert store.list_calibrations(owner=None)[0]["earlier"] == 1
    assert [b["id"] for b in store.list_calibrations(owner=None, superseded_by=second["id"])] == [first["id"]]
    assert store.get_calibration(first["id"], owner=None)["superseded_by"] == second["id"]
    assert "superseded_by" not in store.get_calibration(other_owner["id"], owner="key:a")  # another owner's own
