"""The store on SQLite and PostgreSQL: migrations, durability, owners, files across replicas."""

from __future__ import annotations

import httpx
import pytest
from fastapi.testclient import TestClient

from app.config import Settings
from app.main import create_app
from app.store import NotFoundError, open_store
from app.store.migrate import head_revision
from tests.api.test_calibrations import CANONICAL, six_request
from tests.api.test_recordings import LOG
from tests.conftest import seed_table
from tests.live_server import LiveServer


def body(**kw):
    return {"method": "six_position", "ok": True, "model": {"type": "affine"}, **kw}


def test_migrations_are_versioned_and_idempotent(store, database_url, tmp_path):
    assert store.schema_revision == head_revision() == "0005"
    again = open_store(database_url, tmp_path / "files")  # a restart, or a second replica
    assert again.schema_revision == head_revision()


def test_calibrations_by_owner_and_device(store):
    a = store.add_calibration(body(device_id="d1"), owner="key:a")
    b = store.add_calibration(body(device_id="d1"), owner="key:b")
    c = store.add_calibration(body(device_id="d2"), owner=None)
    assert store.get_calibration(a["id"], owner="key:a") == a
    with pytest.raises(NotFoundError):
        store.get_calibration(a["id"], owner="key:b")
    with pytest.raises(NotFoundError):
        store.get_calibration(a["id"], owner=None)  # keyless callers see only keyless objects
    assert [x["id"] for x in store.list_calibrations(device_id="d1", owner="key:b")] == [b["id"]]
    assert [x["id"] for x in store.list_calibrations(owner=None)] == [c["id"]]


def test_a_link_opens_its_owner_s_calibration_until_it_expires(store):
    import time

    from app.store.repository import LINK_ALPHABET, LINK_LENGTH

    a = store.add_calibration(body(), owner="session:ses_1")
    with pytest.raises(NotFoundError):
        store.add_link(a["id"], owner="key:b", ttl_s=60)  # another owner's calibration: no link
    link = store.add_link(a["id"], owner="session:ses_1", ttl_s=60)
    assert len(link["code"]) == LINK_LENGTH and set(link["code"]) <= set(LINK_ALPHABET)
    opened = store.open_link(link["code"].lower())  # typed in lower case: the same link
    assert (opened["calibration_id"], opened["owner"], opened["expires_at"]) == (
        a["id"],
        "session:ses_1",
        link["expires_at"],
    )
    short = store.add_link(a["id"], owner="session:ses_1", ttl_s=0.05)
    time.sleep(0.1)
    with pytest.raises(NotFoundError, match=r"expired at .*: send it again"):
        store.open_link(short["code"])
    with pytest.raises(NotFoundError, match="no link"):
        store.open_link("ABCDEFGHJK")


def test_two_replicas_share_only_the_database(pg, tmp_path):
    url = pg.new_database()
    replicas = [TestClient(create_app(Settings(database_url=url, data_dir=tmp_path / f"replica{i}"))) for i in range(2)]
    with replicas[0] as first, replicas[1] as second:
        rec = first.post(
            "/api/v1/recordings",
            files={"file": ("log.csv", LOG.read_bytes(), "text/csv")},
            data={"sampling_rate_hz": "150"},
        )
        assert rec.status_code == 201
        # The second replica has never seen the file on its disk: it comes from the database.
        assert not (tmp_path / "replica1" / "recordings").exists() or not any(
            (tmp_path / "replica1" / "recordings").iterdir()
        )
        cal = second.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec.json()["id"]})
        assert cal.status_code == 201, cal.text
        assert first.get(f"/api/v1/calibrations/{cal.json()['id']}").json() == cal.json()


def test_acknowledged_writes_survive_kill_9_on_postgresql(pg, tmp_path):
    env = {"TRICAL_DATABASE_URL": pg.new_database(), "TRICAL_DATA_DIR": str(tmp_path)}
    server = LiveServer(env).start()
    try:
        with httpx.Client(base_url=server.url, timeout=10) as http:
            acked = [
                http.post("/api/v1/calibrations", json=six_request(seed_table(1), CANONICAL)).json() for _ in range(10)
            ]
        server.kill()
        server.start()
        with httpx.Client(base_url=server.url, timeout=10) as http:
            for b in acked:
                assert http.get(f"/api/v1/calibrations/{b['id']}").json() == b
    finally:
        server.stop()


