"""Schema migrations: Alembic, run at store open, serialised between replicas that start together.

The migrations live in this package (app/store/migrations), so an installed wheel carries them.
A database made before Alembic kept its version in a ``schema_version`` table (versions 1–3 of
the hand-written migrations, the same tables as revisions 0001–0003): it is stamped with the
matching revision, the ``schema_version`` table is dropped (Alembic's ``alembic_version`` is then
the one record of the schema; trical versions from before Alembic refuse such a database rather
than run on it), and the upgrade continues — all in one transaction.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from alembic import command
from alembic.config import Config
from alembic.runtime.migration import MigrationContext
from alembic.script import ScriptDirectory
from sqlalchemy import Connection, Engine, inspect, text

from .engine import WRITE

MIGRATIONS_DIR = Path(__file__).with_name("migrations")
LEGACY_REVISIONS: dict[int, str | None] = {0: None, 1: "0001", 2: "0002", 3: "0003"}
"""The Alembic revision of each version of the hand-written ``schema_version`` table."""
MIGRATION_LOCK = 7357001
"""The PostgreSQL advisory lock that replicas starting together migrate under, one after the other."""


class SchemaError(RuntimeError):
    """The database's schema is not one this trical can migrate."""


def alembic_config(connection: Connection | None = None) -> Config:
    """Alembic's configuration, built in code: the package's migrations, on ``connection``."""
    config = Config()
    config.set_main_option("script_location", str(MIGRATIONS_DIR))
    config.attributes["connection"] = connection
    return config


@cache
def head_revision() -> str:
    """The newest revision of the package's migrations (read once a process: Alembic imports every migration's
    module to find it)."""
    head = ScriptDirectory.from_config(alembic_config()).get_current_head()
    assert head is not None, "the migrations have one head"
    return head


def current_revision(connection: Connection) -> str | None:
    return MigrationContext.configure(connection).get_current_revision()


def upgrade(engine: Engine) -> None:
    """Bring the database to the newest revision (adopting a pre-Alembic database first)."""
    with engine.connect().execution_options(**{WRITE: True}) as connection, connection.begin():
        if connection.dialect.name == "postgresql":
            connection.execute(text("SELECT pg_advisory_xact_lock(:key)"), {"key": MIGRATION_LOCK})
        if current_revision(connection) == head_revision():
            return  # at the head: nothing to run (Alembic's upgrade would import every migration to find that out)
        config = alembic_config(connection)
        adopt_legacy_schema(connection, config)
        command.upgrade(config, "head")


def adopt_legacy_schema(connection: Connection, config: Config) -> None:
    """Stamp a database of the hand-written migrations with its revision and drop ``schema_version``."""
    tables = set(inspect(connection).get_table_names())
    if "schema_version" not in tables or "alembic_version" in tables:
        return
    version = connection.execute(text("SELECT version FROM schema_version")).scalar()
    if version is None:
        version = 0
    if version not in LEGACY_REVISIONS:
        raise SchemaError(
            f"the database is at schema_version {version}, newer than this trical knows "
            f"(at most {max(LEGACY_REVISIONS)}): run the trical that made it"
        )
    revision = LEGACY_REVISIONS[version]
    if revision is not None:
        command.stamp(config, revision)
    connection.execute(text("DROP TABLE schema_version"))
