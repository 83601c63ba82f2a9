"""The running service loads no simulation (simulations/__init__.py); that no module of app/ imports one is
the import table's rule, checked by tests/test_architecture.py."""

import sys
from pathlib import Path

from tests.processes import run_ok

ROOT = Path(__file__).resolve().parents[2]
SIMULATIONS = "simulations"


def test_the_service_loads_no_simulation():
    code = (
        "import sys, pkgutil, importlib\n"
        "import app.main, app.workflows, app.guided.sessions, app.cli.main\n"
        "import app.api, app.io, app.store, app.web\n"
        "for pkg in (app.api, app.io, app.store, app.web):\n"
        "    for m in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + '.'):\n"
        "        importlib.import_module(m.name)\n"
        f"print(','.join(sorted(n for n in sys.modules if n.split('.')[0] == {SIMULATIONS!r})))\n"
    )
    out = run_ok([sys.executable, "-c", code], timeout_s=120, cwd=ROOT)
    assert out.stdout.strip() == "", f"the service imported {out.stdout.strip()}"
