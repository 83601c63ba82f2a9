"""Alembic's environment: migrations run on the connection app.store.migrate hands over (in its
transaction, under its lock); nothing is read from an alembic.ini."""

from __future__ import annotations

from alembic import context

from app.store.schema import metadata

connection = context.config.attributes.get("connection")
if connection is None:  # pragma: no cover - app.store.migrate always passes one
    raise RuntimeError("trical's migrations run through app.store.migrate.upgrade(engine), not the alembic command")

context.configure(connection=connection, target_metadata=metadata, render_as_batch=connection.dialect.name == "sqlite")
with context.begin_transaction():
    context.run_migrations()
