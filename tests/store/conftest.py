"""The storage tests run against SQLite and against a real PostgreSQL server."""

from __future__ import annotations

import pytest

from app.store import open_store
from tests.pg_server import postgres_server


@pytest.fixture(scope="session")
def pg():
    with postgres_server() as server:
        yield server


@pytest.fixture(params=["sqlite", "postgresql"])
def database_url(request, tmp_path):
    if request.param == "sqlite":
        return f"sqlite:///{tmp_path / 'trical.db'}"
    return request.getfixturevalue("pg").new_database()


@pytest.fixture
def store(database_url, tmp_path):
    return open_store(database_url, tmp_path / "files")
