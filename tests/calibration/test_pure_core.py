"""The core is importable without the web stack (docs/architecture.md)."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_core_imports_without_web_stack():
    code = (
        "import sys, app.calibration, app.calibration.registry\n"
        "import pkgutil, importlib\n"
        "for m in pkgutil.walk_packages(app.calibration.__path__, 'app.calibration.'):\n"
        "    importlib.import_module(m.name)\n"
        "bad = sorted(n for n in sys.modules if n.split('.')[0] in "
        "('fastapi', 'starlette', 'pydantic', 'uvicorn', 'jinja2', 'sqlite3', 'pyarrow') "
        "or n.startswith(('app.api', 'app.store', 'app.io', 'app.web')))\n"
        "print(','.join(bad))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"app.calibration pulled in: {out.stdout}"
