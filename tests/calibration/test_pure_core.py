"""The core is importable without the web stack (docs/architecture.md)."""

import sys
from pathlib import Path

from tests.processes import run_ok

ROOT = Path(__file__).resolve().parents[2]


def test_core_imports_without_web_stack():
    code = (
        "import sys, app.calibration, app.calibration.shared.result\n"
        "import pkgutil, importlib\n"
        "for m in pkgutil.walk_packages(app.calibration.__path__, 'app.calibration.'):\n"
        "    importlib.import_module(m.name)\n"
        "bad = sorted(n for n in sys.modules if n.split('.')[0] in "
        "('fastapi', 'starlette', 'pydantic', 'uvicorn', 'jinja2', 'sqlite3', 'pyarrow') "
        "or n.startswith(('app.api', 'app.store', 'app.io', 'app.web')))\n"
        "print(','.join(bad))\n"
    )
    out = run_ok([sys.executable, "-c", code], timeout_s=120, cwd=ROOT)
    assert out.stdout.strip() == "", f"app.calibration pulled in: {out.stdout}"
