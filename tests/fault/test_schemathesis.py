"""Property-based fuzzing of every operation of the OpenAPI schema: no input yields a server error."""

from __future__ import annotations

import tempfile
from pathlib import Path

import schemathesis
from hypothesis import HealthCheck, settings
from schemathesis.checks import not_a_server_error

from app.config import Settings
from app.main import create_app

_DB = Path(tempfile.mkdtemp(prefix="trical-fuzz-")) / "trical.db"
app = create_app(Settings(database_url=f"sqlite:///{_DB}"))
schema = schemathesis.openapi.from_asgi("/openapi.json", app)


@schema.parametrize()
@settings(max_examples=60, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
def test_no_server_error(case):
    case.call_and_validate(checks=[not_a_server_error])
