"""The import table of docs/architecture.md ("Who may import whom") as a test: each row's *must not import*
column is read from the document itself, and every module the row names is parsed (its imports at the top and
those inside functions) and must import none of them; a row that says "no module of `app` imports it" bans its
modules from every file of app/. The document and the code cannot drift apart."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "architecture.md"
PORT_LIBRARIES = ("serial",)
"""What "never a port library" names: pyserial's package."""


def table_rows() -> list[tuple[list[str], str]]:
    """(the row's paths, its must-not-import cell) of the table under "Who may import whom"."""
    text = DOC.read_text(encoding="utf-8")
    section = text.split("## Who may import whom", 1)[1].split("\n## ", 1)[0]
    rows = []
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 3 or not cells[0].startswith(("`app", "`simulations")):
            continue
        rows.append((re.findall(r"`((?:app|simulations)[^`]*)`", cells[0]), cells[2]))
    return rows


def module_name(path: str) -> str:
    return path.removesuffix(".py").replace("/", ".")


def forbidden(paths: list[str], cell: str) -> tuple[list[str], list[str]]:
    """The module prefixes a row's modules must not import, and the ones its "but" allows back."""
    names = [module_name(n) if n.startswith("app") else n for n in re.findall(r"`([^`]+)`", cell)]
    names += [w for w in ("fastapi", "pydantic", "sqlalchemy") if re.search(rf"\b{w}\b", cell)]
    allowed = [module_name(p) for p in paths]
    if "everything else in `app`" in cell:
        names.append("app")
        if "but the core" in cell:
            allowed.append("app.calibration")
    if "port library" in cell:
        names += list(PORT_LIBRARIES)
    return sorted(set(names)), allowed


def imports_of(file: Path) -> set[str]:
    """Every module a file imports, absolute, wherever the import statement stands."""
    tree = ast.parse(file.read_text(encoding="utf-8"))
    package = module_name(str(file.relative_to(ROOT))).rsplit(".", 1)[0]
    if file.name == "__init__.py":
        package = module_name(str(file.parent.relative_to(ROOT)))
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[: len(parts) - node.level + 1] + ([node.module] if node.module else []))
            out.add(base)
            out.update(f"{base}.{a.name}" for a in node.names)  # `from app.guided import sessions`
    return out


def files_of(path: str) -> list[Path]:
    p = ROOT / path
    return sorted(p.rglob("*.py")) if p.is_dir() else [p]


def under(name: str, prefix: str) -> bool:
    return name == prefix or name.startswith(prefix + ".")


ROWS = table_rows()


def test_the_table_is_read():
    paths = {p for row, _ in ROWS for p in row}
    assert {"app/calibration", "app/io", "app/store", "app/workflows", "app/guided", "app/api", "app/web",
            "app/cli", "app/cli/board.py", "app/guided/capture_rules.py", "app/reach"} <= paths, paths


@pytest.mark.parametrize("paths, cell", ROWS, ids=[", ".join(p) for p, _ in ROWS])
def test_no_module_imports_what_its_row_forbids(paths, cell):
    banned, allowed = forbidden(paths, cell)
    found = []
    for path in paths:
        own = module_name(path)
        for file in files_of(path):
            for name in imports_of(file):
                if any(under(name, a) for a in allowed) or under(name, own):
                    continue
                hits = [b for b in banned if under(name, b)]
                if hits:
                    found.append(f"{file.relative_to(ROOT)} imports {name} ({hits[0]} is forbidden to {path})")
    assert not found, "\n".join(found)


NOT_FOR_APP = "no module of `app` imports it"
"""The words of a row whose modules serve only the tests and the benches (the simulations)."""


def test_no_module_of_app_imports_what_serves_only_tests():
    banned = [module_name(p) for paths, cell in ROWS if NOT_FOR_APP in cell for p in paths]
    assert banned == ["simulations"], f"the table's rows saying {NOT_FOR_APP!r}: {banned}"
    found = [f"{file.relative_to(ROOT)} imports {name}"
             for file in sorted((ROOT / "app").rglob("*.py")) for name in sorted(imports_of(file))
             if any(under(name, b) for b in banned)]
    assert not found, "\n".join(found)
