"""The import table of docs/architecture.md ("Who may import whom") as a test, both columns of it.

Every Python file under ``app/`` belongs to exactly one row (the row naming the most specific path that holds
it). Each file's imports (at the top and inside functions) are read, each resolved to the module it names, and
every module of ``app`` a row's files import must be allowed by the row's *may import* cell (the row itself, the
paths the cell names, "the core"), and none may be banned by its *must not import* cell. Where a *may import*
cell names third-party libraries, the row's files import no other. Paths are matched exactly: a row or cell
path ``app/workflow.py`` is that module alone, a directory ``app/workflows`` that package and what it holds.
A path that names no file or package fails, so that a move that forgets the table is seen. The document and
the code cannot drift apart.

No import circle between modules of ``app/`` either: the graph of what importing each module runs (its imports at
the top and inside functions, and the packages whose ``__init__.py`` runs first) has no strongly connected
component of two modules or more. Imports under ``if TYPE_CHECKING:`` are exempt: they never run.
"""

from __future__ import annotations

import ast
import functools
import re
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "architecture.md"
PORT_LIBRARIES = ("serial",)
"""What "never a port library" names: pyserial's package."""
WEB_STACK = ("fastapi", "pydantic", "sqlalchemy")
"""Libraries a *must not import* cell may name in plain words."""


@dataclass(frozen=True)
class Row:
    paths: tuple[str, ...]
    may: str
    must_not: str


def table_rows(text: str) -> list[Row]:
    """The rows of the table under "Who may import whom" whose first cell names paths of ``app`` in backticks."""
    section = text.split("## Who may import whom", 1)[1].split("\n## ", 1)[0]
    rows = []
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 3 or not cells[0].startswith("`app"):
            continue
        rows.append(Row(tuple(re.findall(r"`(app[^`]*)`", cells[0])), cells[1], cells[2]))
    return rows


def module_name(path: str) -> str:
    """``app/io/log.py`` → ``app.io.log``; ``app/io`` (or ``app/io/``) → ``app.io``; ``app/__init__.py`` →
    ``app``."""
    return path.rstrip("/").removesuffix(".py").removesuffix("/__init__").replace("/", ".")


@functools.cache
def module_file(name: str, root: Path) -> Path | None:
    """The file or package directory a dotted module of ``root`` is, or None."""
    base = root / name.replace(".", "/")
    if base.with_suffix(".py").is_file():
        return base.with_suffix(".py")
    if (base / "__init__.py").is_file() or base.is_dir():
        return base
    return None


def resolve(name: str, root: Path) -> str:
    """The longest prefix of an imported ``app`` name that is a module or package (``from app import
    __version__`` is the package ``app``; ``from app.io.log import UNITS`` the module ``app.io.log``)."""
    parts = name.split(".")
    for end in range(len(parts), 0, -1):
        if module_file(".".join(parts[:end]), root) is not None:
            return ".".join(parts[:end])
    return name


def for_the_type_checker(node: ast.AST) -> bool:
    """Whether a statement is ``if TYPE_CHECKING:`` (or ``typing.TYPE_CHECKING``), whose body never runs."""
    test = node.test if isinstance(node, ast.If) else None
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def statements(tree: ast.AST, *, running: bool = False):
    """Every statement of a module, nested ones too (imports stand only as statements: no need to walk the
    expressions, which keeps the guard fast); with ``running``, those that can run: not the body of an
    ``if TYPE_CHECKING:``."""
    stack = [tree]
    while stack:
        node = stack.pop()
        yield node
        for field in ("body", "orelse", "finalbody", "handlers", "cases"):
            if not (running and field == "body" and for_the_type_checker(node)):
                stack.extend(getattr(node, field, ()))


@functools.cache
def imports_of(file: Path, root: Path, *, running: bool = False) -> frozenset[str]:
    """Every module a file imports, absolute, wherever the import statement stands (with ``running``, not those
    for the type checker alone); ``app``'s resolved to the module or package named, third-party ones as written."""
    tree = ast.parse(file.read_text(encoding="utf-8"))
    package = module_name(str(file.relative_to(root)))
    if file.name != "__init__.py":
        package = package.rsplit(".", 1)[0]
    names = set()
    for node in statements(tree, running=running):
        if isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[: len(parts) - node.level + 1] + ([node.module] if node.module else []))
            names.update(f"{base}.{a.name}" for a in node.names)  # `from app import sessions`, or a name
    return frozenset(resolve(n, root) if n.split(".")[0] == "app" else n for n in names)


