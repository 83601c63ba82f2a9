"""The simulations stay out of the service's import path (app/calibration/simulations/__init__.py)."""

import ast
import sys
from pathlib import Path
from tests.processes import run_ok

ROOT = Path(__file__).resolve().parents[2]
SIMULATIONS = "app.calibration.simulations"


def test_the_service_loads_no_simulation():
    code = (
        "import sys, pkgutil, importlib\n"
        "import app.main, app.workflows, app.guided.sessions, app.cli\n"
        "import app.api, app.io, app.store, app.web\n"
        "for pkg in (app.api, app.io, app.store, app.web):\n"
        "    for m in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + '.'):\n"
        "        importlib.import_module(m.name)\n"
        f"print(','.join(sorted(n for n in sys.modules if n.startswith({SIMULATIONS!r}))))\n"
    )
    out = run_ok([sys.executable, "-c", code], timeout_s=120, cwd=ROOT)
    assert out.stdout.strip() == "", f"the service imported {out.stdout.strip()}"


def _imported_modules(path: Path) -> set[str]:
    """Absolute names of every module a file imports, at the top or inside a function."""
    package = ".".join(path.relative_to(ROOT).with_suffix("").parts[:-1])
    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package.split(".")[: len(package.split(".")) - node.level + 1] if node.level else []
            mod = ".".join([*base, *([node.module] if node.module else [])])
            names.add(mod)
            names.update(f"{mod}.{a.name}" for a in node.names)
    return names


def test_no_module_outside_simulations_imports_one():
    offenders = []
    for path in sorted((ROOT / "app").rglob("*.py")):
        if (ROOT / "app" / "calibration" / "simulations") in path.parents:
            continue
        hits = sorted(n for n in _imported_modules(path) if n == SIMULATIONS or n.startswith(SIMULATIONS + "."))
        if hits:
            offenders.append(f"{path.relative_to(ROOT)}: {', '.join(hits)}")
    assert not offenders, "simulations imported by the service: " + "; ".join(offenders)
