"""Property-based fuzzing of every operation of the OpenAPI schema: no input yields a server error.

Schemathesis keeps run data (its cache, crash records) under ``.schemathesis/`` in the working
directory by default; here its cache is off and pointed, like the database, at a temporary
directory, so that a run leaves nothing in the work tree.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import schemathesis
from hypothesis import HealthCheck, settings
from schemathesis.checks import not_a_server_error
from schemathesis.config import SchemathesisConfig

from app.config import Settings
from app.main import create_app
from tests.live_server import ROOT

_TMP = Path(tempfile.mkdtemp(prefix="trical-fuzz-"))
_DB = _TMP / "trical.db"
_WORK_TREE_DATA = ROOT / ".schemathesis"
_BEFORE = sorted(_WORK_TREE_DATA.rglob("*")) if _WORK_TREE_DATA.exists() else []
app = create_app(Settings(database_url=f"sqlite:///{_DB}"))
config = SchemathesisConfig.from_dict(
    {
        "cache": {"enabled": False, "directory": str(_TMP / "schemathesis-cache")},
        "reports": {"directory": str(_TMP / "schemathesis-report")},
    }
)
schema = schemathesis.openapi.from_asgi("/openapi.json", app, config=config)


@schema.parametrize()
@settings(
    max_examples=60,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)
def test_no_server_error(case):
    case.call_and_validate(checks=[not_a_server_error])


def test_the_fuzzing_left_nothing_in_the_work_tree():
    after = sorted(_WORK_TREE_DATA.rglob("*")) if _WORK_TREE_DATA.exists() else []
    assert after == _BEFORE, f"schemathesis wrote {sorted(set(after) - set(_BEFORE))} into the work tree"