def under(name: str, module: str, package: bool) -> bool:
    """Exact matching: a module is itself alone, a package itself and what it holds."""
    return name == module or (package and name.startswith(module + "."))


def named_modules(cell: str, root: Path) -> list[tuple[str, bool]]:
    """(module, is a package) of the ``app`` paths a cell names in backticks."""
    out = []
    for path in re.findall(r"`(app[^`]*)`", cell):
        name = module_name(path)
        found = module_file(name, root)
        # A package's `__init__.py` is that one file: it allows `from app import __version__`, not all of `app`.
        out.append((name, found is not None and found.is_dir() and not path.endswith("__init__.py")))
    return out


def missing_paths(rows: list[Row], root: Path) -> list[str]:
    """The paths of the table (rows and cells) that name no file or package."""
    paths = {p for row in rows for p in row.paths}
    paths |= {p for row in rows for cell in (row.may, row.must_not) for p in re.findall(r"`(app[^`]*)`", cell)}
    return sorted(p for p in paths if module_file(module_name(p), root) is None)


def owners(rows: list[Row], root: Path) -> tuple[dict[Path, int], list[str], list[str]]:
    """Each ``.py`` file under ``app/`` → the index of its row (the most specific path holding it); the
    files no row holds; the paths named by more than one row."""
    seen: dict[str, int] = {}
    repeated = []
    for i, row in enumerate(rows):
        for path in (p.rstrip("/") for p in row.paths):
            if path in seen:
                repeated.append(path)
            seen[path] = i
    owner, uncovered = {}, []
    for file in sorted((root / "app").rglob("*.py")):
        rel = file.relative_to(root).as_posix()
        holders = [p for p in seen if rel == p or rel.startswith(p + "/")]
        if holders:
            owner[file] = seen[max(holders, key=len)]
        else:
            uncovered.append(rel)
    return owner, uncovered, repeated


def allowed(row: Row, root: Path) -> list[tuple[str, bool]]:
    """What the row's *may import* cell allows of ``app``: its own paths, the paths it names, the core."""
    out = named_modules(" ".join(f"`{p}`" for p in row.paths), root) + named_modules(row.may, root)
    if re.search(r"\bthe core\b", row.may):
        out.append(("app.calibration", True))
    return out


def forbidden(row: Row, root: Path) -> tuple[list[tuple[str, bool]], list[str], list[tuple[str, bool]]]:
    """The ``app`` modules a row must not import, the libraries, and what its "but" allows back."""
    banned = named_modules(row.must_not, root)
    libraries = [w for w in WEB_STACK if re.search(rf"\b{w}\b", row.must_not)]
    back = []
    if "everything else in `app`" in row.must_not:  # else: than what its may-import cell names
        banned.append(("app", True))
        back += allowed(row, root)
        if "but the core" in row.must_not:
            back.append(("app.calibration", True))
    if "port library" in row.must_not:
        libraries += list(PORT_LIBRARIES)
    return banned, libraries, back


def third_party(name: str) -> str | None:
    """The library a third-party import names (its top-level package), else None (``app`` or the standard
    library's)."""
    top = name.split(".")[0]
    return None if top == "app" or top in sys.stdlib_module_names else top


def violations(rows: list[Row], root: Path) -> list[tuple[int, str]]:
    """(row, sentence) of every import a row's files make that its *may import* cell does not allow or its
    *must not import* cell bans."""
    owner, _, _ = owners(rows, root)
    libraries = {third_party(n) for f in owner for n in imports_of(f, root)} - {None}
    found = []
    for i, row in enumerate(rows):
        may, (banned, banned_libraries, back) = allowed(row, root), forbidden(row, root)
        own = named_modules(" ".join(f"`{p}`" for p in row.paths), root)
        unquoted = re.sub(r"`[^`]*`", "", row.may)
        named_libraries = {w for w in re.findall(r"\w+", unquoted) if w in libraries}
        for file in (f for f, j in owner.items() if j == i):
            rel = file.relative_to(root).as_posix()
            for name in sorted(imports_of(file, root)):
                lib = third_party(name)
                if (lib is None and name.split(".")[0] != "app") or any(under(name, m, p) for m, p in own):
                    continue  # the standard library's, or the row's own
                if lib is None:
                    if not any(under(name, m, p) for m, p in may):
                        found.append((i, f"{rel} imports {name}, which its row's may-import cell does not name"))
                    elif any(under(name, m, p) for m, p in banned) and not any(under(name, m, p) for m, p in back):
                        found.append((i, f"{rel} imports {name}, which its row's must-not-import cell bans"))
                elif lib in banned_libraries:
                    found.append((i, f"{rel} imports {lib}, which its row's must-not-import cell bans"))
                elif named_libraries and lib not in named_libraries:
                    found.append(
                        (
                            i,
                            f"{rel} imports {lib}, a library its row's may-import cell does not name "
                            f"(it names {', '.join(sorted(named_libraries))})",
                        )
                    )
    return found