def test_sessions_and_their_captures(store):
    """Migration 3 on both databases: a capture per pose, a second one only as a redo."""
    from app.store import ConflictError

    s = store.add_session({"protocol": "six", "positions": ["+z", "-z"]}, "hash-a", owner="key:a")
    assert store.session_id_for_token("hash-a") == s["id"] and store.session_id_for_token("hash-b") is None
    first = store.add_capture(s["id"], {"position": "+z", "mean": [0, 0, 9.8]}, {"acc": [[0, 0, 9.8]], "t_ms": [0.0]})
    with pytest.raises(ConflictError):
        store.add_capture(s["id"], {"position": "+z", "mean": [0, 0, 9.7]}, {"acc": [], "t_ms": []})
    store.add_capture(s["id"], {"position": "-z", "mean": [0, 0, -9.8]}, {"acc": [], "t_ms": []})
    store.add_capture(
        s["id"], {"position": "+z", "mean": [0, 0, 9.9]}, {"acc": [[0, 0, 9.9]], "t_ms": [1.0]}, replace=True
    )
    got = store.get_session(s["id"])
    assert {c["position"]: c["mean"] for c in got["captures"]} == {"+z": [0, 0, 9.9], "-z": [0, 0, -9.8]}
    assert got["calibration_id"] is None and first["created_at"]
    assert store.get_capture_samples(s["id"], "+z") == {"acc": [[0, 0, 9.9]], "t_ms": [1.0]}
    cal = store.add_calibration({"method": "six_position", "ok": True}, owner="key:a", session_id=s["id"])
    assert store.get_session(s["id"])["calibration_id"] == cal["id"]  # stored with its session, in one transaction
    assert store.get_calibration(cal["id"], owner="key:a")["id"] == cal["id"]
    with pytest.raises(NotFoundError):
        store.get_session("ses_missing")


def test_replicas_starting_together_migrate_one_after_the_other(pg, tmp_path):
    """Four processes open one fresh PostgreSQL database at once: the advisory lock serialises their
    migrations, so none fails on a table another is creating."""
    import subprocess
    import sys

    from tests.live_server import ROOT

    url = pg.new_database()
    code = "import sys; from app.store import open_store; print(open_store(sys.argv[1], sys.argv[2]).schema_revision)"
    replicas = [
        subprocess.Popen(
            [sys.executable, "-c", code, url, str(tmp_path / f"replica{i}")],
            cwd=ROOT,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for i in range(4)
    ]
    outcomes = [r.communicate(timeout=120) for r in replicas]
    assert [(r.returncode, out.strip()) for r, (out, _) in zip(replicas, outcomes)] == [(0, head_revision())] * 4, [
        err for _, err in outcomes
    ]
    store = open_store(url, tmp_path / "files")
    made = store.add_calibration(body(), owner=None)
    assert store.get_calibration(made["id"], owner=None) == made


def test_sqlite_is_durable_and_enforces_foreign_keys(tmp_path):
    """WAL journal, synchronous=FULL and foreign keys on every connection of the pool."""
    import sqlalchemy

    store = open_store(f"sqlite:///{tmp_path / 'trical.db'}", tmp_path / "files")
    with store.engine.connect() as db:
        assert db.exec_driver_sql("PRAGMA journal_mode").scalar() == "wal"
        assert db.exec_driver_sql("PRAGMA synchronous").scalar() == 2  # FULL
        assert db.exec_driver_sql("PRAGMA foreign_keys").scalar() == 1
    with pytest.raises(sqlalchemy.exc.IntegrityError):
        store.add_capture("ses_missing", {"position": "+z"}, {"acc": []})


def test_concurrent_writers_of_one_sqlite_file_all_commit(tmp_path):
    """Threads of one store queue on its write lock, and a second store on the same file (another process's
    engine) meets them at SQLite's own lock: every acknowledged write is read back, each once."""
    from concurrent.futures import ThreadPoolExecutor

    url = f"sqlite:///{tmp_path / 'trical.db'}"
    first, second = open_store(url, tmp_path / "files"), open_store(url, tmp_path / "files")

    def write(i: int) -> str:
        store = first if i % 4 else second
        return store.add_calibration(body(device_id=f"d{i % 3}", label=str(i)), owner=None)["id"]

    with ThreadPoolExecutor(max_workers=16) as pool:
        ids = list(pool.map(write, range(200)))
    assert len(set(ids)) == 200
    for i, cal_id in enumerate(ids):
        assert first.get_calibration(cal_id, owner=None)["label"] == str(i)
    assert sum(len(first.list_calibrations(owner=None, device_id=f"d{d}", limit=1000)) for d in range(3)) == 200