ROWS = table_rows(DOC.read_text(encoding="utf-8"))


def test_the_table_is_read():
    paths = {p for row in ROWS for p in row.paths}
    assert {
        "app/calibration",
        "app/io",
        "app/store",
        "app/workflows",
        "app/guided",
        "app/api",
        "app/web",
        "app/cli",
        "app/cli/board.py",
        "app/guided/capture_rules.py",
        "app/reach",
        "app/main.py",
    } <= paths, paths


def test_every_path_the_table_names_is_a_module_or_a_package():
    assert not missing_paths(ROWS, ROOT), f"the table names what app/ does not hold: {missing_paths(ROWS, ROOT)}"


def test_every_module_of_app_has_exactly_one_row():
    _, uncovered, repeated = owners(ROWS, ROOT)
    assert not uncovered, f"no row of the import table holds: {', '.join(uncovered)}"
    assert not repeated, f"more than one row names: {', '.join(repeated)}"


@functools.cache
def all_violations() -> list[tuple[int, str]]:
    """Every row's violations, found once in the process that runs the rows' tests (not at the module's import,
    which every worker of the suite pays)."""
    return violations(ROWS, ROOT)


@pytest.mark.parametrize("index", range(len(ROWS)), ids=[", ".join(r.paths) for r in ROWS])
def test_every_module_imports_what_its_row_allows_and_nothing_it_forbids(index):
    found = [sentence for i, sentence in all_violations() if i == index]
    assert not found, "\n".join(found)


NOT_FOR_APP = "no module of `app` imports it"
"""The words of a row whose modules serve only the tests and the benches (the simulations)."""


def test_no_module_of_app_imports_what_serves_only_tests():
    section = DOC.read_text(encoding="utf-8").split("## Who may import whom", 1)[1].split("\n## ", 1)[0]
    banned = [
        re.findall(r"`([^`]+)`", line)[0].rstrip("/")
        for line in section.splitlines()
        if line.startswith("|") and NOT_FOR_APP in line
    ]
    assert banned == ["simulations"], f"the table's rows saying {NOT_FOR_APP!r}: {banned}"
    found = [
        f"{file.relative_to(ROOT)} imports {name}"
        for file in sorted((ROOT / "app").rglob("*.py"))
        for name in sorted(imports_of(file, ROOT))
        if name == "simulations" or name.startswith("simulations.")
    ]
    assert not found, "\n".join(found)


def packages_of(name: str) -> list[str]:
    """The packages holding a module, outermost last: ``app.io.readers.table`` → ``app.io.readers``, ``app.io``,
    ``app``."""
    parts = name.split(".")
    return [".".join(parts[:end]) for end in range(len(parts) - 1, 0, -1)]


def import_graph(root: Path) -> dict[str, set[str]]:
    """Each module of ``app`` (a package is its ``__init__.py``) → the modules of ``app`` that importing it runs:
    those it imports, at the top or inside a function (not those for the type checker alone, under ``if
    TYPE_CHECKING:``, which never run), and the packages holding them that are not already running (Python runs a
    package's ``__init__.py`` before its modules: importing ``app.io.readers.table`` from ``app.io.board`` runs
    ``app.io.readers`` first)."""
    files = {module_name(f.relative_to(root).as_posix()): f for f in sorted((root / "app").rglob("*.py"))}
    graph: dict[str, set[str]] = {}
    for name, file in files.items():
        running = {name, *packages_of(name)}
        targets = set()
        for imported in imports_of(file, root, running=True):
            if imported in files:
                targets.add(imported)
                targets.update(p for p in packages_of(imported) if p in files and p not in running)
        graph[name] = targets - {name}
    return graph


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The import circles: every set of two modules or more each of which imports the others, directly or not
    (the graph's strongly connected components, Tarjan's algorithm), each sorted, in order."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found = []

    def visit(module: str) -> None:
        index[module] = low[module] = len(index)
        stack.append(module)
        for other in sorted(graph.get(module, ())):
            if other not in index:
                visit(other)
                low[module] = min(low[module], low[other])
            elif other in stack:
                low[module] = min(low[module], index[other])
        if low[module] == index[module]:
            component = stack[stack.index(module) :]
            del stack[stack.index(module) :]
            if len(component) > 1:
                found.append(sorted(component))

    for module in sorted(graph):
        if module not in index:
            visit(module)
    return sorted(found)


def test_no_import_circle_between_modules_of_app():
    """No module of ``app`` imports, directly or through others, a module that imports it: the imports of each
    room run one way. Imports inside functions count (they run, later), and so does the package whose
    ``__init__.py`` an import runs first; imports under ``if TYPE_CHECKING:`` are exempt, since they never run
    (two such remain: ``app/io/log.py`` names the flight instances' ``FlightInfo``, ``app/guided/protocols.py``
    the session it is handed)."""
    graph = import_graph(ROOT)
    found = [
        " ⇄ ".join(c) + ": " + "; ".join(f"{m} → {o}" for m in c for o in sorted(graph[m]) if o in c)
        for c in circles(graph)
    ]
    assert not found, "import circles:\n" + "\n".join(found)


# Planted examples: a tiny table and tiny files in tmp_path, each with the one fault a check looks for.

PLANTED_DOC = """# Architecture

## Who may import whom

| module | may import | must not import |
| --- | --- | --- |
| `app/core` | numpy, itself | everything else in `app` |
| `app/workflow.py` | `app/core` | `app/api` |
| `app/workflows` | `app/core` | `app/workflow`, `app/api` |
| `app/api/` | `app/workflows/`, `app/core` | — |
{extra}
## Next
"""


def plant(tmp_path: Path, files: dict[str, str], extra: str = "") -> tuple[list[Row], Path]:
    for rel, source in {
        "app/__init__.py": "",
        "app/core/__init__.py": "",
        "app/core/fit.py": "import numpy\n",
        "app/workflow.py": "from app.core import fit\n",
        "app/workflows/__init__.py": "",
        "app/workflows/still.py": "from app.core.fit import numpy\n",
        "app/api/__init__.py": "",
        "app/api/routes.py": "from app.workflows import still\n",
        **files,
    }.items():
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text(source, encoding="utf-8")
    return table_rows(PLANTED_DOC.format(extra=extra)), tmp_path


def test_planted_a_clean_tree_passes(tmp_path):
    rows, root = plant(tmp_path, {}, "| `app/__init__.py` | — | — |\n")
    assert [v for _, v in violations(rows, root)] == []
    assert owners(rows, root)[1:] == ([], []) and missing_paths(rows, root) == []


def test_planted_an_import_the_may_column_does_not_name_fails(tmp_path):
    rows, root = plant(
        tmp_path, {"app/workflows/still.py": "def f():\n    from app.api import routes\nfrom app.core import fit\n"}
    )
    assert [v for _, v in violations(rows, root)] == [
        "app/workflows/still.py imports app.api.routes, which its row's may-import cell does not name"
    ]


def test_planted_a_package_s_init_named_allows_that_file_alone(tmp_path):
    """A cell naming `app/__init__.py` (the version) allows ``from app import __version__``, not all of ``app``:
    it did, which let `trical serve` import the application with no word of the table."""
    rows, root = plant(tmp_path, {}, "| `app/cli.py` | `app/__init__.py` | — |\n")
    (root / "app/cli.py").write_text("from app import __version__\nfrom app.api import routes\n", encoding="utf-8")
    assert [v for _, v in violations(rows, root)] == [
        "app/cli.py imports app.api.routes, which its row's may-import cell does not name"
    ]


def test_planted_an_import_the_must_not_column_bans_fails_even_when_the_may_column_names_it(tmp_path):
    rows, root = plant(
        tmp_path,
        {"app/workflows/still.py": "import app.workflow\n"},
        "| `app/cli.py` | `app/workflow.py`, `app/api` | `app/api` |\n",
    )
    (root / "app/cli.py").write_text("from app.api import routes\nfrom app import workflow\n", encoding="utf-8")
    assert [v for _, v in violations(rows, root)] == [
        "app/workflows/still.py imports app.workflow, which its row's may-import cell does not name",
        "app/cli.py imports app.api.routes, which its row's must-not-import cell bans",
    ]


def test_planted_everything_else_in_app_is_else_than_what_the_may_column_names(tmp_path):
    """A must-not-import cell's "everything else in `app`" bans what the row's may-import cell does not name: the
    verdict's row names the presenter of headlines, which it then does not ban; another module it still bans."""
    row = "| `app/verdict.py` | `app/workflow.py`, `app/core` | everything else in `app` |\n"
    for tree, source, found in (
        ("named", "from app import workflow\nfrom app.core import fit\n", []),
        (
            "other",
            "from app import workflow\nfrom app.api import routes\n",
            ["app/verdict.py imports app.api.routes, which its row's may-import cell does not name"],
        ),
    ):
        rows, root = plant(tmp_path / tree, {"app/verdict.py": source}, row)
        assert [v for _, v in violations(rows, root)] == found, tree


def test_planted_a_library_the_may_column_does_not_name_fails_where_it_names_libraries(tmp_path):
    rows, root = plant(
        tmp_path,
        {
            "app/core/fit.py": "import numpy\nimport scipy.linalg\n",
            "app/api/routes.py": "import scipy\nfrom app.workflows import still\n",
        },
    )
    assert [v for _, v in violations(rows, root)] == [
        "app/core/fit.py imports scipy, a library its row's may-import cell does not name (it names numpy)"
    ]


def test_planted_a_module_without_a_row_fails(tmp_path):
    rows, root = plant(tmp_path, {"app/tls.py": "import ssl\n"}, "| `app/__init__.py` | — | — |\n")
    assert owners(rows, root)[1] == ["app/tls.py"]


def test_planted_matching_is_exact_not_by_prefix(tmp_path):
    # `app/workflow.py` holds only itself: app/workflows' files are not its, and a ban on `app/workflow`
    # does not ban app.workflows (nor the other way round).
    rows, root = plant(tmp_path, {"app/workflowz.py": ""}, "| `app/__init__.py` | — | — |\n")
    owner, uncovered, _ = owners(rows, root)
    assert uncovered == ["app/workflowz.py"]
    assert owner[root / "app/workflows/still.py"] == 2 and owner[root / "app/workflow.py"] == 1
    assert not under("app.workflows.still", "app.workflow", package=False)
    assert under("app.workflows.still", "app.workflows", package=True)


def test_planted_a_path_that_is_no_module_fails(tmp_path):
    rows, root = plant(tmp_path, {}, "| `app/__init__.py`, `app/requests.py` | `app/protocols` | — |\n")
    assert missing_paths(rows, root) == ["app/protocols", "app/requests.py"]


def test_planted_an_import_circle_fails_wherever_the_import_stands(tmp_path):
    """A module that imports, inside a function, a module that imports it at the top closes a circle; so does a
    chain of three."""
    _, root = plant(
        tmp_path,
        {
            "app/core/gates.py": "def check():\n    from app.core.fit import numpy\n",
            "app/core/fit.py": "import numpy\nfrom app.core import gates\n",
            "app/api/a.py": "from app.api import b\n",
            "app/api/b.py": "from app.api.c import X\n",
            "app/api/c.py": "import app.api.a\n",
        },
    )
    assert circles(import_graph(root)) == [["app.api.a", "app.api.b", "app.api.c"], ["app.core.fit", "app.core.gates"]]


def test_planted_an_import_for_the_type_checker_alone_closes_no_circle(tmp_path):
    _, root = plant(
        tmp_path,
        {
            "app/core/fit.py": "from typing import TYPE_CHECKING\n"
            "if TYPE_CHECKING:\n    from app.core.gates import G\n",
            "app/core/gates.py": "from app.core.fit import numpy\nimport typing\nif typing.TYPE_CHECKING:\n"
            "    import app.core.fit\nelse:\n    pass\n",
        },
    )
    assert circles(import_graph(root)) == []


def test_planted_a_circle_through_a_package_s_init_fails(tmp_path):
    """``app/api/__init__.py`` runs before any module of ``app.api``: a module it imports that imports one of them
    has it run again, half done."""
    _, root = plant(
        tmp_path,
        {
            "app/api/__init__.py": "from app.workflows import still\n",
            "app/workflows/still.py": "from app.api.routes import X\n",
            "app/api/routes.py": "",
        },
    )
    assert circles(import_graph(root)) == [["app.api", "app.workflows.still"]]
